"""``aaria export``: a run as a recording (MCAP, ROS 1 bag, ROS 2 bag, CSV)."""

from __future__ import annotations

from pathlib import Path

import click

_FORMATS = ("mcap", "ros1", "sqlite3", "csv", "ros2-sqlite3", "ros2-mcap")


@click.command(epilog="""\b
Examples:
  aaria export run.h5 -o run.mcap                      # Foxglove, PlotJuggler
  aaria export ds.h5 --run 3 -o run3.bag               # ROS 1
  aaria export run.h5 -o run_bag --format ros2-sqlite3 # a ROS 2 bag folder
  aaria export run.h5 -o run.csv""")  # fmt: skip
@click.argument("file", type=click.Path(path_type=Path, dir_okay=False))
@click.option("--run", "run_index", type=click.IntRange(0), help="Run K of a data set.")
@click.option("-o", "--output", type=click.Path(path_type=Path), required=True,
    help="Recording: .mcap, .bag, .db3, .csv, or a ROS 2 bag folder (with --format).")  # fmt: skip
@click.option("--format", "form", type=click.Choice(_FORMATS),
    help="Format (default: by the output's suffix).")  # fmt: skip
def export(file: Path, run_index: int | None, output: Path, form: str | None) -> None:
    """Write a run's IMUs, joint states and wrenches as sensor_msgs/Imu, JointState, WrenchStamped.

    A simulated run gives what its sensors measured (measured joint values and torques when
    it has encoders and torque sensors); a recorded run (aaria import) its streams as they are.
    """
    from aaria_pin.apps.recordings import export_file

    click.echo(export_file(file, run_index, output, form))
