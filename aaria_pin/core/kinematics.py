"""Frame kinematics and IMU signals over whole trajectories, as arrays.

:func:`trajectory_signals` runs Pinocchio's forward pass for a whole trajectory in one compiled
loop (numba; see ``_kinematics_kernel``): each joint frame's angular velocity, angular
acceleration and proper acceleration (classical acceleration minus gravity) in its own axes,
and its world pose. Frames (IMUs, the tool) are read off their parent joint. It supports
revolute and prismatic joints about any axis and a free-flyer root that carries the prescribed
base motion. One Python call per trajectory, not per sample: a per-sample loop over
Pinocchio's frame functions costs about 70 times the batched RNEA.

The tests hold it equal to Pinocchio's frame algorithms called one sample at a time (their
oracle, ``tests/pinocchio_oracles.py``).

An IMU reports angular velocity and specific force (the frame origin's acceleration minus
gravity), both in its own axes.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from aaria_pin.core.model import RobotModel
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory
from aaria_pin.errors import ModelError

__all__ = [
    "frame_poses",
    "full_state",
    "imu_signals",
    "joint_configuration",
    "joint_kind",
    "trajectory_signals",
]

_AXES = {
    "X": np.array([1.0, 0.0, 0.0]),
    "Y": np.array([0.0, 1.0, 0.0]),
    "Z": np.array([0.0, 0.0, 1.0]),
}


def _unaligned_axis(joint: pin.JointModel, kind: str) -> Array:
    """The unit axis of an unaligned joint, from its motion subspace at the neutral value.

    (Pinocchio 4 exposes no ``axis`` on the unbounded unaligned revolute joint.)
    """
    data = joint.createData()
    neutral = np.array([1.0, 0.0]) if joint.nq == 2 else np.zeros(joint.nq)
    joint.calc(data, neutral)
    S = np.asarray(data.S, dtype=float).reshape(6)
    axis = S[3:] if kind == "revolute" else S[:3]
    return axis / np.linalg.norm(axis)


def joint_kind(joint: pin.JointModel) -> tuple[str, Array]:
    """A Pinocchio joint's kind (``"revolute"``, ``"prismatic"``, ``"freeflyer"``) and unit axis.

    Raises:
        ModelError: any other joint type.
    """
    name = joint.shortname()
    if name == "JointModelFreeFlyer":
        return "freeflyer", np.zeros(3)
    for prefix, kind in (
        ("JointModelRUB", "revolute"),
        ("JointModelR", "revolute"),
        ("JointModelP", "prismatic"),
    ):
        if name.startswith(prefix):
            suffix = name[len(prefix) :]
            if suffix in _AXES:
                return kind, _AXES[suffix]
            if suffix in ("evoluteUnaligned", "evoluteUnboundedUnaligned", "rismaticUnaligned"):
                return kind, _unaligned_axis(joint, kind)
    raise ModelError(
        f"joint type {name} is not supported; allowed: revolute, prismatic, free-flyer",
        parameter="joint",
        value=name,
        allowed="revolute, prismatic, free-flyer",
    )


@dataclass(frozen=True)
class _FlatModel:
    """A Pinocchio model flattened into the arrays the compiled kernel reads."""

    kinds: Array
    axes: Array
    parents: Array
    columns: Array
    placement_R: Array
    placement_p: Array
    gravity: Array


def _flatten(robot: RobotModel) -> _FlatModel:
    from aaria_pin.core._kinematics_kernel import FREEFLYER, PRISMATIC, REVOLUTE

    model = robot.model
    codes = {"revolute": REVOLUTE, "prismatic": PRISMATIC, "freeflyer": FREEFLYER}
    kinds, axes, columns = [FREEFLYER], [np.zeros(3)], [0]
    column = 0
    for j in range(1, model.njoints):
        kind, axis = joint_kind(model.joints[j])
        kinds.append(codes[kind])
        axes.append(axis)
        columns.append(column)
        column += kind != "freeflyer"
    return _FlatModel(
        np.array(kinds, dtype=np.int64),
        np.array(axes),
        np.array(list(model.parents), dtype=np.int64),
        np.array(columns, dtype=np.int64),
        np.array([placement.rotation for placement in model.jointPlacements]),
        np.array([placement.translation for placement in model.jointPlacements]),
        np.asarray(model.gravity.linear, dtype=float).copy(),
    )


def _frames(robot: RobotModel, names: Sequence[str]) -> tuple[np.ndarray, Array, Array]:
    frames = [robot.model.frames[robot.frame_id(name)] for name in names]
    return (
        np.array([frame.parentJoint for frame in frames], dtype=np.int64).reshape(-1),
        np.array([frame.placement.rotation for frame in frames]).reshape(-1, 3, 3),
        np.array([frame.placement.translation for frame in frames]).reshape(-1, 3),
    )


def _check_shapes(robot: RobotModel, base: BaseMotion, trajectory: JointTrajectory) -> None:
    """Refuse arrays the compiled kernel would read out of bounds."""
    n = trajectory.q.shape[0]
    expected = (n, robot.n_joints)
    for name in ("q", "qd", "qdd"):
        shape = np.shape(getattr(trajectory, name))
        if shape != expected:
            raise ModelError(
                f"trajectory {name} has shape {shape}; allowed: {expected}",
                parameter="trajectory",
                value=shape,
                allowed=str(expected),
                element=name,
            )
    if robot.moving_base:
        for name, tail in (
            ("rotation", (3, 3)),
            ("position", (3,)),
            ("velocity", (3,)),
            ("acceleration", (3,)),
            ("omega", (3,)),
            ("omega_dot", (3,)),
        ):
            shape = np.shape(getattr(base, name))
            if shape != (n, *tail):
                raise ModelError(
                    f"base {name} has shape {shape}; allowed: {(n, *tail)}",
                    parameter="base",
                    value=shape,
                    allowed=str((n, *tail)),
                    element=name,
                )


def trajectory_signals(
    robot: RobotModel,
    base: BaseMotion,
    trajectory: JointTrajectory,
    imu_frames: Sequence[str],
    pose_frames: Sequence[str] = (),
    *,
    imu_out: Array | None = None,
    imu_slots: Sequence[int] | None = None,
) -> tuple[Array, Array]:
    """IMU signals and world poses of frames over a whole trajectory, in one compiled pass.

    Args:
        robot: the model (a moving base needs ``robot.moving_base``)
        base: the base motion (ignored on a fixed base, which rests at the world origin)
        trajectory: joint values over time, columns in model order
        imu_frames: frames whose IMU signals to compute
        pose_frames: frames whose world poses to compute
        imu_out: where to write the signals, (T, S, 6) (a view into a larger array is fine);
            default a new (T, F, 6) array
        imu_slots: the slot of ``imu_out`` each IMU frame goes to (default 0, 1, …)

    Returns:
        IMU signals ``[wx wy wz fx fy fz]`` (angular velocity [rad/s] and specific force
        [m/s²], in each frame's axes) and poses ``T_world_frame`` (T, P, 4, 4).
    """
    from aaria_pin.core._kinematics_kernel import trajectory_kinematics

    flat = _flatten(robot)
    n = trajectory.q.shape[0]
    _check_shapes(robot, base, trajectory)
    if robot.moving_base:
        base_arrays = [
            np.ascontiguousarray(x, dtype=float)
            for x in (base.rotation, base.position, base.omega, base.omega_dot, base.acceleration)
        ]
    else:
        base_arrays = [np.zeros((n, 3, 3)), *(np.zeros((n, 3)) for _ in range(4))]
    if imu_out is None:
        imu_out = np.empty((n, len(imu_frames), 6))
    slots = np.arange(len(imu_frames)) if imu_slots is None else np.asarray(imu_slots)
    if (
        imu_out.shape[0] != n
        or imu_out.shape[2:] != (6,)
        or len(slots) != len(imu_frames)
        or (len(slots) and not 0 <= slots.min() <= slots.max() < imu_out.shape[1])
    ):
        raise ModelError(
            f"imu_out of shape {imu_out.shape} and slots {slots.tolist()} do not fit"
            f" {len(imu_frames)} IMUs over {n} samples",
            parameter="imu_out",
            value=imu_out.shape,
            allowed=f"({n}, >= {len(imu_frames)}, 6) with a slot per IMU frame",
        )
    poses = np.empty((n, len(pose_frames), 4, 4))
    q, qd, qdd = (
        np.ascontiguousarray(x, dtype=float).reshape(n, -1)
        for x in (trajectory.q, trajectory.qd, trajectory.qdd)
    )
    trajectory_kinematics(
        flat.kinds,
        flat.axes,
        flat.parents,
        flat.columns,
        flat.placement_R,
        flat.placement_p,
        q,
        qd,
        qdd,
        *base_arrays,
        flat.gravity,
        *_frames(robot, imu_frames),
        slots.astype(np.int64),
        imu_out,
        *_frames(robot, pose_frames),
        poses,
    )
    return imu_out, poses


def imu_signals(
    robot: RobotModel, base: BaseMotion, trajectory: JointTrajectory, frames: Sequence[str]
) -> Array:
    """Noise-free IMU signals ``[wx wy wz fx fy fz]`` of frames over a trajectory, (T, F, 6).

    Args:
        robot: the model
        base: the base motion
        trajectory: joint values over time
        frames: IMU frame names

    Returns:
        Angular velocity [rad/s] and specific force [m/s²] in each IMU's axes.
    """
    return trajectory_signals(robot, base, trajectory, frames)[0]


def frame_poses(
    robot: RobotModel, base: BaseMotion, trajectory: JointTrajectory, frames: Sequence[str]
) -> Array:
    """World poses ``T_world_frame`` of frames over a trajectory, (T, F, 4, 4)."""
    return trajectory_signals(robot, base, trajectory, (), frames)[1]


def full_state(
    robot: RobotModel, base: BaseMotion, trajectory: JointTrajectory
) -> tuple[Array, Array, Array]:
    """Pinocchio configuration, velocity and acceleration over time, (T, nq) and (T, nv) ×2.

    On a moving base the free-flyer entries are the base pose ``[p, quat xyzw]``, its spatial
    velocity in base axes ``[Rᵀṗ, ω]`` and that velocity's derivative
    ``[Rᵀp̈ - ω × Rᵀṗ, ω̇]``.
    """
    if not robot.moving_base:
        return joint_configuration(robot, trajectory.q), trajectory.qd, trajectory.qdd
    from aaria_pin.core._kinematics_kernel import free_flyer_state

    n, n_joints = trajectory.q.shape
    q, v, a = np.empty((n, 7 + n_joints)), np.empty((n, 6 + n_joints)), np.empty((n, 6 + n_joints))
    free_flyer_state(
        *(
            np.ascontiguousarray(x, dtype=float)
            for x in (
                base.rotation,
                base.position,
                base.velocity,
                base.acceleration,
                base.omega,
                base.omega_dot,
            )
        ),
        q,
        v,
        a,
    )
    if robot.model.nq != 7 + n_joints:
        q = np.hstack([q[:, :7], joint_configuration(robot, trajectory.q)])
    else:
        q[:, 7:] = trajectory.q
    v[:, 6:] = trajectory.qd
    a[:, 6:] = trajectory.qdd
    return q, v, a


def joint_configuration(robot: RobotModel, joint_values: Array) -> Array:
    """Pinocchio configurations of the actuated joints from one value per joint, (T, nq - base).

    A continuous (unbounded revolute) joint has two configuration entries, ``cos θ, sin θ``;
    every other joint its value.
    """
    model = robot.model
    if model.nq - robot.base_nq == joint_values.shape[1]:
        return joint_values
    out = np.empty((joint_values.shape[0], model.nq - robot.base_nq))
    first = 2 if robot.moving_base else 1
    for column, joint in enumerate(model.joints[first:]):
        start = joint.idx_q - robot.base_nq
        if joint.nq == 2:
            out[:, start] = np.cos(joint_values[:, column])
            out[:, start + 1] = np.sin(joint_values[:, column])
        else:
            out[:, start] = joint_values[:, column]
    return out
