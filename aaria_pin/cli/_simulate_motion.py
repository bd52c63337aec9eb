"""``aaria simulate --motion fourier`` and ``--trajectory FILE``: the run's joint motion.

The flags are checked here; the motion is made by the library
(:mod:`aaria_pin.aaria.run_motion`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import click

if TYPE_CHECKING:
    from pathlib import Path

    from aaria_pin.aaria.run_motion import MotionChoice
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


def _check_flags(params: dict[str, Any]) -> str | None:
    """The motion asked for (``fourier``, ``trajectory``, ``sine`` or None: as stored/default).

    Raises:
        click.UsageError: options that do not go together.
    """
    motion, trajectory = params.get("motion"), params.get("trajectory")
    if trajectory is not None and motion is not None:
        raise click.UsageError("--trajectory FILE is the motion; drop --motion")
    if trajectory is not None and params.get("drive") == "torque":
        raise click.UsageError("--trajectory is a motion; not allowed with --drive torque")
    if motion != "fourier":
        for key, flag in (("harmonics", "--harmonics"), ("base_frequency", "--base-frequency")):
            if params.get(key) is not None:
                raise click.UsageError(f"{flag} is for --motion fourier")
    if trajectory is None and params.get("smoothing") is not None:
        raise click.UsageError("--smoothing is for --trajectory FILE")
    if params.get("joints_file") is not None:
        if motion == "fourier" or trajectory is not None:
            raise click.UsageError(
                "--joints is the sines' table; not allowed with --motion fourier or --trajectory"
            )
        return "sine"  # the table given is followed (also by a run re-made --from)
    return "trajectory" if trajectory is not None else motion


def motion_choice(params: dict[str, Any]) -> MotionChoice:
    """The motion the options ask for (:class:`~aaria_pin.aaria.run_motion.MotionChoice`).

    Raises:
        click.UsageError: options that do not go together.
    """
    from aaria_pin.aaria.run_motion import MotionChoice

    named = {key: params.get(key) for key in ("harmonics", "base_frequency", "trajectory")}
    return MotionChoice(_check_flags(params), **named, smoothing=params.get("smoothing") or 0.0)
