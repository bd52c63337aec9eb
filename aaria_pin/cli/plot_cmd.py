"""``aaria plot``: a run's signals (a run file or a data set's run) as panels in one picture."""

from __future__ import annotations

from pathlib import Path

import click

from aaria_pin.cli._viz_options import PICTURE_SUFFIXES, check_run_option, output_option


@click.command(
    epilog="""\b
Examples:
  aaria plot run.h5 -o run.png                    # every panel, 1400 px wide
  aaria plot run.h5 --imu imu_link3_a -o imu.svg  # one IMU's signals
  aaria plot ds.h5 --run 12 --width 900 -o run12.pdf"""
)
@click.argument("run_file", type=click.Path(path_type=Path, dir_okay=False))
@click.option(
    "--run", "run_index", type=click.IntRange(0), help="One run of a data set (default 0)."
)
@click.option("--imu", help="Show only this IMU (e.g. imu_link3_a); default every IMU.")
@click.option("--width", type=int, default=1400, show_default=True, help="Width [px].")
@output_option("picture", PICTURE_SUFFIXES)
def plot(run_file: Path, run_index: int | None, imu: str | None, width: int, output: Path) -> None:
    """Plot joint values, torques and forces, the base wrench and the IMUs of a run.

    RUN_FILE is a run file of any robot (any version) or a data set (--run picks the run).
    The output's suffix picks the format: .png, .pdf or .svg.
    """
    from aaria_pin.errors import ParameterError
    from aaria_pin.viz.plot import plot_panels, signal_panels
    from aaria_pin.viz.render import MAX_PIXELS
    from aaria_pin.viz.sources import load_run_view

    check_run_option(run_file, run_index)
    if not 400 <= width <= MAX_PIXELS:
        raise ParameterError(f"width {width} px; allowed: 400 to {MAX_PIXELS} px")
    view = load_run_view(run_file, run_index)
    panels = signal_panels(view.signals, imu)
    title = view.title if imu is None else f"{view.title}: {imu}"
    plot_panels(view.time, panels, output, title, width=width)
    click.echo(f"wrote {output}: {len(panels)} panels, {view.time.size} samples")
