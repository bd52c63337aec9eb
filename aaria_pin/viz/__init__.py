"""Pictures of arms and runs: a pose, signal panels (PNG, PDF, SVG), an interactive HTML viewer.

:mod:`~aaria_pin.viz.scene` describes what is drawn (plain arrays, no plotting library),
:mod:`~aaria_pin.viz.visuals` turns a URDF's visual geometry (meshes, boxes, cylinders, spheres)
into scene solids, :mod:`~aaria_pin.viz.sources` gets scenes, poses and signals from tables and
from the one run record of any run file or data set, :mod:`~aaria_pin.viz.render` and
:mod:`~aaria_pin.viz.plot` draw pictures with matplotlib, :mod:`~aaria_pin.viz.html` writes the
self-contained viewer page (three.js, vendored in ``viz/vendor``),
:mod:`~aaria_pin.viz.report_plots` draws the applications' reports (torque split, wrist
workspace) and :mod:`~aaria_pin.viz.arm_pictures` the pick-and-place arm's contact sheet and
animation.
"""

__all__: list[str] = []
