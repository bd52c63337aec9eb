"""What the pictures show, from a DH table or a run file: a scene, frame poses, signals.

A DH table (a preset or a file) gives one pose: every joint at zero, the base at the world
origin. A run file gives the run: the arm rebuilt from the file's inputs (its table, IMU mounts
and body dimensions), the frame poses over time computed by Pinocchio from the stored joint
values and the base motion (:func:`aaria_pin.kinematics.frame_poses`), and the stored signals.

Run kinds are recognised by :func:`run_kind` and loaded by the loader registered for them:
``"aaria"`` (``aaria simulate`` / data-set run files), ``"wrist"`` (``aaria wrist simulate``)
and ``"generic"`` (the generic run file of a URDF robot, which the pick-and-place arm writes
too: the model is rebuilt from the URDF text the file holds, drawn as a stick figure by
:func:`~aaria_pin.viz.scene.scene_from_model`, since URDF meshes are not drawn). Other kinds
plug in with :func:`register_run_kind`: a probe that recognises the file and a loader that
returns a :class:`RunView`.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin._se3 import Array
from aaria_pin.dh import Convention
from aaria_pin.dh_robot import DHRobot, build_dh_robot
from aaria_pin.errors import InputFileError, ParameterError
from aaria_pin.model import RobotModel
from aaria_pin.trajectory import BaseMotion, JointTrajectory
from aaria_pin.viz.scene import Scene, scene_from_dh_robot, scene_from_model

__all__ = [
    "RunView",
    "Signals",
    "load_run_view",
    "register_run_kind",
    "run_kind",
    "sample_at",
    "table_view",
]


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
    """

    time: Array
    q: Array
    q_labels: tuple[str, ...]
    tau: Array
    tau_labels: tuple[str, ...]
    base_wrench: Array | None = None
    imus: dict[str, Array] = field(default_factory=dict)


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


def _poses(robot: RobotModel, scene: Scene, base: BaseMotion, trajectory: JointTrajectory) -> Array:
    """World poses (T, F, 4, 4) of a scene's frames, the world's identity first."""
    from aaria_pin.kinematics import frame_poses

    model_poses = frame_poses(robot, base, trajectory, scene.model_frames)
    world = np.broadcast_to(np.eye(4), (model_poses.shape[0], 1, 4, 4))
    return np.concatenate([world, model_poses], axis=1)


def _subset(base: BaseMotion, samples: Array) -> BaseMotion:
    return BaseMotion(
        *(
            np.ascontiguousarray(getattr(base, name)[samples])
            for name in ("position", "velocity", "acceleration", "rotation", "omega", "omega_dot")
        )
    )


def _view(
    title: str,
    kind: str,
    robot: DHRobot,
    moving_base: bool,
    base: BaseMotion,
    q: Array,
    signals: Signals,
) -> RunView:
    model = robot.model(moving_base=moving_base)
    scene = scene_from_dh_robot(robot, title)

    def frame_poses(samples: Array) -> Array:
        index = np.asarray(samples, dtype=int)
        values = np.ascontiguousarray(q[index])
        zeros = np.zeros_like(values)
        trajectory = JointTrajectory(signals.time[index], values, zeros, zeros.copy())
        return _poses(model, scene, _subset(base, index), trajectory)

    return RunView(title, kind, scene, signals, frame_poses)


def table_view(
    table: ArrayLike, convention: Convention = "aaria", name: str = "arm"
) -> tuple[Scene, Array]:
    """The scene of a DH table and its frame poses with every joint at zero, base at the origin.

    Args:
        table: the DH table
        convention: its convention
        name: what to call it

    Returns:
        The scene and the (F, 4, 4) world pose of each of its frames.

    Raises:
        TableError: a bad table.
    """
    robot = build_dh_robot(table, convention)
    model = robot.model(moving_base=False)
    scene = scene_from_dh_robot(robot, name)
    n = model.n_joints
    zeros = np.zeros((1, n))
    trajectory = JointTrajectory(np.zeros(1), zeros, zeros.copy(), zeros.copy())
    return scene, _poses(model, scene, BaseMotion.resting(1), trajectory)[0]


