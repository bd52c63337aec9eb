"""Frame kinematics and IMU signals over whole trajectories, as arrays.

:func:`frame_kinematics` walks the Pinocchio model's joint tree once, with every quantity an
array over time (world-frame rotation, position, angular velocity and acceleration, linear
velocity and acceleration of each joint frame), then places the requested frames. It supports
revolute and prismatic joints about any axis and a free-flyer root that carries the prescribed
base motion. :func:`reference_imu_signals` computes the same signals one sample at a time with
Pinocchio's own frame algorithms; the tests hold the two equal.

An IMU reports angular velocity and specific force (the frame origin's acceleration minus
gravity), both in its own axes.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from aaria_pin._se3 import Array
from aaria_pin.errors import ModelError
from aaria_pin.model import GRAVITY, RobotModel
from aaria_pin.trajectory import BaseMotion, JointTrajectory

__all__ = [
    "FrameKinematics",
    "frame_kinematics",
    "full_state",
    "imu_signals",
    "reference_imu_signals",
]

_AXES = {
    "X": np.array([1.0, 0.0, 0.0]),
    "Y": np.array([0.0, 1.0, 0.0]),
    "Z": np.array([0.0, 0.0, 1.0]),
}


@dataclass(frozen=True)
class FrameKinematics:
    """Kinematics of frames over time, shape (T, F, ...).

    Attributes:
        rotation: ``R_world_frame``, (T, F, 3, 3)
        position: frame origin in the world, (T, F, 3) [m]
        omega: angular velocity in frame axes, (T, F, 3) [rad/s]
        acceleration: classical linear acceleration of the origin, frame axes, no gravity,
            (T, F, 3) [m/s²]
    """

    rotation: Array
    position: Array
    omega: Array
    acceleration: Array

    def specific_force(self, gravity: Array = GRAVITY) -> Array:
        """What an accelerometer on each frame measures: ``Rᵀ(a - g)``, (T, F, 3) [m/s²]."""
        return self.acceleration - np.einsum("tfji,j->tfi", self.rotation, gravity)

    def poses(self) -> Array:
        """Homogeneous poses ``T_world_frame``, (T, F, 4, 4)."""
        T = np.zeros((*self.position.shape[:2], 4, 4))
        T[..., :3, :3] = self.rotation
        T[..., :3, 3] = self.position
        T[..., 3, 3] = 1.0
        return T


def _joint_kind(joint: pin.JointModel) -> tuple[str, Array]:
    name = joint.shortname()
    if name == "JointModelFreeFlyer":
        return "freeflyer", np.zeros(3)
    for prefix, kind in (("JointModelR", "revolute"), ("JointModelP", "prismatic")):
        if name.startswith(prefix):
            suffix = name[len(prefix) :]
            if suffix in _AXES:
                return kind, _AXES[suffix]
            if suffix in ("evoluteUnaligned", "rismaticUnaligned"):
                return kind, np.asarray(joint.extract().axis, dtype=float)
    raise ModelError(
        f"joint type {name} is not supported; allowed: revolute, prismatic, free-flyer"
    )


def _cross(a: Array, b: Array) -> Array:
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)


def _axis_rotation(axis: Array, angle: Array) -> Array:
    """Rotations about a fixed unit axis by angles (T,), Rodrigues' formula, (T, 3, 3)."""
    c, s = np.cos(angle)[:, None, None], np.sin(angle)[:, None, None]
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + s * K + (1 - c) * (K @ K)


def _matvec(R: Array, v: Array) -> Array:
    return np.matmul(R, v[..., None])[..., 0]


