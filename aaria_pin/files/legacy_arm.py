"""The arm of aaria_pin 0.1.0's DH run files and data sets: what those files do not store.

0.1.0 stored a DH arm's run in its module order: one joint per module, the IMU slots named by
the ``senSen`` columns and their mounts, the base sines (``senSenB``) but no ``base_pose``, no
robot name and no IMU parent. The files layer knows no DH arm, so the layer that does (the Aaria
layer, :mod:`aaria_pin.aaria.legacy_v0_1`) registers it here as a :class:`LegacyArm`; both
0.1.0 readers (:mod:`aaria_pin.files.runfile._legacy_runs`,
:mod:`aaria_pin.files.dataset.legacy_datasets`) make today's record with it.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from aaria_pin.errors import InputFileError

if TYPE_CHECKING:
    from aaria_pin.core.record import ImuMount
    from aaria_pin.core.se3 import Array

__all__ = ["LegacyArm", "base_pose_from_table", "legacy_arm", "register_legacy_arm"]


@dataclass(frozen=True)
class LegacyArm:
    """The DH arm of a 0.1.0 run file or data set.

    Attributes:
        robot: the ``robot`` attribute its records get (0.1.0 stored none)
        joints: its joint names, one per module, in module order
        slots: how many IMU slots a run stores (the ``senSen`` columns name them)
        slot_parent: the frame a slot is mounted on, by slot name (``""``: none)
    """

    robot: str
    joints: tuple[str, ...]
    slots: int
    slot_parent: Callable[[str], str]

    @property
    def modules(self) -> int:
        """How many modules (joints) the arm has."""
        return len(self.joints)

    def mounts(self, slots: Sequence[str], poses: Array) -> tuple[ImuMount, ...]:
        """The slots as mounts: an all-zero stored pose is an empty module's slot (parent ``""``).

        Args:
            slots: the S slot names
            poses: their stored poses in the parent frame, S × 4 × 4 [m]
        """
        from aaria_pin.core.record import mounts_from_poses

        return mounts_from_poses(slots, [self.slot_parent(slot) for slot in slots], poses)


_REGISTERED: list[LegacyArm] = []


def register_legacy_arm(arm: LegacyArm) -> None:
    """Register the arm the 0.1.0 DH files hold (the last registered is used)."""
    _REGISTERED.append(arm)


def legacy_arm(file: Path) -> LegacyArm:
    """The registered 0.1.0 DH arm.

    Raises:
        InputFileError: none is registered (``parameter="file"``: ``file`` cannot be read).
    """
    if not _REGISTERED:
        raise InputFileError(
            f"{file}: an aaria_pin 0.1.0 DH file, whose arm no layer registered; allowed: "
            "import aaria_pin (it registers the Aaria arm)",
            parameter="file",
            value=str(file),
        )
    return _REGISTERED[-1]


def base_pose_from_table(table: Array | None, time: Array) -> Array:
    """``T_world_base`` over time, T × 4 × 4 [m], re-made from a base table as the run made it.

    Args:
        table: the 2 × 4 or 6 × 4 base oscillation table (``senSenB``, ``base_table``); None for
            a fixed base (the identity)
        time: sample times, T [s]

    Raises:
        TableError: a table of the wrong shape or values.
    """
    import numpy as np

    from aaria_pin.core.oscillation import base_motion

    if table is None:
        return np.broadcast_to(np.eye(4), (np.shape(time)[0], 4, 4)).copy()
    return base_motion(table, time).T_world_base()