def sample_at(time: Array, t: float) -> int:
    """Index of the sample nearest to time ``t`` [s].

    Raises:
        ParameterError: ``t`` outside the run (beyond half a sample step of its ends).
    """
    step = float(np.median(np.diff(time))) if time.size > 1 else 0.0
    if not (np.isfinite(t) and time[0] - step / 2 <= t <= time[-1] + step / 2):
        raise ParameterError(
            f"time {t:g} s is outside the run; allowed: {time[0]:g} to {time[-1]:g} s"
        )
    return int(np.argmin(np.abs(time - t)))


# --- run kinds -----------------------------------------------------------------------------------

Probe = Callable[[Path], bool]
Loader = Callable[[Path], RunView]
_KINDS: dict[str, tuple[Probe, Loader]] = {}


def register_run_kind(kind: str, probe: Probe, loader: Loader) -> None:
    """Teach the viewers a new kind of run file.

    Args:
        kind: its name
        probe: True for a file of this kind (it must not raise on other files)
        loader: reads such a file into a :class:`RunView`
    """
    _KINDS[kind] = (probe, loader)


def _hdf5_attributes(file: Path) -> tuple[set[str], dict[str, object]]:
    import h5py

    try:
        with h5py.File(file, "r") as handle:
            return set(handle.keys()), {key: handle.attrs[key] for key in handle.attrs}
    except OSError:
        return set(), {}


def _mat_names(file: Path) -> set[str]:
    from scipy.io import whosmat

    try:
        return {name for name, _, _ in whosmat(file)}
    except (OSError, ValueError, NotImplementedError):
        return set()


def _is_aaria(file: Path) -> bool:
    if file.suffix.lower() == ".mat":
        names = _mat_names(file)
        return "senSen" in names and "attr_format" in names and "attr_layout" not in names
    _, attributes = _hdf5_attributes(file)
    return attributes.get("format") == "aaria_pin run" and "layout" not in attributes


def _is_wrist(file: Path) -> bool:
    if file.suffix.lower() == ".mat":
        names = _mat_names(file)
    else:
        keys, attributes = _hdf5_attributes(file)
        names = keys | set(attributes)
    return {"time", "q", "tau", "targets_rad"} <= names


def run_kind(path: str | os.PathLike[str]) -> str:
    """The kind of a run file (a key given to :func:`register_run_kind`).

    Raises:
        InputFileError: a missing file, or none of the known kinds.
    """
    file = Path(path)
    if not file.is_file():
        raise InputFileError(f"{file}: no such file")
    for kind, (probe, _) in _KINDS.items():
        if probe(file):
            return kind
    raise InputFileError(
        f"{file}: not a run file the viewers know; allowed: {', '.join(_KINDS)} run files"
        " (.h5 or .mat)"
    )


def load_run_view(path: str | os.PathLike[str]) -> RunView:
    """Read a run file of any known kind for drawing.

    Raises:
        InputFileError: as :func:`run_kind`, or an unreadable file.
    """
    file = Path(path)
    return _KINDS[run_kind(file)][1](file)


def _joint_labels(
    symbols: Sequence[str], kinds: Sequence[str], modules: Sequence[int]
) -> tuple[tuple[str, ...], tuple[str, ...]]:
    q_labels = tuple(
        f"q{m} [{'rad' if k == 'revolute' else 'm'}]" for k, m in zip(kinds, modules, strict=True)
    )
    tau_labels = tuple(
        f"{s}{m} [{'N·m' if k == 'revolute' else 'N'}]"
        for s, k, m in zip(symbols, kinds, modules, strict=True)
    )
    return q_labels, tau_labels


def _load_aaria(file: Path) -> RunView:
    from aaria_pin.dh_robot import BodyDimensions
    from aaria_pin.oscillation import base_motion
    from aaria_pin.record import imu_slot_order
    from aaria_pin.runfile import read_run
    from aaria_pin.simulate import mounted_slots

    record = read_run(file)
    dims = None
    if "body_dimensions" in record.attributes:
        try:
            dims = BodyDimensions(**record.attributes["body_dimensions"])
        except TypeError as exc:
            raise InputFileError(f"{file}: body_dimensions cannot be used ({exc})") from None
    robot = build_dh_robot(record.senSenDH, "aaria", dims)
    robot = build_dh_robot(
        record.senSenDH, "aaria", dims, imu_slots=mounted_slots(robot, record.imu_mount)
    )
    time = np.asarray(record.senSen[:, 0], dtype=float)
    columns = [module - 1 for module in robot.chain.modules]
    kinds = [joint.kind for joint in robot.chain.joints]
    symbols = ["tau" if kind == "revolute" else "f" for kind in kinds]
    q_labels, tau_labels = _joint_labels(symbols, kinds, robot.chain.modules)
    block = record.senSen[:, 7:].reshape(time.size, -1, 6)
    imus = {
        name: np.asarray(block[:, k], dtype=float)
        for k, (name, slot) in enumerate(zip(imu_slot_order(), robot.imu_slots, strict=True))
        if slot.parent is not None
    }
    signals = Signals(
        time,
        np.asarray(record.q[:, columns], dtype=float),
        q_labels,
        np.asarray(record.tau[:, columns], dtype=float),
        tau_labels,
        np.asarray(record.base_wrench, dtype=float),
        imus,
    )
    base = base_motion(record.senSenB, time)
    return _view(file.name, "aaria", robot, True, base, signals.q, signals)


