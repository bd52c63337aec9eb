"""Frame kinematics and IMU signals over whole trajectories, as arrays.

:class:`TrajectoryKinematics` walks the Pinocchio model's joint tree once, like Pinocchio's own
forward pass but with every quantity an array over the whole trajectory: each joint frame's
angular velocity, angular acceleration and proper acceleration (classical acceleration minus
gravity), in the joint's own axes. Frames (IMUs, the tool) are read off their parent joint.
It supports revolute and prismatic joints about any axis and a free-flyer root that carries
the prescribed base motion.

:func:`reference_imu_signals` and :func:`reference_frame_poses` compute the same quantities one
sample at a time with Pinocchio's frame algorithms; the tests hold the two paths equal.

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
from aaria_pin.model import RobotModel
from aaria_pin.trajectory import BaseMotion, JointTrajectory

__all__ = [
    "TrajectoryKinematics",
    "frame_poses",
    "full_state",
    "imu_signals",
    "reference_frame_poses",
    "reference_imu_signals",
]

_AXES = {
    "X": np.array([1.0, 0.0, 0.0]),
    "Y": np.array([0.0, 1.0, 0.0]),
    "Z": np.array([0.0, 0.0, 1.0]),
}


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


# Vectors are (3, T) arrays and rotations (3, 3, T) arrays ("structure of arrays"): every
# operation is a few element-wise products of contiguous length-T rows, or a constant 3 × 3
# matrix times a (3, T) block (one BLAS call). Quantities fixed in time are (3, 1) and broadcast.


def _cross(a: Array, b: Array) -> Array:
    out = np.empty((3, max(a.shape[1], b.shape[1])))
    np.subtract(a[1] * b[2], a[2] * b[1], out=out[0])
    np.subtract(a[2] * b[0], a[0] * b[2], out=out[1])
    np.subtract(a[0] * b[1], a[1] * b[0], out=out[2])
    return out


def _transport(f: Array, al: Array, w: Array, r: Array) -> Array:
    """Acceleration of the point r of a body from its origin's: ``f + α × r + ω × (ω × r)``."""
    return f + _cross(al, r) + _cross(w, _cross(w, r))


def _aligned(axis: Array) -> int | None:
    """Index of the coordinate axis that ``axis`` is, or None for any other direction."""
    nonzero = np.flatnonzero(axis)
    if nonzero.size == 1 and axis[nonzero[0]] == 1.0:
        return int(nonzero[0])
    return None


@dataclass(frozen=True)
class _AxisRotation:
    """Rotations by angles q (one per sample) about one fixed unit axis."""

    axis: Array
    cos: Array
    sin: Array

    def inverse_apply(self, v: Array) -> Array:
        """``Rot(q)ᵀ · v`` for vectors v of shape (3, T) or (3, 1)."""
        k, c, s = self.axis, self.cos, self.sin
        index = _aligned(k)
        if index is None:
            k3 = k[:, None]
            return v * c - _cross(k3, v) * s + k3 * (k @ v) * (1.0 - c)
        i, j = (index + 1) % 3, (index + 2) % 3
        out = np.empty((3, c.shape[0]))
        out[index] = v[index]
        out[i] = c * v[i] + s * v[j]
        out[j] = c * v[j] - s * v[i]
        return out

    def right_multiply(self, R: Array) -> Array:
        """``R · Rot(q)`` for rotations R of shape (3, 3, T) or (3, 3, 1)."""
        k, c, s = self.axis, self.cos, self.sin
        index = _aligned(k)
        if index is None:
            K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
            rot = np.eye(3)[:, :, None] + K[:, :, None] * s + (K @ K)[:, :, None] * (1.0 - c)
            return np.einsum("ijt,jkt->ikt", R, rot)
        i, j = (index + 1) % 3, (index + 2) % 3
        out = np.empty((3, 3, c.shape[0]))
        out[:, index] = R[:, index]
        out[:, i] = R[:, i] * c + R[:, j] * s
        out[:, j] = R[:, j] * c - R[:, i] * s
        return out


def _times_constant(R: Array, C: Array) -> Array:
    """``R · C`` for rotations R (3, 3, T) and a constant 3 × 3 matrix C."""
    return np.matmul(R.transpose(0, 2, 1), C).transpose(0, 2, 1)


def _apply(R: Array, v: Array) -> Array:
    """``R · v`` for rotations R (3, 3, T) and vectors v (3, T) or (3, 1)."""
    return np.einsum("ijt,jt->it", R, v)


