"""``aaria mjcf``: a robot (DH table, URDF robot or run file) as a MuJoCo model with its IMUs."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from aaria_pin.cli._options import given, robot_source_options, table_source_options
from aaria_pin.cli._viz_options import output_option
from aaria_pin.cli.urdf_cmd import table_arm

if TYPE_CHECKING:
    from aaria_pin.core.record import ImuMount

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


def _robot(
    source: str, moving: bool, params: dict[str, Any]
) -> tuple[str, Path | None, str, Sequence[ImuMount], str, int]:
    """A DH arm's or URDF robot's URDF, folder, tool, IMU mounts, name and joint count."""
    if source == "dh":
        from aaria_pin.aaria.arm_run import dh_imu_mounts

        density = 2700.0 if params["density"] is None else params["density"]
        arm, name = table_arm(params["preset"], params["dh_file"], params["convention"], density)
        return arm.urdf, None, "tool_tip", dh_imu_mounts(arm), name, len(arm.chain.joints)
    from aaria_pin.aaria.robot_inputs import urdf_source
    from aaria_pin.core.imu_layout import read_imu_layout
    from aaria_pin.core.urdf_robot import load_urdf_robot
    from aaria_pin.files.paths import existing_input

    urdf, folder, name = urdf_source(params["robot"], params["urdf_file"])
    layout = params["imu_layout_file"]
    if layout is not None:
        layout = read_imu_layout(existing_input(layout, None, "IMU layout"))
    loaded = load_urdf_robot(
        urdf,
        urdf_dir=folder,
        moving_base=moving,
        tool_frame=params["tool_frame"],
        imu_layout=layout,
    )
    tool, joints = loaded.robot.tool_frame, loaded.robot.n_joints
    return urdf, folder, tool, loaded.imu_mounts, name, joints


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
@click.option(
    "--rate", type=float, help="Sample rate [Hz]; timestep 1/rate (default 100, or the run's)."
)
@output_option("MJCF file", (".xml", ".mjcf"), help="MJCF file to write (.xml).")
def mjcf(**params: Any) -> None:
    """Write a MuJoCo model (MJCF) of a robot, with a gyro and an accelerometer per IMU.

    A body per link, a site at every IMU with its two sensors, and on a moving base a 6-DOF
    base chain (slides along x, y, z, hinges about x, y, z) so a run can be replayed.
    """
    import warnings
    from importlib.util import find_spec

    from aaria_pin.apps.record_model import record_mjcf, record_moving_base
    from aaria_pin.core.export.mjcf_emit import BASE_JOINTS, emit_mjcf
    from aaria_pin.core.trajectory import DEFAULT_RATE
    from aaria_pin.files.io import write_text_atomic

    source, rate, output = _source(params), params["rate"], params["output"]
    moving = not params["fixed_base"]
    imus: Sequence[ImuMount]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        if source == "run":
            from aaria_pin.files.runfile import read_run

            record = read_run(params["from_run"])
            moving = moving and record_moving_base(record)
            name = record.metadata.robot or params["from_run"].stem
            joints, imus = len(record.joint_names), record.imu_mounts
            mjcf = record_mjcf(record, moving_base=moving, rate=rate, balance_inertia="auto")
        else:
            urdf, folder, tool, imus, name, joints = _robot(source, moving, params)
            mjcf = emit_mjcf(
                urdf,
                imus,
                moving_base=moving,
                rate=DEFAULT_RATE if rate is None else rate,
                urdf_dir=folder,
                tool_frame=tool,
                balance_inertia="auto",
            )
    text, skipped = mjcf
    write_text_atomic(output, text)
    for warning in caught:
        click.echo(f"aaria: warning: {warning.message}", err=True)
    if skipped:
        click.echo(
            f"aaria: warning: {len(skipped)} visual mesh file(s) left out (MuJoCo reads STL and "
            f"OBJ; missing or other formats, e.g. {skipped[0]}); those links show their "
            "collision meshes where these are STL or OBJ",
            err=True,
        )
    sensors = sum(1 for mount in imus if mount.parent)
    base = f"moving base ({', '.join(BASE_JOINTS)})" if moving else "fixed base"
    checked = (
        "compiles in MuJoCo" if find_spec("mujoco") else "not checked: mujoco is not installed"
    )
    click.echo(
        f"wrote {output}: {name}, {joints} joints, {sensors} IMU sites with a gyro and an "
        f"accelerometer, {base}, {checked}"
    )
