"""What a run kind's loader returns (:class:`RunView`, :class:`Signals`) and the helpers it uses.

The loaders of :mod:`aaria_pin.viz.sources` (one module per run kind) build on these; the
public names are re-exported by :mod:`~aaria_pin.viz.sources`.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from aaria_pin.aaria.dh_robot import DHRobot
from aaria_pin.core.model import RobotModel
from aaria_pin.core.record import RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory
from aaria_pin.viz.scene import Scene, scene_from_dh_robot

__all__ = [
    "RunFile",
    "RunView",
    "Signals",
    "base_subset",
    "dataset_run",
    "dh_view",
    "joint_labels",
    "record_run",
    "record_signals",
    "run_file",
    "run_record",
    "run_title",
    "scene_poses",
    "still",
]

_FORCE_UNITS = {"N": "prismatic", "N·m": "revolute"}


@dataclass(frozen=True)
class Signals:
    """The signals of a run, labelled, with units.

    Attributes:
        time: sample times (T,) [s]
        q: joint values (T, n) [rad or m]
        q_labels: one label per column of ``q``, units included (``"q1 [rad]"``)
        tau: joint torques or forces (T, n) [N·m or N]
        tau_labels: one label per column of ``tau``, units included
        base_wrench: ``[fx fy fz mx my mz]`` (T, 6) [N, N·m], or None
        imus: IMU name → ``[wx wy wz fx fy fz]`` (T, 6) [rad/s, m/s²], in record order
        joint_kinds: ``"revolute"`` or ``"prismatic"`` per joint (column of ``q`` and ``tau``);
            empty: told by the unit of each torque label (``[N]`` prismatic, ``[N·m]`` revolute)
    """

    time: Array
    q: Array
    q_labels: tuple[str, ...]
    tau: Array
    tau_labels: tuple[str, ...]
    base_wrench: Array | None = None
    imus: dict[str, Array] = field(default_factory=dict)
    joint_kinds: tuple[str, ...] = ()

    @property
    def kinds(self) -> tuple[str, ...]:
        """The kind of each joint, ``"revolute"`` or ``"prismatic"`` (see ``joint_kinds``)."""
        if self.joint_kinds:
            return self.joint_kinds
        return tuple(
            _FORCE_UNITS.get(label.rsplit("[", 1)[-1].rstrip("]"), "revolute")
            for label in self.tau_labels
        )


@dataclass(frozen=True)
class RunView:
    """A run ready to be drawn.

    Attributes:
        title: what to call it (the file name)
        kind: the run kind (``"aaria"``, ``"wrist"``, …)
        scene: the arm's scene
        signals: the stored signals
        frame_poses: given sample indices (S,), the world pose of every scene frame,
            (S, F, 4, 4)
    """

    title: str
    kind: str
    scene: Scene
    signals: Signals
    frame_poses: Callable[[Array], Array]

    @property
    def time(self) -> Array:
        """Sample times (T,) [s]."""
        return self.signals.time


def scene_poses(
    robot: RobotModel, scene: Scene, base: BaseMotion, trajectory: JointTrajectory
) -> Array:
    """World poses (T, F, 4, 4) of a scene's frames, the world's identity first.

    Args:
        robot: the model the scene draws
        scene: the scene (``scene.model_frames`` are frames of ``robot``)
        base: the base motion, one sample per trajectory sample
        trajectory: joint values (T, n) [rad or m]
    """
    from aaria_pin.core.kinematics import frame_poses

    model_poses = frame_poses(robot, base, trajectory, scene.model_frames)
    world = np.broadcast_to(np.eye(4), (model_poses.shape[0], 1, 4, 4))
    return np.concatenate([world, model_poses], axis=1)


def still(q: Array) -> JointTrajectory:
    """Joint values (T, n) [rad or m] as a trajectory with zero rates (enough for poses)."""
    values = np.ascontiguousarray(q)
    zeros = np.zeros_like(values)
    return JointTrajectory(np.zeros(values.shape[0]), values, zeros, zeros.copy())


def base_subset(base: BaseMotion, samples: Array) -> BaseMotion:
    """The base motion at the given sample indices (S,)."""
    return BaseMotion(
        *(
            np.ascontiguousarray(getattr(base, name)[samples])
            for name in ("position", "velocity", "acceleration", "rotation", "omega", "omega_dot")
        )
    )


def dh_view(
    title: str,
    kind: str,
    robot: DHRobot,
    base: BaseMotion | None,
    q: Array,
    signals: Signals,
) -> RunView:
    """The view of a run of a DH arm, drawn as the paper draws it.

    Args:
        title: what to call it
        kind: its run kind
        robot: the arm
        base: the base motion over the run (None: fixed at the world origin)
        q: joint values (T, n) [rad or m], one column per joint of ``robot``
        signals: the stored signals
    """
    model = robot.model(moving_base=base is not None)
    scene = scene_from_dh_robot(robot, title)
    motion = BaseMotion.resting(q.shape[0]) if base is None else base

    def frame_poses(samples: Array) -> Array:
        index = np.asarray(samples, dtype=int)
        return scene_poses(model, scene, base_subset(motion, index), still(q[index]))

    return RunView(title, kind, scene, signals, frame_poses)


def record_signals(record: RunRecord, robot: RobotModel, by_module: bool = False) -> Signals:
    """A record's signals for the model's joints (matched by name), labelled with units.

    Args:
        record: the run's record
        robot: the model it is drawn on (its joints name columns of the record; an Aaria
            run's empty module has none and is left out)
        by_module: label joints by their 1-based column (``"q3 [m]"``, ``"f3 [N]"``, the
            paper's modules), else by name (``"shoulder [rad]"``, ``"shoulder [N·m]"``)

    Returns:
        The signals; the base wrench where the base moves (a base table) or the record's is not
        zero; every mounted IMU (an empty slot is left out).

    Raises:
        InputFileError: a joint of the model with no column, or neither revolute nor prismatic.
    """
    from aaria_pin.apps.record_model import BASE_TABLES, record_columns, record_joint_kinds

    kinds = record_joint_kinds(robot)
    columns = record_columns(record, robot)
    if by_module:
        symbols = ["tau" if kind == "revolute" else "f" for kind in kinds]
        q_labels, tau_labels = joint_labels(symbols, kinds, [c + 1 for c in columns])
    else:
        pairs = tuple(zip(robot.joint_names, kinds, strict=True))
        q_labels = tuple(f"{n} [{'m' if k == 'prismatic' else 'rad'}]" for n, k in pairs)
        tau_labels = tuple(f"{n} [{'N' if k == 'prismatic' else 'N·m'}]" for n, k in pairs)
    wrench = np.asarray(record.base_wrench, dtype=float)
    moving = any(name in record.tables for name in BASE_TABLES)
    return Signals(
        np.asarray(record.time, dtype=float),
        np.asarray(record.q, dtype=float)[:, columns],
        q_labels,
        np.asarray(record.tau, dtype=float)[:, columns],
        tau_labels,
        wrench if moving or bool(np.any(wrench)) else None,
        {
            mount.name: np.asarray(record.imu_signals(mount.name), dtype=float)
            for mount in record.imu_mounts
            if mount.parent
        },
        kinds,
    )


def joint_labels(
    symbols: Sequence[str], kinds: Sequence[str], modules: Sequence[int]
) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """Labels with units of joint values and torques: ``("q2 [rad]", …), ("tau2 [N·m]", …)``.

    Args:
        symbols: torque symbol per joint (``"tau"``, ``"f"``)
        kinds: ``"revolute"`` or ``"prismatic"`` per joint
        modules: module number per joint
    """
    q_labels = tuple(
        f"q{m} [{'rad' if k == 'revolute' else 'm'}]" for k, m in zip(kinds, modules, strict=True)
    )
    tau_labels = tuple(
        f"{s}{m} [{'N·m' if k == 'revolute' else 'N'}]"
        for s, k, m in zip(symbols, kinds, modules, strict=True)
    )
    return q_labels, tau_labels


@dataclass(frozen=True)
class RunFile:
    """A run to draw: its file, and its record, read once.

    Every run kind's probe is given one (it is path-like: ``os.fspath`` gives the file, so a
    probe or a loader written for a path takes it too; ``str`` gives the file, or ``run K of
    FILE``, for a message). The record is read on first use
    (:attr:`record`) and kept, so the probes and the loader read the file once.

    Attributes:
        path: the file (a run file, or the data set holding the run)
        run: the run's index in a data set (None: ``path`` is a run file)
    """

    path: Path
    run: int | None = None
    _records: list[RunRecord | None] = field(default_factory=list, compare=False, repr=False)

    def __fspath__(self) -> str:
        return os.fspath(self.path)

    def __str__(self) -> str:
        """How a message names the run: ``FILE``, or ``run K of FILE`` for a data set's run."""
        from aaria_pin.core.record_checks import record_source

        return record_source(self.path, self.run)

    @property
    def title(self) -> str:
        """What to call the run: the file's name, and the run's index in a data set."""
        return self.path.name if self.run is None else f"{self.path.name} run {self.run}"

    @property
    def record(self) -> RunRecord | None:
        """The run's record (read on first use), or None if the file is not a run file.

        Raises:
            InputFileError: a run file or data set that cannot be read.
        """
        if not self._records:
            self._records.append(_read_record(self.path, self.run))
        return self._records[0]


def _read_record(path: Path, run: int | None) -> RunRecord | None:
    """A run file's record (None if it is not one), or run ``run`` of a data set."""
    from aaria_pin.files.runfile import is_run_file
    from aaria_pin.files.source import open_record

    if run is None and (not path.is_file() or not is_run_file(path)):
        return None
    return open_record(path, run)


def run_file(file: str | os.PathLike[str]) -> RunFile:
    """A run file as a :class:`RunFile` (one is passed through); never raises.

    Its record is read later, on first use.
    """
    return file if isinstance(file, RunFile) else RunFile(Path(file))


def dataset_run(path: str | os.PathLike[str], run: int) -> RunFile:
    """Run ``run`` of a data set, as a :class:`RunFile` whose record is that run's."""
    return RunFile(Path(path), run)


def record_run(record: RunRecord, title: str = "run") -> RunFile:
    """A record already in memory, as a :class:`RunFile` (its path is ``title``; no file)."""
    return RunFile(Path(title), None, [record])


def run_record(file: str | os.PathLike[str]) -> RunRecord:
    """The record of a run: a :class:`RunFile`'s (read once), or a run file's.

    Raises:
        InputFileError: not a run file, or one that cannot be read.
    """
    from aaria_pin.errors import InputFileError

    record = file.record if isinstance(file, RunFile) else _read_record(Path(file), None)
    if record is None:
        raise InputFileError(
            f"{os.fspath(file)}: not a run file; allowed: a run file of aaria_pin",
            parameter="file",
            value=os.fspath(file),
        )
    return record


def run_title(file: str | os.PathLike[str]) -> str:
    """What to call a run (:attr:`RunFile.title`, or the file's name)."""
    return file.title if isinstance(file, RunFile) else Path(file).name