def _load_wrist(file: Path) -> RunView:
    from aaria_pin.wrist_run import report_wrist

    if file.suffix.lower() == ".mat":
        from scipy.io import loadmat

        contents = loadmat(file)
        arrays = {name: np.asarray(contents[name], dtype=float) for name in ("time", "q", "tau")}
    else:
        import h5py

        with h5py.File(file, "r") as handle:
            arrays = {name: np.asarray(handle[name], dtype=float) for name in ("time", "q", "tau")}
    time = arrays["time"].reshape(-1)
    q, tau = (arrays[name].reshape(time.size, -1) for name in ("q", "tau"))
    robot = report_wrist()
    if q.shape[1] != len(robot.chain.joints) or tau.shape != q.shape:
        raise InputFileError(f"{file}: q of shape {q.shape}, tau {tau.shape}; allowed: T × 3 each")
    modules = robot.chain.modules
    kinds = ["revolute"] * len(modules)
    q_labels, tau_labels = _joint_labels(["tau"] * len(modules), kinds, modules)
    signals = Signals(time, q, q_labels, tau, tau_labels)
    return _view(file.name, "wrist", robot, False, BaseMotion.resting(time.size), q, signals)


def _is_generic(file: Path) -> bool:
    from aaria_pin.runfile import is_generic_run_file

    return is_generic_run_file(file)


def _load_generic(file: Path) -> RunView:
    import pinocchio as pin

    from aaria_pin.errors import ModelError
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
    time = np.asarray(record.time, dtype=float)
    q = np.asarray(record.q, dtype=float)
    origins = _poses(robot, scene_from_model(robot), BaseMotion.resting(1), _still(q[:1]))
    extent = float(np.ptp(origins[0, :, :3, 3], axis=0).max())
    scene = scene_from_model(robot, size=max(0.01, 0.04 * extent))
    kinds = [
        "prismatic" if model.joints[j].shortname().startswith("JointModelP") else "revolute"
        for j in range(1, model.njoints)
    ]
    q_labels = tuple(
        f"{name} [{'m' if kind == 'prismatic' else 'rad'}]"
        for name, kind in zip(record.joint_names, kinds, strict=False)
    )
    tau_labels = tuple(
        f"{name} [{'N' if kind == 'prismatic' else 'N·m'}]"
        for name, kind in zip(record.joint_names, kinds, strict=False)
    )
    moving = bool(attributes.get("moving_base", False))
    signals = Signals(
        time,
        q,
        q_labels,
        np.asarray(record.tau, dtype=float),
        tau_labels,
        np.asarray(record.base_wrench, dtype=float) if moving else None,
        {name: np.asarray(record.imu_signals(name), dtype=float) for name in imu_names},
    )
    base_pose = np.asarray(record.base_pose, dtype=float)

    def frame_poses(samples: Array) -> Array:
        index = np.asarray(samples, dtype=int)
        local = _poses(robot, scene, BaseMotion.resting(index.size), _still(q[index]))
        local[:, 1:] = base_pose[index, None] @ local[:, 1:]
        return local

    return RunView(file.name, "generic", scene, signals, frame_poses)


def _still(q: Array) -> JointTrajectory:
    values = np.ascontiguousarray(q)
    zeros = np.zeros_like(values)
    return JointTrajectory(np.zeros(values.shape[0]), values, zeros, zeros.copy())


register_run_kind("aaria", _is_aaria, _load_aaria)
register_run_kind("wrist", _is_wrist, _load_wrist)
register_run_kind("generic", _is_generic, _load_generic)
