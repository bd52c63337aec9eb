"""``aaria robots``: the robots of the installed example-robot-data."""

from __future__ import annotations

import json
from pathlib import Path

import click


@click.command(
    epilog="""\b
Examples:
  aaria robots                   # the names --robot takes
  aaria robots --check --paths   # which ones load, their joints and IMUs, their files
  aaria simulate --robot ur5 -o ur5.h5"""
)
@click.option("--paths", is_flag=True, help="Also print each robot's URDF file.")
@click.option("--check", is_flag=True,
    help="Load each robot: its joint count, or why it is refused.")  # fmt: skip
@click.option("--json", "as_json", is_flag=True, help="Print name → URDF file as JSON.")
def robots(paths: bool, check: bool, as_json: bool) -> None:
    """List the robots of example-robot-data, for --robot NAME of simulate and dataset."""
    from aaria_pin.core.catalogue import robot_catalogue, robots_folder

    for name, value in (("check", check), ("paths", paths)):
        if as_json and value:  # the JSON object is every robot's URDF file, unchecked
            from aaria_pin.core.conflicts import OptionConflictError

            raise OptionConflictError(parameter=name, other="as_json", given_with=True, value=True)
    catalogue = robot_catalogue()
    if as_json:
        click.echo(json.dumps({name: str(e.urdf) for name, e in catalogue.items()}, indent=2))
        return
    folder = robots_folder()
    for name, entry in catalogue.items():
        line = f"{name:<32} {entry.urdf.relative_to(folder)}" if paths else f"{name:<32}"
        if check:
            line += f"  {_status(entry.urdf)}"
        click.echo(line.rstrip())
    click.echo(f"{len(catalogue)} robots in {folder}", err=True)


def _status(urdf: Path) -> str:
    """``N joints, M IMUs`` for a robot that loads, else ``refused: <reason>``."""
    import warnings

    from aaria_pin.core.urdf_robot import load_urdf_robot, read_urdf_file
    from aaria_pin.errors import AariaError

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            loaded = load_urdf_robot(read_urdf_file(urdf), urdf_dir=urdf.parent)
    except AariaError as exc:
        return f"refused: {exc}"
    return f"{loaded.robot.n_joints} joints, {len(loaded.imu_mounts)} IMUs"