def frame_kinematics(
    robot: RobotModel, base: BaseMotion, trajectory: JointTrajectory, frames: Sequence[str]
) -> FrameKinematics:
    """Kinematics of named frames over a whole trajectory.

    Args:
        robot: the model (a moving base needs ``robot.moving_base``)
        base: the base motion (ignored, and taken as resting at the origin, on a fixed base)
        trajectory: joint values over time, columns in model order
        frames: frame names

    Returns:
        The frames' kinematics, frame axis 1 in the order of ``frames``.
    """
    model = robot.model
    n = trajectory.q.shape[0]
    zero = np.zeros((1, 3))
    # per joint: R, p, omega, alpha, v, a (world axes); a fixed root is broadcast over time
    state: list[tuple[Array, Array, Array, Array, Array, Array]] = [
        (np.eye(3)[None], zero, zero, zero, zero, zero)
    ]
    column = 0
    for j in range(1, model.njoints):
        kind, axis = _joint_kind(model.joints[j])
        if kind == "freeflyer":
            R = base.rotation
            state.append(
                (
                    R,
                    base.position,
                    _matvec(R, base.omega),
                    _matvec(R, base.omega_dot),
                    base.velocity,
                    base.acceleration,
                )
            )
            continue
        Rp, pp, wp, alp, vp, ap = state[model.parents[j]]
        placement = model.jointPlacements[j]
        Rp_pl = Rp @ placement.rotation
        e = _matvec(Rp_pl, axis)
        q, qd, qdd = (x[:, column, None] for x in (trajectory.q, trajectory.qd, trajectory.qdd))
        column += 1
        d = _matvec(Rp, placement.translation)
        e_qd = e * qd
        if kind == "revolute":
            R = Rp_pl @ _axis_rotation(axis, q[:, 0])
            w, al = wp + e_qd, alp + e * qdd + _cross(wp, e_qd)
            v = vp + _cross(wp, d)
            a = ap + _cross(alp, d) + _cross(wp, _cross(wp, d))
        else:
            d = d + e * q
            R, w, al = Rp_pl, wp, alp
            v = vp + _cross(wp, d) + e_qd
            a = ap + _cross(alp, d) + _cross(wp, _cross(wp, d)) + 2.0 * _cross(wp, e_qd) + e * qdd
        state.append((np.broadcast_to(R, (n, 3, 3)), pp + d, w, al, v, a))
    rotations, positions, omegas, accelerations = [], [], [], []
    for name in frames:
        frame = model.frames[robot.frame_id(name)]
        Rj, pj, wj, alj, _, aj = state[frame.parentJoint]
        R = Rj @ frame.placement.rotation
        d = _matvec(Rj, frame.placement.translation)
        a = aj + _cross(alj, d) + _cross(wj, _cross(wj, d))
        Rt = np.swapaxes(np.broadcast_to(R, (n, 3, 3)), -1, -2)
        rotations.append(np.broadcast_to(R, (n, 3, 3)))
        positions.append(np.broadcast_to(pj + d, (n, 3)))
        omegas.append(_matvec(Rt, np.broadcast_to(wj, (n, 3))))
        accelerations.append(_matvec(Rt, np.broadcast_to(a, (n, 3))))
    return FrameKinematics(
        np.stack(rotations, axis=1),
        np.stack(positions, axis=1),
        np.stack(omegas, axis=1),
        np.stack(accelerations, axis=1),
    )


def imu_signals(
    robot: RobotModel, base: BaseMotion, trajectory: JointTrajectory, frames: Sequence[str]
) -> Array:
    """Noise-free IMU signals ``[wx wy wz fx fy fz]`` of frames, (T, F, 6).

    Args:
        robot: the model
        base: the base motion
        trajectory: joint values over time
        frames: IMU frame names

    Returns:
        Angular velocity [rad/s] and specific force [m/s²] in each IMU's axes.
    """
    kin = frame_kinematics(robot, base, trajectory, frames)
    return np.concatenate([kin.omega, kin.specific_force()], axis=-1)


def full_state(
    robot: RobotModel, base: BaseMotion, trajectory: JointTrajectory
) -> tuple[Array, Array, Array]:
    """Pinocchio configuration, velocity and acceleration over time, (T, nq) and (T, nv) ×2.

    On a moving base the free-flyer entries are the base pose ``[p, quat xyzw]``, its spatial
    velocity in base axes ``[Rᵀṗ, ω]`` and that velocity's derivative
    ``[Rᵀp̈ - ω × Rᵀṗ, ω̇]``.
    """
    if not robot.moving_base:
        return trajectory.q, trajectory.qd, trajectory.qdd
    from scipy.spatial.transform import Rotation

    Rt = np.swapaxes(base.rotation, -1, -2)
    v_lin = _matvec(Rt, base.velocity)
    a_lin = _matvec(Rt, base.acceleration) - _cross(base.omega, v_lin)
    quat = Rotation.from_matrix(base.rotation).as_quat()
    q = np.hstack([base.position, quat, trajectory.q])
    v = np.hstack([v_lin, base.omega, trajectory.qd])
    a = np.hstack([a_lin, base.omega_dot, trajectory.qdd])
    return q, v, a


def reference_imu_signals(
    robot: RobotModel, base: BaseMotion, trajectory: JointTrajectory, frames: Sequence[str]
) -> Array:
    """The same as :func:`imu_signals`, one Pinocchio call per sample (the slow reference)."""
    model = robot.model
    data = model.createData()
    q, v, a = full_state(robot, base, trajectory)
    ids = [robot.frame_id(name) for name in frames]
    out = np.empty((q.shape[0], len(ids), 6))
    for k in range(q.shape[0]):
        pin.forwardKinematics(model, data, q[k], v[k], a[k])
        for f, frame_id in enumerate(ids):
            R = pin.updateFramePlacement(model, data, frame_id).rotation
            out[k, f, :3] = pin.getFrameVelocity(model, data, frame_id, pin.LOCAL).angular
            acc = pin.getFrameClassicalAcceleration(model, data, frame_id, pin.LOCAL).linear
            out[k, f, 3:] = acc - R.T @ model.gravity.linear
    return out
