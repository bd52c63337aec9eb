"""The gripped cylinder's mass on the hand, and joint torques with and without it.

While the cylinder is held, its mass properties are added to the hand's body (the
``hand_roll`` joint's) in Pinocchio: ``model.inertias[hand] += pin.Inertia(m, c, I_c)``, with
``c`` its centre of mass in the hand frame (the grasp point: it is held at half height, on the
grasp axis) and ``I_c`` the solid cylinder's inertia about its centre (axis along the hand's
approach axis z, so the tensor is the same in hand axes). Torques come from
:func:`aaria_pin.core.dynamics.inverse_dynamics` over whole intervals: the whole path on the bare
model, the held interval again on the loaded one.

**Mount wrench.** On a moving-base model (a free-flyer root,
:func:`aaria_pin.core.model.build_model`
with ``moving_base=True``) whose base rests at the world origin
(:meth:`aaria_pin.core.trajectory.BaseMotion.resting`), the same inverse dynamics gives the joint
torques of the fixed arm and the wrench that the pillar's mount applies to the arm:
``[fx fy fz mx my mz]`` in world axes (the base is not turned) about the pillar's origin on the
floor [N, N·m]. On a fixed-base model the wrench is zero.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.apps.arm.dims import ArmDimensions, grasp_offset
from aaria_pin.apps.arm.task import Cylinder
from aaria_pin.core.model import RobotModel
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import JointTrajectory
from aaria_pin.errors import ParameterError

__all__ = ["HAND_JOINT", "TaskTorques", "payload_inertia", "task_torques", "with_payload"]

HAND_JOINT = "hand_roll"
"""The joint whose body carries the gripped cylinder."""

_FIELDS = ("time", "q", "qd", "qdd")  # of a JointTrajectory


class TaskTorques(NamedTuple):
    """Joint torques and mount wrenches along a path (T rows each).

    Attributes:
        tau: joint torques with the payload where held (T, n) [N·m or N]
        tau_free: the same without the payload anywhere (T, n)
        base_wrench: the mount's wrench with the payload where held (T, 6) [N, N·m]
        base_wrench_free: the same without the payload (T, 6)
    """

    tau: Array
    tau_free: Array
    base_wrench: Array
    base_wrench_free: Array


def payload_inertia(dims: ArmDimensions, cylinder: Cylinder) -> Any:
    """The held cylinder as a ``pinocchio.Inertia`` in the hand joint's frame."""
    import pinocchio as pin

    inertia = cylinder.inertia()
    com = grasp_offset(dims, cylinder.radius, cylinder.height)[:3, 3]
    return pin.Inertia(inertia.mass, com, inertia.inertia_com)


def with_payload(model: Any, payload: Any, joint: str = HAND_JOINT) -> Any:
    """A copy of ``model`` with ``payload`` (a ``pinocchio.Inertia``) added to a joint's body.

    Raises:
        ParameterError: no joint of that name.
    """
    if not model.existJointName(joint):
        raise ParameterError(parameter="joint", value=joint, allowed=f"one of {list(model.names)}")
    loaded = model.copy()
    index = loaded.getJointId(joint)
    loaded.inertias[index] = loaded.inertias[index] + payload
    return loaded


def task_torques(
    robot: RobotModel,
    payload: Any,
    trajectory: JointTrajectory,
    held: ArrayLike,
    threads: int = 1,
) -> TaskTorques:
    """Joint torques and the mount's wrench along a path, with the payload on the hand where held.

    Args:
        robot: the bare arm, its base resting at the world origin (on a moving base the mount's
            wrench is computed, else it is zero)
        payload: the held object's ``pinocchio.Inertia`` in the hand joint's frame
        trajectory: the joint path (T samples)
        held: (T,) True where the object is in the hand
        threads: RNEA worker threads

    Returns:
        The torques and wrenches.

    Raises:
        ParameterError: a held mask that is not one flag per sample.
    """
    from aaria_pin.core.dynamics import inverse_dynamics
    from aaria_pin.core.trajectory import BaseMotion

    held = np.asarray(held, dtype=bool)
    n = np.shape(trajectory.q)[0]
    if held.shape != (n,):
        raise ParameterError(parameter="held", value=held.shape, allowed=f"({n},)", element="shape")
    tau_free, wrench_free = inverse_dynamics(robot, BaseMotion.resting(n), trajectory, threads)
    tau, wrench = tau_free.copy(), wrench_free.copy()
    if np.any(held):
        loaded = replace(robot, model=with_payload(robot.model, payload))
        part = JointTrajectory(
            *(np.ascontiguousarray(getattr(trajectory, name)[held]) for name in _FIELDS)
        )
        tau[held], wrench[held] = inverse_dynamics(
            loaded, BaseMotion.resting(int(held.sum())), part, threads
        )
    return TaskTorques(tau, tau_free, wrench, wrench_free)
