"""``aaria mjcf``: a robot (DH table, URDF robot or run file) as a MuJoCo model with its IMUs."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from aaria_pin.cli._options import given, robot_source_options, table_source_options
from aaria_pin.cli._viz_options import output_option
from aaria_pin.cli.urdf_cmd import table_arm

_FILE = click.Path(path_type=Path, dir_okay=False)
_SOURCES = {"dh": ("preset", "dh_file"), "urdf": ("robot", "urdf_file"), "run": ("from_run",)}
_REFUSED = {"dh": ("tool_frame", "imu_layout_file"), "urdf": ("density", "convention"),
            "run": ("tool_frame", "imu_layout_file", "convention", "density")}  # fmt: skip
"""Options that do nothing for a robot of that source (refused, naming both)."""


def _source(params: dict[str, Any]) -> str:
    """``dh``, ``urdf`` or ``run``: the one robot source the options name (else a UsageError)."""
    named = [name for name, keys in _SOURCES.items() if any(params[k] is not None for k in keys)]
    if len(named) != 1:
        raise click.UsageError(
            "give one robot: --preset NAME or --dh FILE, --robot NAME or --urdf FILE, or --from RUN"
        )
    for key in _REFUSED[named[0]]:
        if given(key):
            from aaria_pin.core.conflicts import OptionConflictError

            source = next(k for k in _SOURCES[named[0]] if params[k] is not None)
            raise OptionConflictError(parameter=key, other=source, given_with=True)
    return named[0]


@click.command(
    epilog="""\b
Examples:
  aaria mjcf --preset aaria-fig2 -o fig2.xml         # moving base: a 6-DOF base chain
  aaria mjcf --robot panda --fixed-base -o panda.xml
  aaria mjcf --from run.h5 -o run.xml                # the run's robot, IMUs and rate"""
)
@table_source_options
@robot_source_options
@click.option(
    "--from",
    "from_run",
    type=_FILE,
    help="A run file (any kind): its URDF, IMU mounts, gravity, rate, base and actuators.",
)
@click.option("--density", type=float, help="DH arm: body density [kg/m^3] (default 2700).")
@click.option("--rate", type=float,
    help="Sample rate [Hz]; timestep 1/rate (default 100, or the run's).")  # fmt: skip
@output_option("MJCF file", (".xml", ".mjcf"), help="MJCF file to write (.xml).")
def mjcf(**params: Any) -> None:
    """Write a MuJoCo model (MJCF) of a robot, with a gyro and an accelerometer per IMU.

    A body per link, a site at every IMU with its two sensors, and on a moving base a 6-DOF
    base chain (slides along x, y, z, hinges about x, y, z) so a run can be replayed.
    """
    from aaria_pin.apps.robot_mjcf import MjcfSource, robot_mjcf

    source, arm = _source(params), None
    if source == "dh":
        density = 2700.0 if params["density"] is None else params["density"]
        arm = table_arm(params["preset"], params["dh_file"], params["convention"], density)
    spec = MjcfSource(source, arm, (params["robot"], params["urdf_file"]), params["from_run"],
                      params["tool_frame"], params["imu_layout_file"], not params["fixed_base"],
                      params["rate"])  # fmt: skip
    line, notes = robot_mjcf(params["output"], spec)
    for note in notes:
        click.echo(f"aaria: warning: {note}", err=True)
    click.echo(line)
