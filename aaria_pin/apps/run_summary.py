"""The summary line of a written run, as ``aaria simulate`` prints it.

``wrote run.h5: ur5, 6 joints, 14 IMUs, 1001 samples at 100 Hz, noise on, peak |tau| 58.99
(N*m, N for a prismatic joint)``; a closed-loop run adds its drive and how well it tracked its
reference: the RMS over every joint and sample of ``q - q_reference`` (:func:`tracking_rms`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from pathlib import Path

    from aaria_pin.core.record import RunRecord

__all__ = ["run_summary", "tracking_rms"]


def tracking_rms(record: RunRecord) -> float | None:
    """RMS of ``q - q_reference`` over every joint and sample [rad or m] (None: no reference)."""
    reference = record.tables.get("q_reference")
    if reference is None:
        return None
    return float(np.sqrt(np.mean((np.asarray(record.q) - np.asarray(reference)) ** 2)))


def run_summary(output: Path, record: RunRecord, samples: int, peak: float, robot: bool) -> str:
    """The summary line of a written run (``robot``: name its robot, joints, IMUs).

    Args:
        output: the file written
        record: the run (its last piece: the tables and attributes)
        samples: the run's samples
        peak: the run's peak |tau| [N·m or N]
        robot: name the robot, its joints and IMUs
    """
    meta = record.metadata
    what = f"{meta.robot}, {len(record.joint_names)} joints, {len(record.imu_mounts)} IMUs, "
    motion = "" if meta.motion == "sine" else f"motion {meta.motion}, "
    rms = tracking_rms(record)
    if rms is not None:
        motion += f"drive {meta.drive}, tracking RMS {rms:.3g} (rad or m), "
    return (
        f"wrote {output}: {what if robot else ''}{samples} samples at {meta.rate:g} Hz, {motion}"
        f"noise {'on' if meta.noise else 'off'}, "
        f"peak |tau| {peak:.4g} (N*m, N for a prismatic joint)"
    )
