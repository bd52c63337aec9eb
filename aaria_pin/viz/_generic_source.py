"""The ``"generic"`` run kind: the run file of a URDF robot (``aaria simulate --robot/--urdf``).

The model is rebuilt from the URDF text the file holds and drawn as a stick figure by
:func:`~aaria_pin.viz.scene.scene_from_model` (URDF meshes are not drawn). The kind of each
joint (for units and panels) is its Pinocchio joint type
(:func:`aaria_pin.core.kinematics.joint_kind`), matched by exact name.

:func:`read_generic_view` does everything but the scene (the record, the model, the labelled
signals, the frame poses), so an application's kind of generic run file draws its own scene on
the same model (the pick-and-place arm's, :mod:`aaria_pin.viz._arm_source`).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from aaria_pin.core.model import RobotModel
from aaria_pin.core.record import GenericRunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion
from aaria_pin.errors import InputFileError, ModelError
from aaria_pin.viz._run_view import RunFile, RunView, Signals, run_file, scene_poses, still
from aaria_pin.viz.scene import scene_from_model

__all__ = ["GenericView", "is_generic_run", "load_generic_run", "read_generic_view"]

_HDF5_SUFFIXES = (".h5", ".hdf5")


def is_generic_run(file: Path | RunFile) -> bool:
    """Whether ``file`` is an HDF5 file marked as a generic (URDF robot) run file."""
    from aaria_pin.files.runfile import GENERIC_FORMAT

    header = run_file(file)
    return header.suffix in _HDF5_SUFFIXES and header.text("format") == GENERIC_FORMAT


@dataclass(frozen=True)
class GenericView:
    """A generic run file read for drawing, all but its scene.

    Attributes:
        record: the file's record
        robot: the model built from its URDF (fixed base; IMU frames added)
        signals: its signals, labelled with units
    """

    record: GenericRunRecord
    robot: RobotModel
    signals: Signals

    def poser(self, frames: Sequence[str]) -> Callable[[Array], Array]:
        """Given sample indices (S,), the world poses (S, F, 4, 4) of model frames [m]."""
        from aaria_pin.core.kinematics import frame_poses

        q = self.signals.q
        base_pose = np.asarray(self.record.base_pose, dtype=float)
        names = list(frames)

        def poses(samples: Array) -> Array:
            index = np.asarray(samples, dtype=int)
            local = frame_poses(self.robot, BaseMotion.resting(index.size), still(q[index]), names)
            return np.asarray(base_pose[index, None] @ local)

        return poses


def read_generic_view(path: str | os.PathLike[str]) -> GenericView:
    """Read a generic run file's record, model and signals.

    The mount's wrench is shown where the base moves or the file stores a non-zero one.

    Raises:
        InputFileError: an unreadable file, a URDF that cannot be built, an unknown base or
            tool frame, or a stored joint that is neither revolute nor prismatic.
    """
    from aaria_pin.core.imu_layout import add_imu_frames
    from aaria_pin.files.runfile import read_generic_run

    file = Path(path)
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
    pairs = tuple(zip(record.joint_names, kinds, strict=True))
    q_labels = tuple(f"{name} [{'m' if kind == 'prismatic' else 'rad'}]" for name, kind in pairs)
    tau_labels = tuple(f"{name} [{'N' if kind == 'prismatic' else 'N·m'}]" for name, kind in pairs)
    wrench = np.asarray(record.base_wrench, dtype=float)
    shown = bool(attributes.get("moving_base", False)) or bool(np.any(wrench))
    signals = Signals(
        np.asarray(record.time, dtype=float),
        np.asarray(record.q, dtype=float),
        q_labels,
        np.asarray(record.tau, dtype=float),
        tau_labels,
        wrench if shown else None,
        {name: np.asarray(record.imu_signals(name), dtype=float) for name in imu_names},
        kinds,
    )
    return GenericView(record, robot, signals)


def load_generic_run(path: str | os.PathLike[str]) -> RunView:
    """Read a generic run file for drawing: the model as a stick figure.

    Raises:
        InputFileError: as :func:`read_generic_view`.
    """
    file = Path(path)
    view = read_generic_view(file)
    robot = view.robot
    q = view.signals.q
    origins = scene_poses(robot, scene_from_model(robot), BaseMotion.resting(1), still(q[:1]))
    extent = float(np.ptp(origins[0, :, :3, 3], axis=0).max())
    scene = scene_from_model(robot, size=max(0.01, 0.04 * extent))
    poser = view.poser(scene.model_frames)

    def frame_poses(samples: Array) -> Array:
        model_poses = poser(samples)
        world = np.broadcast_to(np.eye(4), (model_poses.shape[0], 1, 4, 4))
        return np.concatenate([world, model_poses], axis=1)

    return RunView(file.name, "generic", scene, view.signals, frame_poses)


def _joint_kinds(file: Path, model: pin.Model, names: tuple[str, ...]) -> tuple[str, ...]:
    """``"revolute"``/``"prismatic"`` of each stored joint, from its URDF joint type."""
    from aaria_pin.core.kinematics import joint_kind

    kinds = []
    for name in names:
        joint_id = model.getJointId(name)
        if joint_id >= model.njoints:
            raise InputFileError(f"{file}: joint {name!r} is not in the file's URDF")
        joint = model.joints[joint_id]
        try:
            kind, _ = joint_kind(joint)
        except ModelError:
            kind = ""
        if kind not in ("revolute", "prismatic"):
            raise InputFileError(
                f"{file}: joint {name!r} is a {joint.shortname()}; allowed: revolute and"
                " prismatic joints"
            )
        kinds.append(kind)
    return tuple(kinds)
