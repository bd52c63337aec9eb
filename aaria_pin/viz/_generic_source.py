"""The ``"generic"`` run kind: the run file of a URDF robot (``aaria simulate --robot/--urdf``).

The model is rebuilt from the URDF text the file holds and drawn as a stick figure by
:func:`~aaria_pin.viz.scene.scene_from_model` (URDF meshes are not drawn). The kind of each
joint (for units and panels) is its Pinocchio joint type, matched by exact name.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin

from aaria_pin._se3 import Array
from aaria_pin.errors import InputFileError, ModelError
from aaria_pin.model import RobotModel
from aaria_pin.trajectory import BaseMotion
from aaria_pin.viz._joints import joint_type_kind
from aaria_pin.viz._run_view import RunView, Signals, scene_poses, still
from aaria_pin.viz.scene import scene_from_model

__all__ = ["is_generic_run", "load_generic_run"]


def is_generic_run(file: Path) -> bool:
    """Whether ``file`` is an HDF5 file marked as a generic (URDF robot) run file."""
    from aaria_pin.runfile import is_generic_run_file

    return is_generic_run_file(file)


def load_generic_run(file: Path) -> RunView:
    """Read a generic run file for drawing.

    Raises:
        InputFileError: an unreadable file, a URDF that cannot be built, an unknown base or
            tool frame, or a stored joint that is neither revolute nor prismatic.
    """
    from aaria_pin.imu_layout import add_imu_frames
    from aaria_pin.runfile import read_generic_run

    record = read_generic_run(file)
    attributes = record.attributes
    try:
        model = pin.buildModelFromXML(record.urdf)
    except (RuntimeError, ValueError) as exc:
        raise InputFileError(f"{file}: its URDF cannot be built ({exc})") from None
    add_imu_frames(model, record.imu_mounts)
    base_frame = str(attributes.get("base_frame") or model.frames[1].name)
    tool_frame = str(attributes.get("tool_frame") or model.frames[-1].name)
    imu_names = tuple(mount.name for mount in record.imu_mounts)
    try:
        robot = RobotModel(model, record.urdf, False, base_frame, tool_frame, imu_names)
        for name in (base_frame, tool_frame):
            robot.frame_id(name)
    except ModelError as exc:
        raise InputFileError(f"{file}: {exc}") from None
    kinds = _joint_kinds(file, model, record.joint_names)
    time = np.asarray(record.time, dtype=float)
    q = np.asarray(record.q, dtype=float)
    origins = scene_poses(robot, scene_from_model(robot), BaseMotion.resting(1), still(q[:1]))
    extent = float(np.ptp(origins[0, :, :3, 3], axis=0).max())
    scene = scene_from_model(robot, size=max(0.01, 0.04 * extent))
    pairs = tuple(zip(record.joint_names, kinds, strict=True))
    q_labels = tuple(f"{name} [{'m' if kind == 'prismatic' else 'rad'}]" for name, kind in pairs)
    tau_labels = tuple(f"{name} [{'N' if kind == 'prismatic' else 'N·m'}]" for name, kind in pairs)
    moving = bool(attributes.get("moving_base", False))
    signals = Signals(
        time,
        q,
        q_labels,
        np.asarray(record.tau, dtype=float),
        tau_labels,
        np.asarray(record.base_wrench, dtype=float) if moving else None,
        {name: np.asarray(record.imu_signals(name), dtype=float) for name in imu_names},
        kinds,
    )
    base_pose = np.asarray(record.base_pose, dtype=float)

    def frame_poses(samples: Array) -> Array:
        index = np.asarray(samples, dtype=int)
        local = scene_poses(robot, scene, BaseMotion.resting(index.size), still(q[index]))
        local[:, 1:] = base_pose[index, None] @ local[:, 1:]
        return local

    return RunView(file.name, "generic", scene, signals, frame_poses)


def _joint_kinds(file: Path, model: pin.Model, names: tuple[str, ...]) -> tuple[str, ...]:
    """``"revolute"``/``"prismatic"`` of each stored joint, from its URDF joint type."""
    kinds = []
    for name in names:
        joint_id = model.getJointId(name)
        if joint_id >= model.njoints:
            raise InputFileError(f"{file}: joint {name!r} is not in the file's URDF")
        short = model.joints[joint_id].shortname()
        kind = joint_type_kind(short)
        if kind is None:
            raise InputFileError(
                f"{file}: joint {name!r} is a {short}; allowed: revolute and prismatic joints"
            )
        kinds.append(kind)
    return tuple(kinds)
