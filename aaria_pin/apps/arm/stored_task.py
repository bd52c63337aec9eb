"""The pick-and-place task a run record holds, read once from its typed metadata.

The torque report (the held payload) and the viewer (the cylinder's track) both need the arm,
the cylinder, where it was put down and when the hand held it; :func:`stored_task` reads them
from :attr:`~aaria_pin.core.record.RunRecord.metadata` (the task's own attributes are in
:attr:`~aaria_pin.core.run_metadata.RunMetadata.extra`), through the pick-and-place codec of
:mod:`aaria_pin.apps.arm.run`.
"""

from __future__ import annotations

from dataclasses import dataclass

from aaria_pin.apps.arm.dims import ArmDimensions, get_arm_preset
from aaria_pin.apps.arm.task import Cylinder
from aaria_pin.core.record import RunRecord
from aaria_pin.core.run_metadata import RunMetadata
from aaria_pin.errors import AariaError, InputFileError

__all__ = ["PICK_PLACE_KIND", "PICK_PLACE_ROBOTS", "StoredTask", "is_pick_place", "stored_task"]

PICK_PLACE_KIND = "pick-place"
"""The run kind of a pick-and-place run (``RunMetadata.kind``)."""

PICK_PLACE_ROBOTS = ("pick-place-arm", "pick_place_arm")
"""The ``robot`` of a pick-and-place run (this version's, 0.1.0's)."""


@dataclass(frozen=True)
class StoredTask:
    """What a pick-and-place run did.

    Attributes:
        dims: the arm (its preset)
        cylinder: the cylinder and where it stood
        place: where it was put down (x, y) [m]
        held: the interval the hand held it, [start, end) [s]
        payload_joint: the joint whose body carried it
    """

    dims: ArmDimensions
    cylinder: Cylinder
    place: tuple[float, float]
    held: tuple[float, float]
    payload_joint: str


def is_pick_place(metadata: RunMetadata) -> bool:
    """Whether a run's metadata is a pick-and-place run's (its kind, or a 0.1.0 file's robot)."""
    kind_or_robot = metadata.kind == PICK_PLACE_KIND or metadata.robot in PICK_PLACE_ROBOTS
    return kind_or_robot and metadata.extra.get("task", PICK_PLACE_KIND) == PICK_PLACE_KIND


def stored_task(record: RunRecord) -> StoredTask | None:
    """The task of a pick-and-place record (:func:`is_pick_place`), None for another run.

    A pick-and-place record with no ``cylinder`` is another run too.

    Args:
        record: the run record

    Raises:
        InputFileError: a pick-and-place record whose arm, cylinder, place or held interval
            cannot be used (``parameter="record"``).
    """
    from aaria_pin.apps.arm.payload import HAND_JOINT
    from aaria_pin.apps.arm.run import stored_cylinder, stored_preset

    metadata = record.metadata
    extra = metadata.extra
    if not is_pick_place(metadata) or "cylinder" not in extra:
        return None
    try:
        start, end = (float(v) for v in extra["held_interval"])
        task = StoredTask(
            dims=get_arm_preset(stored_preset({**extra, "source": metadata.source})),
            cylinder=stored_cylinder(extra),
            place=(float(extra["place"][0]), float(extra["place"][1])),
            held=(start, end),
            payload_joint=str(extra.get("payload_joint") or HAND_JOINT),
        )
    except (KeyError, TypeError, ValueError, IndexError, AariaError) as exc:
        raise InputFileError(
            f"the run's pick-place attributes cannot be used ({exc})", parameter="record"
        ) from None
    return task
