"""``aaria simulate --motion fourier`` and ``--trajectory FILE``: the run's joint motion.

The flags are checked here; the rules are the library's: a trajectory file's columns are
matched to the robot's and its mimic joints filled by
:func:`~aaria_pin.core.sampled_motion.fit_samples`, the Fourier coefficients of a run with
``--seed S`` come from its ``fourier`` stream (:class:`~aaria_pin.core.seeds.RunSeeds`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import click

if TYPE_CHECKING:
    from aaria_pin.core.record import RunRecord
    from aaria_pin.core.sampled_motion import JointColumns
    from aaria_pin.core.urdf_robot import UrdfRobot


def motion_note(record: RunRecord) -> str:
    """``"motion fourier, "`` for the command's summary line; ``""`` for the joint table's sines."""
    motion = record.metadata.motion
    return "" if motion == "sine" else f"motion {motion}, "


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


def motion_overrides(
    params: dict[str, Any],
    overrides: dict[str, Any],
    stored: RunRecord | None,
    joints: Callable[[], JointColumns],
    fourier: Callable[[float, float, dict[str, Any]], Any],
) -> dict[str, Any]:
    """The producer's ``motion`` (and the time grid of a trajectory file) from the options.

    Args:
        params: the option values of ``aaria simulate``
        overrides: the producer's keyword arguments so far (``duration``, ``rate``, ...)
        stored: the record of ``--from``, if given
        joints: the robot's motion columns (called only for a trajectory file)
        fourier: ``(duration, rate, settings) -> FourierExcitation`` of the robot

    Returns:
        ``motion`` (None: back to the joint table's sines) and, for a trajectory file, its
        ``duration`` and ``rate`` where not given; nothing when the options leave the motion
        as stored (or as the default sines).
    """
    from aaria_pin.core.run import RunSettings

    kind = _check_flags(params)
    if kind is None:
        return {}
    if kind == "sine":
        return {"motion": None}
    grid = RunSettings.from_attributes(stored.attributes if stored is not None else {})
    rate = overrides.get("rate", grid.rate)
    if kind == "fourier":
        from aaria_pin.core.seeds import RunSeeds
        from aaria_pin.core.trajectory import MAX_STREAMED_SAMPLES

        stored_seed = stored.metadata.seed if stored else 0
        seed = overrides.get("seed", getattr(stored_seed, "entropy", stored_seed))
        settings = {
            "base_frequency": params.get("base_frequency"),
            "harmonics": params.get("harmonics"),
            "seed": RunSeeds(int(seed)).sequence("fourier"),
            "max_samples": MAX_STREAMED_SAMPLES,
        }
        return {"motion": fourier(overrides.get("duration", grid.duration), rate, settings)}
    from aaria_pin.core.sampled_motion import GivenSamples, fit_samples
    from aaria_pin.files.trajectory_file import read_trajectory_file

    path = params["trajectory"]
    time, q, qd, qdd, names = read_trajectory_file(path)
    trajectory, duration, file_rate = fit_samples(
        GivenSamples(str(path), time, q, qd, qdd, names),
        joints(),
        rate=overrides.get("rate"),
        duration=overrides.get("duration"),
        fallback_rate=grid.rate,
        smoothing=params.get("smoothing") or 0.0,
    )
    return {"motion": trajectory, "duration": duration, "rate": file_rate}


def dh_motion_overrides(
    params: dict[str, Any], overrides: dict[str, Any], stored: RunRecord | None, dh_table: Any
) -> dict[str, Any]:
    """:func:`motion_overrides` for a DH arm (six module columns)."""
    from aaria_pin.aaria.arm_run import dh_joint_columns
    from aaria_pin.aaria.simulate import dh_fourier_excitation

    def fourier(duration: float, rate: float, settings: dict[str, Any]) -> Any:
        return dh_fourier_excitation(dh_table, duration, rate, **settings)

    return motion_overrides(params, overrides, stored, lambda: dh_joint_columns(dh_table), fourier)


def urdf_motion_overrides(
    params: dict[str, Any],
    overrides: dict[str, Any],
    stored: RunRecord | None,
    load: Callable[[], UrdfRobot],
) -> dict[str, Any]:
    """:func:`motion_overrides` for a URDF robot (``load`` gives it, called only if needed)."""
    from aaria_pin.core.run.urdf_kind import urdf_joint_columns
    from aaria_pin.core.urdf_run import urdf_fourier_excitation

    def fourier(duration: float, rate: float, settings: dict[str, Any]) -> Any:
        return urdf_fourier_excitation(load(), duration, rate, **settings)

    return motion_overrides(params, overrides, stored, lambda: urdf_joint_columns(load()), fourier)
