"""``aaria identify --rigid/--joint``: IMUs on rigid bodies and the joints between them.

The robot without encoders: each ``--rigid A B`` pair is located (B's pose and time offset
relative to A, :func:`~aaria_pin.apps.identify.rigid.identify_rigid`), each ``--joint A B``
found (the joint between A's body and B's, its type, axis and point,
:func:`~aaria_pin.apps.identify.rigid_joint.identify_joint`), from one recording's IMU signals
alone. A pair whose fit ends above the noise floor makes the whole result a failure (one line,
the CLI exits 1), never a pose printed as a result.

Example::

    from aaria_pin.apps.identify.bodies import identify_bodies
    from aaria_pin.apps.recordings import open_recorded

    found = identify_bodies(open_recorded("rec.mcap"), pairs=[("imu_a", "imu_b")])
    for line in found.lines:
        print(line)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from aaria_pin.core.recording import RecordedRun

__all__ = ["BodiesFound", "identify_bodies"]


@dataclass(frozen=True)
class BodiesFound:
    """What :func:`identify_bodies` found.

    Attributes:
        report: ``{"pairs": [...], "joints": [...]}``, JSON types
        lines: the report as text lines
        failure: the first pair's failure (one line), or None
    """

    report: dict[str, Any]
    lines: tuple[str, ...]
    failure: str | None


def identify_bodies(
    source: RecordedRun,
    pairs: Sequence[tuple[str, str]] = (),
    joints: Sequence[tuple[str, str]] = (),
) -> BodiesFound:
    """Locate IMU pairs on one body each, and the joints between IMUs' bodies.

    Args:
        source: the recording (its IMU streams, each at its own time stamps)
        pairs: (A, B): B located relative to A, both on one rigid body
        joints: (A, B): the joint between A's body and B's (one clock)

    Returns:
        The fits' report, text and failure.

    Raises:
        ParameterError: an IMU not in the recording, too little overlap, no motion.
    """
    from aaria_pin.apps.identify.rigid import identify_rigid
    from aaria_pin.apps.identify.rigid_joint import identify_joint

    pair_fits = [identify_rigid(source, a, b) for a, b in pairs]
    joint_fits = [identify_joint(source, a, b) for a, b in joints]
    lines = [line for fit in pair_fits for line in fit.lines()]
    lines += [line for fit in joint_fits for line in fit.lines()]
    failures = [f"{fit.imu_a} -> {fit.imu_b}: {fit.failure}" for fit in pair_fits if fit.failure]
    report = {
        "pairs": [fit.to_json() for fit in pair_fits],
        "joints": [fit.to_json() for fit in joint_fits],
    }
    return BodiesFound(report, tuple(lines), failures[0] if failures else None)
