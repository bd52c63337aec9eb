"""A robot as a MuJoCo model file: a DH arm, a URDF robot or a run file's robot, with its IMUs.

What ``aaria mjcf`` does, for a Python user too: :func:`dh_arm` builds the DH arm of a table
(a preset's measured masses), :func:`robot_mjcf` writes the MJCF of one robot source (a gyro
and an accelerometer per IMU site; on a moving base a 6-DOF base chain) and returns the line
that reports it and the warnings met on the way (each one line).
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from aaria_pin.aaria.dh import Convention
    from aaria_pin.aaria.dh_robot import DHRobot
    from aaria_pin.core.record import ImuMount

__all__ = ["MjcfSource", "dh_arm", "robot_mjcf"]


def dh_arm(
    table_source: tuple[Any, Convention, str], density: float, preset: str | None
) -> DHRobot:
    """The DH arm of a table (a preset's measured masses when ``preset`` names one).

    Args:
        table_source: ``(table, convention, name)`` as
            :func:`~aaria_pin.aaria.robot_inputs.dh_table_source` returns it
        density: density of every body [kg/m^3]
        preset: the preset the table is, or None
    """
    from aaria_pin.aaria.dh_robot import BodyDimensions, build_dh_robot
    from aaria_pin.aaria.presets import get_preset
    from aaria_pin.aaria.robot_inputs import robot_name

    table, convention, name = table_source
    masses = get_preset(preset).mass_properties if preset else None
    dims = BodyDimensions(density=density)
    return build_dh_robot(table, convention, dims, name=robot_name(name), mass_properties=masses)


@dataclass(frozen=True)
class MjcfSource:
    """The one robot an MJCF is written of, and how.

    Attributes:
        source: ``dh``, ``urdf`` or ``run``
        arm: the DH arm and its name (``dh``)
        robot: ``(robot, urdf_file)``, a robot name or a URDF file (``urdf``)
        run_file: the run file (``run``)
        tool_frame: a URDF robot's tool frame (None: its default)
        imu_layout: a URDF robot's IMU layout file (None: the default layout)
        moving_base: whether the base moves (a run's: only if it moved)
        rate: the sample rate [Hz] (None: 100, or the run's)
    """

    source: str
    arm: tuple[DHRobot, str] | None = None
    robot: tuple[str | None, Path | None] = (None, None)
    run_file: Path | None = None
    tool_frame: str | None = None
    imu_layout: Path | None = None
    moving_base: bool = True
    rate: float | None = None


def _urdf_robot(
    spec: MjcfSource,
) -> tuple[str, Path | None, str, Sequence[ImuMount], str, int]:
    """A URDF robot's URDF, folder, tool, IMU mounts, name and joint count."""
    from aaria_pin.aaria.robot_inputs import urdf_source
    from aaria_pin.core.imu_layout import read_imu_layout
    from aaria_pin.core.urdf_robot import load_urdf_robot
    from aaria_pin.files.paths import existing_input

    urdf, folder, name = urdf_source(*spec.robot)
    layout = spec.imu_layout
    imu_layout = None
    if layout is not None:
        imu_layout = read_imu_layout(existing_input(layout, None, "IMU layout"))
    loaded = load_urdf_robot(urdf, urdf_dir=folder, moving_base=spec.moving_base,
                             tool_frame=spec.tool_frame, imu_layout=imu_layout)  # fmt: skip
    tool, joints = loaded.robot.tool_frame, loaded.robot.n_joints
    return urdf, folder, tool, loaded.imu_mounts, name, joints


def robot_mjcf(output: Path, spec: MjcfSource) -> tuple[str, list[str]]:
    """Write the MJCF of a robot to ``output``.

    Returns:
        The line reporting it (robot, joints, IMU sites, base, whether MuJoCo compiled it) and
        the warnings met (one line each; left-out visual meshes last).
    """
    from importlib.util import find_spec

    from aaria_pin.apps.record_model import record_mjcf, record_moving_base
    from aaria_pin.core.export.mjcf_emit import BASE_JOINTS, emit_mjcf
    from aaria_pin.core.trajectory import DEFAULT_RATE
    from aaria_pin.files.io import write_text_atomic

    moving, rate = spec.moving_base, spec.rate
    imus: Sequence[ImuMount]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        if spec.source == "run" and spec.run_file is not None:
            from aaria_pin.files.runfile import read_run

            record = read_run(spec.run_file)
            moving = moving and record_moving_base(record)
            name = record.metadata.robot or spec.run_file.stem
            joints, imus = len(record.joint_names), record.imu_mounts
            mjcf = record_mjcf(record, moving_base=moving, rate=rate, balance_inertia="auto")
        else:
            if spec.arm is not None:
                from aaria_pin.aaria.arm_run import dh_imu_mounts

                arm, name = spec.arm
                urdf, folder, tool, imus = arm.urdf, None, "tool_tip", dh_imu_mounts(arm)
                joints = len(arm.chain.joints)
            else:
                urdf, folder, tool, imus, name, joints = _urdf_robot(spec)
            rate = DEFAULT_RATE if rate is None else rate
            mjcf = emit_mjcf(urdf, imus, moving_base=moving, rate=rate, urdf_dir=folder,
                             tool_frame=tool, balance_inertia="auto")  # fmt: skip
    text, skipped = mjcf
    write_text_atomic(output, text)
    notes = [str(warning.message) for warning in caught]
    if skipped:
        notes.append(
            f"{len(skipped)} visual mesh file(s) left out (MuJoCo reads STL and OBJ; missing or "
            f"other formats, e.g. {skipped[0]}); those links show their collision meshes where "
            "these are STL or OBJ"
        )
    sensors = sum(1 for mount in imus if mount.parent)
    base = f"moving base ({', '.join(BASE_JOINTS)})" if moving else "fixed base"
    checked = "compiles in MuJoCo" if find_spec("mujoco") else "not checked: mujoco is not"
    checked += "" if find_spec("mujoco") else " installed"
    line = (f"wrote {output}: {name}, {joints} joints, {sensors} IMU sites with a gyro and an "
            f"accelerometer, {base}, {checked}")  # fmt: skip
    return line, notes
