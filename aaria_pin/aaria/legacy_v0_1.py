"""The Aaria arm as aaria_pin 0.1.0 stored it, registered with the files layer's 0.1.0 readers.

0.1.0 stored an Aaria arm's run in the paper's module order: the six modules' joints
(``joint1`` … ``joint6``), 14 IMU slots (``imu_base``, ``imu_tool``, ``imu_link1_a`` …
``imu_link6_b``) named by the ``senSen`` columns, their mounts (all zeros for an empty
module's slots), and no robot name. Importing this module registers :data:`AARIA_V0_1` with
:func:`aaria_pin.files.legacy_arm.register_legacy_arm` (``import aaria_pin`` does).
"""

from __future__ import annotations

import re

from aaria_pin.files.legacy_arm import LegacyArm, register_legacy_arm

__all__ = ["AARIA_JOINTS", "AARIA_MODULES", "AARIA_ROBOT", "AARIA_V0_1", "aaria_slot_parent"]

AARIA_MODULES = 6
"""Modules of an Aaria arm (one joint each)."""
AARIA_JOINTS = tuple(f"joint{module}" for module in range(1, AARIA_MODULES + 1))
"""The joints of an Aaria run's record, one per module."""
AARIA_ROBOT = "aaria-arm"
"""The ``robot`` of a 0.1.0 Aaria run (0.1.0 did not store a preset's name; a 0.2 run whose
table is not a named preset records the same)."""

_LINK_SLOT = re.compile(r"imu_link([1-9][0-9]*)_[ab]")
_OTHER_SLOTS = {"imu_base": "base", "imu_tool": "tool_tip"}


def aaria_slot_parent(slot: str) -> str:
    """The frame a 0.1.0 IMU slot is mounted on (the 0.1.0 README's slot table; ``""``: none)."""
    link = _LINK_SLOT.fullmatch(slot)
    return f"link{link[1]}" if link else _OTHER_SLOTS.get(slot, "")


AARIA_V0_1 = LegacyArm(
    robot=AARIA_ROBOT,
    joints=AARIA_JOINTS,
    slots=2 + 2 * AARIA_MODULES,  # base, tool, two a module
    slot_parent=aaria_slot_parent,
)
"""The Aaria arm of 0.1.0's DH run files and data sets."""

register_legacy_arm(AARIA_V0_1)
