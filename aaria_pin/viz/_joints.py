"""The kind of a Pinocchio joint type, by its exact short name (no prefix matching)."""

from __future__ import annotations

__all__ = ["PRISMATIC_JOINTS", "REVOLUTE_JOINTS", "joint_type_kind"]

PRISMATIC_JOINTS = frozenset(
    {"JointModelPX", "JointModelPY", "JointModelPZ", "JointModelPrismaticUnaligned"}
)
"""Short names of Pinocchio's one-axis prismatic joints (``JointModelPlanar`` is not one)."""

REVOLUTE_JOINTS = frozenset(
    {
        "JointModelRX",
        "JointModelRY",
        "JointModelRZ",
        "JointModelRevoluteUnaligned",
        "JointModelRUBX",
        "JointModelRUBY",
        "JointModelRUBZ",
        "JointModelRevoluteUnboundedUnaligned",
    }
)
"""Short names of Pinocchio's one-axis revolute joints, bounded or not (URDF continuous)."""


def joint_type_kind(shortname: str) -> str | None:
    """``"prismatic"``, ``"revolute"`` or None (any other joint type) for a joint's short name.

    Args:
        shortname: ``joint.shortname()`` of a Pinocchio joint model, e.g. ``"JointModelRUBZ"``
    """
    if shortname in PRISMATIC_JOINTS:
        return "prismatic"
    if shortname in REVOLUTE_JOINTS:
        return "revolute"
    return None
