"""``aaria plot``: a run's signals (a run file or a data set's run) as panels in one picture."""

from __future__ import annotations

from pathlib import Path

import click

from aaria_pin.cli._options import shown
from aaria_pin.cli._viz_options import PICTURE_SUFFIXES, output_option, run_option


@click.command(
    epilog="""\b
Examples:
  aaria plot run.h5 -o run.png                    # every panel, 1400 px wide
  aaria plot run.h5 --imu imu_link3_a -o imu.svg  # one IMU's signals
  aaria plot ds.h5 --run 12 --width 900 -o run12.pdf"""
)
@click.argument("run_file", type=click.Path(path_type=Path, dir_okay=False))
@run_option()
@click.option("--imu", help="Show only this IMU (e.g. imu_link3_a); default every IMU.")
@shown("--width", default=1400, help="Width [px].")
@output_option("picture", PICTURE_SUFFIXES)
def plot(run_file: Path, run_index: int | None, imu: str | None, width: int, output: Path) -> None:
    """Plot joint values, torques and forces, the base wrench and the IMUs of a run.

    RUN_FILE is a run file of any robot (any version) or a data set (--run picks the run).
    The output's suffix picks the format: .png, .pdf or .svg.
    """
    from aaria_pin.viz.plot import plot_run

    panels, samples = plot_run(run_file, output, run_index, imu, width)
    click.echo(f"wrote {output}: {panels} panels, {samples} samples")
