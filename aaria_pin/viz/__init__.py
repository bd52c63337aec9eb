"""Pictures of arms and runs: a PNG of a pose, signal panels, an interactive HTML viewer.

:mod:`~aaria_pin.viz.scene` describes what is drawn (plain arrays, no plotting library),
:mod:`~aaria_pin.viz.sources` gets scenes, poses and signals from tables and run files,
:mod:`~aaria_pin.viz.render` and :mod:`~aaria_pin.viz.plot` draw PNGs with matplotlib, and
:mod:`~aaria_pin.viz.html` writes the self-contained viewer page.
"""

__all__: list[str] = []