class TrajectoryKinematics:
    """Kinematics of a model over a whole trajectory, computed once, read for any frames.

    Args:
        robot: the model (a moving base needs ``robot.moving_base``)
        base: the base motion (ignored on a fixed base, which rests at the world origin)
        trajectory: joint values over time, columns in model order
    """

    def __init__(self, robot: RobotModel, base: BaseMotion, trajectory: JointTrajectory) -> None:
        self.robot = robot
        self.base = base
        self.n_samples = trajectory.q.shape[0]
        model = robot.model
        gravity = np.asarray(model.gravity.linear, dtype=float)
        rest = np.zeros((3, 1))
        # per joint, in its own axes: angular velocity, angular acceleration, proper acceleration
        self._w: list[Array] = [rest]
        self._al: list[Array] = [rest]
        self._f: list[Array] = [-gravity[:, None]]
        # per joint, to compose world poses: its motion and the origin's offset in the parent
        self._kind: list[str] = ["universe"]
        self._motion: list[_AxisRotation | None] = [None]
        self._offset: list[Array] = [rest]
        q, qd, qdd = trajectory.q.T, trajectory.qd.T, trajectory.qdd.T
        column = 0
        for j in range(1, model.njoints):
            kind, axis = _joint_kind(model.joints[j])
            self._kind.append(kind)
            if kind == "freeflyer":
                proper = (base.acceleration - gravity)[:, :, None]
                self._w.append(np.ascontiguousarray(base.omega.T))
                self._al.append(np.ascontiguousarray(base.omega_dot.T))
                self._f.append(np.matmul(np.swapaxes(base.rotation, 1, 2), proper)[:, :, 0].T)
                self._motion.append(None)
                self._offset.append(rest)
                continue
            w_p, al_p, f_p = (x[model.parents[j]] for x in (self._w, self._al, self._f))
            placement = model.jointPlacements[j]
            Ct = placement.rotation.T
            r = placement.translation[:, None]
            k3 = axis[:, None]
            qj, qdj, qddj = q[column], qd[column], qdd[column]
            column += 1
            if kind == "revolute":
                motion = _AxisRotation(axis, np.cos(qj), np.sin(qj))
                w_c = motion.inverse_apply(Ct @ w_p)
                self._w.append(w_c + k3 * qdj)
                self._al.append(motion.inverse_apply(Ct @ al_p) + k3 * qddj + _cross(w_c, k3 * qdj))
                self._f.append(motion.inverse_apply(Ct @ _transport(f_p, al_p, w_p, r)))
                self._motion.append(motion)
                self._offset.append(r)
            else:
                e = (placement.rotation @ axis)[:, None]
                d = r + e * qj
                e_qd = e * qdj
                f_o = _transport(f_p, al_p, w_p, d) + 2.0 * _cross(w_p, e_qd) + e * qddj
                self._w.append(Ct @ w_p)
                self._al.append(Ct @ al_p)
                self._f.append(Ct @ f_o)
                self._motion.append(None)
                self._offset.append(d)

    def imu_signals(self, frames: Sequence[str], out: Array | None = None) -> Array:
        """Noise-free IMU signals ``[wx wy wz fx fy fz]`` of frames, (T, F, 6).

        Angular velocity [rad/s] and specific force (acceleration minus gravity) [m/s²], both
        in each frame's own axes.

        Args:
            frames: frame names
            out: where to write them, shape (T, F, 6) (a view into a larger array is fine)

        Returns:
            ``out``, or a new array.
        """
        if out is None:
            out = np.empty((self.n_samples, len(frames), 6))
        block = np.empty((6, self.n_samples))
        for index, name in enumerate(frames):
            frame = self.robot.model.frames[self.robot.frame_id(name)]
            j = frame.parentJoint
            Ct = frame.placement.rotation.T
            r = frame.placement.translation[:, None]
            block[:3] = Ct @ self._w[j]
            block[3:] = Ct @ _transport(self._f[j], self._al[j], self._w[j], r)
            out[:, index, :] = block.T
        return out

    def _world(self, j: int, cache: dict[int, tuple[Array, Array]]) -> tuple[Array, Array]:
        """World rotation (3, 3, T) and position (3, T) of joint j's frame."""
        if j in cache:
            return cache[j]
        if self._kind[j] == "universe":
            cache[j] = (np.eye(3)[:, :, None], np.zeros((3, 1)))
        elif self._kind[j] == "freeflyer":
            cache[j] = (self.base.rotation.transpose(1, 2, 0), self.base.position.T)
        else:
            model = self.robot.model
            R_p, p_p = self._world(model.parents[j], cache)
            R = _times_constant(R_p, model.jointPlacements[j].rotation)
            motion = self._motion[j]
            cache[j] = (
                motion.right_multiply(R) if motion is not None else R,
                p_p + _apply(R_p, self._offset[j]),
            )
        return cache[j]

    def poses(self, frames: Sequence[str]) -> Array:
        """World poses ``T_world_frame`` of frames, (T, F, 4, 4)."""
        cache: dict[int, tuple[Array, Array]] = {}
        out = np.zeros((self.n_samples, len(frames), 4, 4))
        out[:, :, 3, 3] = 1.0
        for index, name in enumerate(frames):
            frame = self.robot.model.frames[self.robot.frame_id(name)]
            R_j, p_j = self._world(frame.parentJoint, cache)
            out[:, index, :3, :3] = _times_constant(R_j, frame.placement.rotation).transpose(
                2, 0, 1
            )
            out[:, index, :3, 3] = (p_j + _apply(R_j, frame.placement.translation[:, None])).T
        return out


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
    return TrajectoryKinematics(robot, base, trajectory).imu_signals(frames)


