"""Inverse dynamics over whole trajectories: joint torques and the base-mount wrench.

Torques come from Pinocchio's RNEA over the whole batch (``rneaInParallel``). On a moving base
the free-flyer's six entries of the result are the wrench that the base mount applies to hold
the arm on its motion, in base axes about the base origin; :func:`inverse_dynamics` returns it
in world-aligned axes, still about the base origin.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from aaria_pin.core.kinematics import full_state
from aaria_pin.core.model import RobotModel
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory

__all__ = ["batched_rnea", "inverse_dynamics"]


def batched_rnea(model: pin.Model, q: Array, v: Array, a: Array, threads: int = 1) -> Array:
    """RNEA for every sample of a batch, (T, nv).

    Args:
        model: the Pinocchio model
        q: configurations, (T, nq)
        v: velocities, (T, nv)
        a: accelerations, (T, nv)
        threads: worker threads of Pinocchio's parallel RNEA

    Returns:
        Generalized forces, (T, nv).
    """
    pool = pin.ModelPool(model, max(threads, 1))  # copies the model: cheap (~40 µs), never stale
    # (T, n) C-ordered arrays are (n, T) column-major matrices for Eigen: no copy.
    tau = pin.rneaInParallel(
        max(threads, 1),
        pool,
        np.ascontiguousarray(q).T,
        np.ascontiguousarray(v).T,
        np.ascontiguousarray(a).T,
    )
    return np.asarray(tau).reshape(model.nv, -1).T  # a one-sample batch comes back as a vector


def _split(robot: RobotModel, base: BaseMotion, generalized: Array) -> tuple[Array, Array]:
    n_base = robot.base_nv
    tau = generalized[:, n_base:]
    if not robot.moving_base:
        return tau, np.zeros((generalized.shape[0], 6))
    R = base.rotation
    force = np.matmul(R, generalized[:, 0:3, None])[..., 0]
    moment = np.matmul(R, generalized[:, 3:6, None])[..., 0]
    return tau, np.hstack([force, moment])


def inverse_dynamics(
    robot: RobotModel, base: BaseMotion, trajectory: JointTrajectory, threads: int = 1
) -> tuple[Array, Array]:
    """Joint torques and base wrench over a trajectory.

    Args:
        robot: the model
        base: the prescribed base motion
        trajectory: joint values over time, columns in model order
        threads: worker threads

    Returns:
        ``tau`` (T, n) [N·m or N] and ``base_wrench`` (T, 6) ``[fx fy fz mx my mz]``, world-aligned
        axes, about the base origin [N, N·m] (zeros on a fixed base).
    """
    q, v, a = full_state(robot, base, trajectory)
    return _split(robot, base, batched_rnea(robot.model, q, v, a, threads))
