"""``aaria import``: recordings (ROS 1/ROS 2 bags, MCAP, CSV) to a recorded run file."""

from __future__ import annotations

from pathlib import Path

import click


@click.command("import", epilog="""\b
Examples:
  aaria import run.mcap -o rec.h5                       # every Imu, JointState, WrenchStamped
  aaria import lab.bag --imu tool=/imu/data --joints /joint_states -o rec.h5
  aaria import bag_dir --imu a=/imus@imu_a --imu b=/imus@imu_b --time log -o rec.h5
  aaria import lab.csv --map rec.toml -o rec.h5  # map: aaria template recording""")  # fmt: skip
@click.argument("recordings", nargs=-1, required=True, type=click.Path(path_type=Path))
@click.option("-o", "--output", type=click.Path(path_type=Path, dir_okay=False), required=True,
    help="Recorded run file (.h5).")  # fmt: skip
@click.option("--map", "map_file", type=click.Path(path_type=Path, dir_okay=False),
    help="TOML map of topics or CSV columns to sensors (aaria template recording).")  # fmt: skip
@click.option("--imu", "imus", multiple=True, metavar="NAME=TOPIC[@FRAME]",
    help="An IMU: its sensor_msgs/Imu topic (and frame id); repeat per IMU.")  # fmt: skip
@click.option("--joints", help="The sensor_msgs/JointState topic (default: every one).")
@click.option("--wrench", "wrenches", multiple=True, metavar="NAME=TOPIC",
    help="A wrench: its geometry_msgs/WrenchStamped topic; repeat per wrench.")  # fmt: skip
@click.option("--time", type=click.Choice(["header", "log"]),
    help="Each sensor's time: its header stamps (default) or the log (receive) time.")  # fmt: skip
def import_(
    recordings: tuple[Path, ...], output: Path, map_file: Path | None, **flags: str
) -> None:
    """Read recordings into one run file of measured signals, each sensor at its own times.

    Without a map or flags, every sensor_msgs/Imu topic is an IMU named after its frame id,
    every JointState topic joined by joint name, every WrenchStamped a wrench. Prints per
    stream: kind, name, messages, rate, time span, source.
    """
    from aaria_pin.apps.recordings import import_file
    from aaria_pin.files.recordings.mapping import read_map, with_flags

    mapping = with_flags(read_map(map_file) if map_file else None, **flags)
    click.echo(import_file(recordings, output, mapping))
