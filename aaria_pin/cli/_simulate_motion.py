"""``aaria simulate``'s summary line of a written run.

The motion flags are the library's :class:`~aaria_pin.aaria.run_motion.MotionChoice` options
(``MotionChoice.from_options``), checked and made there (:mod:`aaria_pin.aaria.run_motion`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from pathlib import Path

    from aaria_pin.core.record import RunRecord


def summary(output: Path, record: RunRecord, samples: int, peak: float, robot: bool) -> str:
    """The command's summary line of a written run (``robot``: name its robot, joints, IMUs)."""
    meta = record.metadata
    what = f"{meta.robot}, {len(record.joint_names)} joints, {len(record.imu_mounts)} IMUs, "
    motion = "" if meta.motion == "sine" else f"motion {meta.motion}, "
    return (
        f"wrote {output}: {what if robot else ''}{samples} samples at {meta.rate:g} Hz, {motion}"
        f"noise {'on' if meta.noise else 'off'}, "
        f"peak |tau| {peak:.4g} (N*m, N for a prismatic joint)"
    )
