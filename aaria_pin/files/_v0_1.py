"""What the 0.1.0 run files and data sets share, read the same way by both readers.

0.1.0 stored an Aaria arm's run in the paper's module order: the six modules' joints, 14 IMU
slots (``imu_base``, ``imu_tool``, ``imu_link1_a`` … ``imu_link6_b``) named by the ``senSen``
columns, their mounts (all zeros for an empty module's slots). Neither its Aaria nor its URDF
runs stored ``base_pose``: only the base sines (``senSenB``, ``base_table``). Both readers
(:mod:`aaria_pin.files.runfile._legacy`, :mod:`aaria_pin.files.dataset.legacy`) make today's
record from them with these helpers.
"""

from __future__ import annotations

import re
from collections.abc import Sequence

import numpy as np

from aaria_pin.core.oscillation import base_motion
from aaria_pin.core.record import ImuMount, mounts_from_poses
from aaria_pin.core.se3 import Array

__all__ = [
    "AARIA_JOINTS",
    "AARIA_MODULES",
    "AARIA_ROBOT",
    "AARIA_SLOTS",
    "aaria_mounts",
    "aaria_slot_parent",
    "base_pose_from_table",
]

AARIA_MODULES = 6
AARIA_SLOTS = 2 + 2 * AARIA_MODULES
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


def aaria_mounts(slots: Sequence[str], poses: Array) -> tuple[ImuMount, ...]:
    """The slots as mounts: an all-zero stored pose is an empty module's slot (parent ``""``).

    Args:
        slots: the S slot names
        poses: their stored poses in the parent frame, S × 4 × 4 [m]
    """
    return mounts_from_poses(slots, [aaria_slot_parent(slot) for slot in slots], poses)


def base_pose_from_table(table: Array | None, time: Array) -> Array:
    """``T_world_base`` over time, T × 4 × 4 [m], re-made from a base table as the run made it.

    Args:
        table: the 2 × 4 or 6 × 4 base oscillation table (``senSenB``, ``base_table``); None for
            a fixed base (the identity)
        time: sample times, T [s]

    Raises:
        TableError: a table of the wrong shape or values.
    """
    if table is None:
        return np.broadcast_to(np.eye(4), (np.shape(time)[0], 4, 4)).copy()
    return base_motion(table, time).T_world_base()
