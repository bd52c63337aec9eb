"""The ``"model"`` run kind: any run, drawn from the model it stores, as the robot looks.

The model is rebuilt from the record (:func:`aaria_pin.apps.record_model.record_model`: its URDF
text, or an Aaria run's DH table when it has none), with a frame for each mounted IMU. Its links
are drawn with their URDF visual geometry (meshes, boxes, cylinders, spheres, in their colours:
:func:`aaria_pin.viz.visuals.urdf_visual_solids`), with the world, tool and IMU frames of
:func:`~aaria_pin.viz.scene.scene_from_model`; a model with no visual geometry is drawn as that
function's stick figure. The kind of each
joint (for units and panels) is its Pinocchio joint type
(:func:`aaria_pin.core.kinematics.joint_kind`), the joint matched by exact name. It is the
fallback kind: tried after every other kind, so it draws any run the others do not claim (a
URDF robot's).

:func:`read_model_view` does everything but the scene (the record, the model, the labelled
signals, the frame poses), so an application's kind draws its own scene on the same model (the
pick-and-place arm's, :mod:`aaria_pin.viz._arm_source`).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from dataclasses import replace as replace_fields
from pathlib import Path

import numpy as np

from aaria_pin.core.model import RobotModel
from aaria_pin.core.record import RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion
from aaria_pin.errors import InputFileError, ModelError
from aaria_pin.viz._run_view import (
    RunFile,
    RunView,
    Signals,
    base_subset,
    record_signals,
    run_file,
    run_record,
    run_title,
    scene_poses,
    still,
)
from aaria_pin.viz.scene import Scene, scene_from_model

__all__ = [
    "MODEL_KIND",
    "ModelView",
    "is_any_run",
    "load_model_run",
    "read_model_view",
    "with_visuals",
]

MODEL_KIND = "model"
"""The kind's name: the run is drawn from the model it stores."""


def is_any_run(file: str | os.PathLike[str] | RunFile) -> bool:
    """Whether ``file`` holds a run of any robot (a run file of any kind and version)."""
    return run_file(file).record is not None


@dataclass(frozen=True)
class ModelView:
    """A run read for drawing, all but its scene.

    Attributes:
        record: the run's record
        robot: the model rebuilt from it (IMU frames added; a free-flyer base where it moves)
        signals: its signals, labelled with units
        base: the base motion (None: fixed at the world origin)
    """

    record: RunRecord
    robot: RobotModel
    signals: Signals
    base: BaseMotion | None = None

    def poser(self, frames: Sequence[str]) -> Callable[[Array], Array]:
        """Given sample indices (S,), the world poses (S, F, 4, 4) of model frames [m]."""
        from aaria_pin.core.kinematics import frame_poses

        q = self.signals.q
        names = list(frames)

        def poses(samples: Array) -> Array:
            index = np.asarray(samples, dtype=int)
            resting = BaseMotion.resting(index.size)
            base = resting if self.base is None else base_subset(self.base, index)
            return np.asarray(frame_poses(self.robot, base, still(q[index]), names))

        return poses


def _with_imu_frames(robot: RobotModel, record: RunRecord) -> RobotModel:
    """The model with a frame for each mounted IMU of the record it does not have yet."""
    from aaria_pin.core.imu_layout import add_imu_frames

    mounted = [mount for mount in record.imu_mounts if mount.parent]
    missing = [mount for mount in mounted if not robot.model.existFrame(mount.name)]
    try:
        add_imu_frames(robot.model, missing)
    except ModelError as exc:
        raise InputFileError(
            f"the run's IMU mounts cannot be used: {exc}", parameter="record"
        ) from None
    return replace_fields(robot, sensor_frames=tuple(mount.name for mount in mounted))


def read_model_view(path: str | os.PathLike[str]) -> ModelView:
    """Read a run's record, model and signals (labelled by joint name).

    Args:
        path: a run file, or a :class:`~aaria_pin.viz._run_view.RunFile` (a run of a data set)

    Raises:
        InputFileError: an unreadable file, a model that cannot be rebuilt, an IMU on a frame
            the model lacks, or a stored joint that is neither revolute nor prismatic.
    """
    from aaria_pin.apps.record_model import record_base, record_model

    record = run_record(path)
    base = record_base(record)
    try:
        robot = _with_imu_frames(record_model(record, moving_base=base is not None), record)
        signals = record_signals(record, robot)
    except InputFileError as exc:
        raise InputFileError(f"{os.fspath(path)}: {exc}", parameter="run") from None
    return ModelView(record, robot, signals, base)


def with_visuals(scene: Scene, robot: RobotModel, urdf: str, urdf_dir: Path | None = None) -> Scene:
    """A model's scene with its URDF visual geometry in place of its stick figure.

    The scene's frames' axes (world, tool, IMUs) stay; its joint cylinders and bones go when
    the URDF has any visual geometry on the model's frames (else the scene is returned as is).
    Meshes given by relative path are found in ``urdf_dir`` (the run's ``urdf_dir``
    attribute); meshes that cannot be found are named in a warning.
    """
    import warnings

    from aaria_pin.errors import MeshWarning
    from aaria_pin.viz.visuals import urdf_visual_solids

    names = [str(frame.name) for frame in robot.model.frames]
    visuals = urdf_visual_solids(urdf, names, urdf_dir)
    if visuals.missing:
        shown = ", ".join(str(m) for m in list(visuals.missing)[:3])
        warnings.warn(
            f"{len(visuals.missing)} visual mesh(es) not found, drawn without them: {shown}",
            MeshWarning,
            stacklevel=2,
        )
    if not visuals.solids:
        return scene
    frames = tuple(dict.fromkeys([*scene.frames, *(s.frame for s in visuals.solids)]))
    return Scene(scene.name, frames, visuals.solids, scene.lines)


def load_model_run(path: str | os.PathLike[str]) -> RunView:
    """Read a run for drawing: the model with its URDF visual geometry (or a stick figure).

    Raises:
        InputFileError: as :func:`read_model_view`.
    """
    view = read_model_view(path)
    robot = view.robot
    q = view.signals.q
    origins = scene_poses(robot, scene_from_model(robot), BaseMotion.resting(1), still(q[:1]))
    extent = float(np.ptp(origins[0, :, :3, 3], axis=0).max())
    scene = scene_from_model(robot, size=max(0.01, 0.04 * extent))
    if view.record.urdf:
        folder = view.record.metadata.urdf_dir
        scene = with_visuals(scene, robot, view.record.urdf, Path(folder) if folder else None)
    poser = view.poser(scene.model_frames)

    def frame_poses(samples: Array) -> Array:
        model_poses = poser(samples)
        world = np.broadcast_to(np.eye(4), (model_poses.shape[0], 1, 4, 4))
        return np.concatenate([world, model_poses], axis=1)

    return RunView(run_title(path), MODEL_KIND, scene, view.signals, frame_poses)
