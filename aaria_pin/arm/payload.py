"""The gripped cylinder's mass on the hand, and joint torques with and without it.

While the cylinder is held, its mass properties are added to the hand's body (the
``hand_roll`` joint's) in Pinocchio: ``model.inertias[hand] += pin.Inertia(m, c, I_c)``, with
``c`` its centre of mass in the hand frame (the grasp point: it is held at half height, on the
grasp axis) and ``I_c`` the solid cylinder's inertia about its centre (axis along the hand's
approach axis z, so the tensor is the same in hand axes). Torques come from RNEA
(:func:`aaria_pin.dynamics.batched_rnea`) over whole intervals: the whole path on the bare
model, the held interval again on the loaded one.

**Mount wrench.** Built on a free-flyer root held still at the world origin (configuration
``[0 0 0, 0 0 0 1, q]``, zero base velocity and acceleration), the same RNEA gives the joint
torques of the fixed arm and, in its first six entries, the wrench that the pillar's mount
applies to the arm (:func:`still_base_state`): ``[fx fy fz mx my mz]`` in world axes (the
base is not turned) about the pillar's origin on the floor [N, N·m].
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin._se3 import Array
from aaria_pin.arm.dims import ArmDimensions, grasp_offset
from aaria_pin.arm.task import Cylinder
from aaria_pin.dynamics import batched_rnea
from aaria_pin.errors import ParameterError

__all__ = ["HAND_JOINT", "payload_inertia", "still_base_state", "task_torques", "with_payload"]

HAND_JOINT = "hand_roll"
"""The joint whose body carries the gripped cylinder."""


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
        raise ParameterError(f"joint {joint!r} is not in the model; allowed: {list(model.names)}")
    loaded = model.copy()
    index = loaded.getJointId(joint)
    loaded.inertias[index] = loaded.inertias[index] + payload
    return loaded


def task_torques(
    model: Any, payload: Any, q: Array, qd: Array, qdd: Array, held: ArrayLike, threads: int = 1
) -> tuple[Array, Array]:
    """Joint torques along a path, with the payload on the hand where ``held``.

    Args:
        model: the bare arm's Pinocchio model
        payload: the held object's ``pinocchio.Inertia`` in the hand joint's frame
        q: joint values (T, nq)
        qd: joint velocities (T, nv)
        qdd: joint accelerations (T, nv)
        held: (T,) True where the object is in the hand
        threads: RNEA worker threads

    Returns:
        ``tau`` with the payload where held, and ``tau_free`` without it anywhere (T, nv)
        [N·m or N].
    """
    held = np.asarray(held, dtype=bool)
    if held.shape != (np.shape(q)[0],):
        raise ParameterError(f"held mask of shape {held.shape}; allowed: ({np.shape(q)[0]},)")
    tau_free = batched_rnea(model, q, qd, qdd, threads)
    tau = tau_free.copy()
    if np.any(held):
        loaded = with_payload(model, payload)
        tau[held] = batched_rnea(loaded, q[held], qd[held], qdd[held], threads)
    return tau, tau_free


def still_base_state(model: Any, q: Array, qd: Array, qdd: Array) -> tuple[Array, Array, Array]:
    """The state of a free-flyer model whose root is held still at the world origin.

    Args:
        model: the arm's Pinocchio model on a free-flyer root (nq = 7 + n, nv = 6 + n)
        q: joint values (T, n)
        qd: joint velocities (T, n)
        qdd: joint accelerations (T, n)

    Returns:
        Configurations (T, 7 + n), velocities and accelerations (T, 6 + n).

    Raises:
        ParameterError: a model that is not of that shape.
    """
    q = np.asarray(q, dtype=float)
    n = q.shape[1]
    if model.nq != 7 + n or model.nv != 6 + n:
        raise ParameterError(
            f"model of nq = {model.nq}, nv = {model.nv}; allowed: a free-flyer root and"
            f" {n} joints (nq = {7 + n}, nv = {6 + n})"
        )
    rest = np.zeros((q.shape[0], 7))
    rest[:, 6] = 1.0  # identity quaternion (x, y, z, w)
    still = np.zeros((q.shape[0], 6))
    return (
        np.hstack([rest, q]),
        np.hstack([still, np.asarray(qd, dtype=float)]),
        np.hstack([still, np.asarray(qdd, dtype=float)]),
    )
