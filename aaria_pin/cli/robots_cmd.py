"""``aaria robots``: the robots of the installed example-robot-data."""

from __future__ import annotations

import json

import click


@click.command()
@click.option("--paths", is_flag=True, help="Also print each robot's URDF file.")
@click.option("--json", "as_json", is_flag=True, help="Print name → URDF file as JSON.")
def robots(paths: bool, as_json: bool) -> None:
    """List the robots of example-robot-data, for --robot NAME of simulate and dataset."""
    from aaria_pin.robots import robot_catalogue, robots_folder

    catalogue = robot_catalogue()
    if as_json:
        click.echo(json.dumps({name: str(e.urdf) for name, e in catalogue.items()}, indent=2))
        return
    folder = robots_folder()
    for name, entry in catalogue.items():
        click.echo(f"{name:<32} {entry.urdf.relative_to(folder)}" if paths else name)
    click.echo(f"{len(catalogue)} robots in {folder}", err=True)
