"""Test oracles: the library's whole-trajectory passes written one Pinocchio call per sample.

Slow references for the tests (and the benchmarks' per-sample timings); the library ships only
the batched passes they check: ``core.kinematics.imu_signals``/``frame_poses``,
``core.dynamics.inverse_dynamics`` and ``apps.identify.torque_regressor``.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pinocchio as pin

from aaria_pin.core.kinematics import full_state
from aaria_pin.core.model import RobotModel
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory


def _frame_ids(robot: RobotModel, frames: Sequence[str]) -> list[int]:
    return [robot.frame_id(name) for name in frames]


def reference_imu_signals(
    robot: RobotModel, base: BaseMotion, trajectory: JointTrajectory, frames: Sequence[str]
) -> np.ndarray:
    """IMU signals ``[w f]`` of frames, (T, F, 6), by Pinocchio's frame algorithms per sample."""
    model, data, ids = robot.model, robot.model.createData(), _frame_ids(robot, frames)
    q, v, a = full_state(robot, base, trajectory)
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
) -> np.ndarray:
    """World poses ``T_world_frame`` of frames, (T, F, 4, 4), one Pinocchio call per sample."""
    model, data, ids = robot.model, robot.model.createData(), _frame_ids(robot, frames)
    q = full_state(robot, base, trajectory)[0]
    out = np.empty((q.shape[0], len(ids), 4, 4))
    for k in range(q.shape[0]):
        pin.framesForwardKinematics(model, data, q[k])
        for f, frame_id in enumerate(ids):
            out[k, f] = data.oMf[frame_id].homogeneous
    return out


def reference_inverse_dynamics(
    robot: RobotModel, base: BaseMotion, trajectory: JointTrajectory
) -> tuple[np.ndarray, np.ndarray]:
    """Joint torques (T, n) and base wrench (T, 6), one ``pinocchio.rnea`` call per sample.

    The free flyer's six entries (base axes) are turned into world-aligned axes, about the base
    origin; zeros on a fixed base.
    """
    data = robot.model.createData()
    q, v, a = full_state(robot, base, trajectory)
    generalized = np.array([pin.rnea(robot.model, data, *x) for x in zip(q, v, a, strict=True)])
    tau = generalized[:, robot.base_nv :]
    if not robot.moving_base:
        return tau, np.zeros((q.shape[0], 6))
    wrench = np.empty((q.shape[0], 6))
    for k, R_world_base in enumerate(base.rotation):
        wrench[k, :3] = R_world_base @ generalized[k, :3]
        wrench[k, 3:] = R_world_base @ generalized[k, 3:6]
    return tau, wrench


def reference_torque_regressor(
    robot: RobotModel, base: BaseMotion, trajectory: JointTrajectory
) -> np.ndarray:
    """The joint torque regressor (T, nv, 10·B), one ``computeJointTorqueRegressor`` per sample."""
    q, v, a = full_state(robot, base, trajectory)
    data = robot.model.createData()
    return np.stack(
        [
            np.array(pin.computeJointTorqueRegressor(robot.model, data, *x))
            for x in zip(q, v, a, strict=True)
        ]
    )
