"""``aaria mjcf``: a robot (DH table, URDF robot or run file) as a MuJoCo model with its IMUs."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from aaria_pin.cli._options import (
    load_robot_source,
    load_table_source,
    robot_name,
    robot_source_options,
    table_source_options,
)
from aaria_pin.cli._viz_options import output_option
from aaria_pin.errors import ModelError

_FILE = click.Path(path_type=Path, dir_okay=False)


def _source(params: dict[str, Any]) -> str:
    """Which robot source the options name: ``dh``, ``urdf`` or ``run``.

    Raises:
        click.UsageError: none or more than one source, or an option of another source.
    """
    given = {
        "dh": params["preset"] is not None or params["dh_file"] is not None,
        "urdf": params["robot"] is not None or params["urdf_file"] is not None,
        "run": params["from_run"] is not None,
    }
    if sum(given.values()) != 1:
        raise click.UsageError(
            "give one robot: --preset NAME or --dh FILE, --robot NAME or --urdf FILE, or --from RUN"
        )
    source = next(name for name, on in given.items() if on)
    refused = {
        "dh": {"tool_frame": "--tool", "imu_layout_file": "--imu-layout"},
        "urdf": {"density": "--density"},
        "run": {"tool_frame": "--tool", "imu_layout_file": "--imu-layout", "density": "--density"},
    }[source]
    for key, flag in refused.items():
        if params[key] is not None:
            where = {"dh": "a DH arm", "urdf": "a URDF robot", "run": "--from"}[source]
            raise click.UsageError(f"{flag} is not allowed with {where}")
    return source


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
    help="A run file (any kind): its URDF, IMU mounts, gravity, rate and base.",
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
    from functools import partial

    from aaria_pin.core.mjcf import (
        BASE_JOINTS,
        emit_mjcf,
        load_mjcf,
        record_mjcf,
        record_moving_base,
    )
    from aaria_pin.core.trajectory import DEFAULT_RATE
    from aaria_pin.files.io import write_text_atomic

    source = _source(params)
    moving = not params["fixed_base"]
    rate = params["rate"]
    output: Path = params["output"]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        if source == "run":
            from aaria_pin.files.runfile import read_run

            record = read_run(params["from_run"])
            if not record.urdf:  # a 0.1.0 DH or wrist file: the URDF of the run re-made
                from dataclasses import replace

                from aaria_pin.apps.remake import remake_record

                record = replace(record, urdf=remake_record(record).urdf)
            moving = not params["fixed_base"] and record_moving_base(record)
            emit = partial(record_mjcf, record, moving_base=moving, rate=rate)
            name = str(record.attributes.get("robot", params["from_run"].stem))
            joints, imus = len(record.joint_names), record.imu_mounts
        elif source == "dh":
            from aaria_pin.aaria.arm_run import dh_imu_mounts
            from aaria_pin.aaria.dh_robot import BodyDimensions, build_dh_robot
            from aaria_pin.aaria.presets import get_preset

            table, convention, name = load_table_source(
                params["preset"], params["dh_file"], params["convention"]
            )
            density = 2700.0 if params["density"] is None else params["density"]
            preset = params["preset"]
            arm = build_dh_robot(
                table,
                convention,
                BodyDimensions(density=density),
                name=robot_name(name),
                mass_properties=get_preset(preset).mass_properties if preset else None,
            )
            imus = dh_imu_mounts(arm)
            joints = len(arm.chain.joints)
            emit = partial(
                emit_mjcf,
                arm.urdf,
                imus,
                moving_base=moving,
                rate=DEFAULT_RATE if rate is None else rate,
                tool_frame="tool_tip",
            )
        else:
            from aaria_pin.core.imu_layout import read_imu_layout
            from aaria_pin.core.urdf_robot import load_urdf_robot

            urdf, folder, name = load_robot_source(params["robot"], params["urdf_file"])
            layout_file = params["imu_layout_file"]
            if layout_file is not None:
                from aaria_pin.files.paths import existing_input

                layout_file = existing_input(layout_file, None, "IMU layout")
            robot = load_urdf_robot(
                urdf,
                urdf_dir=folder,
                moving_base=moving,
                tool_frame=params["tool_frame"],
                imu_layout=None if layout_file is None else read_imu_layout(layout_file),
            )
            imus = robot.imu_mounts
            joints = robot.robot.n_joints
            emit = partial(
                emit_mjcf,
                urdf,
                imus,
                moving_base=moving,
                rate=DEFAULT_RATE if rate is None else rate,
                urdf_dir=folder,
                tool_frame=robot.robot.tool_frame,
            )
        text, skipped = emit()
    try:
        import mujoco  # noqa: F401  (the optional extra: check the model compiles)
    except ImportError:
        compiled = "not checked: mujoco is not installed"
    else:
        compiled = "compiles in MuJoCo"
        try:
            load_mjcf(text)
        except ModelError as exc:
            if "A + B >= C" not in str(exc):
                raise
            text, skipped = emit(balance_inertia=True)
            load_mjcf(text)
            click.echo(
                "aaria: warning: MuJoCo refuses inertias of this URDF whose principal moments "
                f"break A + B >= C ({str(exc).partition('Element name ')[2] or exc}); written "
                'with balanceinertia="true", which raises them: those links\' dynamics differ '
                "from the URDF's",
                err=True,
            )
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
    click.echo(
        f"wrote {output}: {name}, {joints} joints, {sensors} IMU sites with a gyro and an "
        f"accelerometer, {base}, {compiled}"
    )