def frame_poses(
    robot: RobotModel, base: BaseMotion, trajectory: JointTrajectory, frames: Sequence[str]
) -> Array:
    """World poses ``T_world_frame`` of frames over a trajectory, (T, F, 4, 4)."""
    return TrajectoryKinematics(robot, base, trajectory).poses(frames)


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
    n = trajectory.q.shape[0]
    R = base.rotation.transpose(1, 2, 0)  # (3, 3, T)
    q, v, a = (
        np.empty((n, robot.model.nq)),
        np.empty((n, robot.model.nv)),
        np.empty((n, 6 + trajectory.qd.shape[1])),
    )
    q[:, :3] = base.position
    q[:, 3:7] = _quaternion_xyzw(R).T
    q[:, 7:] = trajectory.q
    v_lin = np.einsum("jit,tj->it", R, base.velocity)
    v[:, :3] = v_lin.T
    v[:, 3:6] = base.omega
    v[:, 6:] = trajectory.qd
    omega = np.ascontiguousarray(base.omega.T)
    a[:, :3] = (np.einsum("jit,tj->it", R, base.acceleration) - _cross(omega, v_lin)).T
    a[:, 3:6] = base.omega_dot
    a[:, 6:] = trajectory.qdd
    return q, v, a


def _quaternion_xyzw(R: Array) -> Array:
    """Unit quaternions ``[x, y, z, w]`` (w >= 0) of rotations (3, 3, T), as (4, T).

    Shepperd's method: each sample uses the largest of the four squared components, so the
    square root never meets a small argument.
    """
    trace = R[0, 0] + R[1, 1] + R[2, 2]
    candidates = np.stack(
        [1 + 2 * R[0, 0] - trace, 1 + 2 * R[1, 1] - trace, 1 + 2 * R[2, 2] - trace, 1 + trace]
    )
    best = np.argmax(candidates, axis=0)
    root = np.sqrt(np.take_along_axis(candidates, best[None], axis=0)[0])
    half = 0.5 / root
    quat = np.empty((4, R.shape[2]))
    pairs = {  # off-diagonal sums/differences giving each component times 4·component[best]
        0: (R[1, 0] + R[0, 1], R[0, 2] + R[2, 0], R[2, 1] - R[1, 2]),
        1: (R[1, 0] + R[0, 1], R[2, 1] + R[1, 2], R[0, 2] - R[2, 0]),
        2: (R[0, 2] + R[2, 0], R[2, 1] + R[1, 2], R[1, 0] - R[0, 1]),
        3: (R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]),
    }
    others = {0: (1, 2, 3), 1: (0, 2, 3), 2: (0, 1, 3), 3: (0, 1, 2)}
    for index in range(4):
        mask = best == index
        if not mask.any():
            continue
        quat[index, mask] = 0.5 * root[mask]
        for component, value in zip(others[index], pairs[index], strict=True):
            quat[component, mask] = value[mask] * half[mask]
    quat *= np.where(quat[3] < 0, -1.0, 1.0)
    return quat


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


def reference_frame_poses(
    robot: RobotModel, base: BaseMotion, trajectory: JointTrajectory, frames: Sequence[str]
) -> Array:
    """The same as :func:`frame_poses`, one Pinocchio call per sample (the slow reference)."""
    model = robot.model
    data = model.createData()
    q, _, _ = full_state(robot, base, trajectory)
    ids = [robot.frame_id(name) for name in frames]
    out = np.empty((q.shape[0], len(ids), 4, 4))
    for k in range(q.shape[0]):
        pin.framesForwardKinematics(model, data, q[k])
        for f, frame_id in enumerate(ids):
            out[k, f] = data.oMf[frame_id].homogeneous
    return out
