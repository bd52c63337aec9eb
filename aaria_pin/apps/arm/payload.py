"""The gripped cylinder's mass on the hand: the payload the arm carries while it is held.

While the cylinder is held, its mass properties are added to the hand's body (the
``hand_roll`` joint's) in Pinocchio: ``model.inertias[hand] += pin.Inertia(m, c, I_c)``, with
``c`` its centre of mass in the hand frame (the grasp point: it is held at half height, on the
grasp axis) and ``I_c`` the solid cylinder's inertia about its centre (axis along the hand's
approach axis z, so the tensor is the same in hand axes). The run engine takes the torques of
the held samples from the loaded model (:class:`aaria_pin.core.run.Payload`, given by the arm's
adapter :class:`aaria_pin.apps.arm.run.PickPlaceRobot`) and those of the rest from the bare one.

**Mount wrench.** On a moving-base model (a free-flyer root,
:func:`aaria_pin.core.model.build_model` with ``moving_base=True``) whose base rests at the world
origin (:meth:`aaria_pin.core.trajectory.BaseMotion.resting`), inverse dynamics gives the joint
torques of the fixed arm and the wrench that the pillar's mount applies to the arm:
``[fx fy fz mx my mz]`` in world axes (the base is not turned) about the pillar's origin on the
floor [N, N·m]. On a fixed-base model the wrench is zero.
"""

from __future__ import annotations

from typing import Any

from aaria_pin.apps.arm.dims import ArmDimensions, grasp_offset
from aaria_pin.apps.arm.task import Cylinder
from aaria_pin.errors import ParameterError

__all__ = ["HAND_JOINT", "payload_inertia", "with_payload"]

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
        raise ParameterError(parameter="joint", value=joint, allowed=f"one of {list(model.names)}")
    loaded = model.copy()
    index = loaded.getJointId(joint)
    loaded.inertias[index] = loaded.inertias[index] + payload
    return loaded
