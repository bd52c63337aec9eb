"""``aaria simulate --motion fourier`` and ``--trajectory FILE``: the run's joint motion.

A DH arm's motion is by module (six columns, those of empty modules zero), a URDF robot's one
column per actuated joint in model order (a mimic joint follows its leader). The Fourier
coefficients of a run with ``--seed S`` are drawn from ``SeedSequence(S, spawn_key=(1,))``
(:data:`FOURIER_STREAM`), a stream apart from the run's noise (``default_rng(S)``).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

if TYPE_CHECKING:
    import numpy as np

    from aaria_pin.core.record import RunRecord
    from aaria_pin.core.urdf_robot import UrdfRobot

FOURIER_STREAM = 1
"""``aaria simulate --motion fourier --seed S`` draws its coefficients from
``SeedSequence(S, spawn_key=(FOURIER_STREAM,))``."""

_UNIFORM = 1e-9
"""Relative spread of a file's time steps within which its rate is taken as ``--rate``."""


def fourier_seed(seed: int) -> np.random.SeedSequence:
    """The seed of a run's Fourier coefficients from the run's ``--seed`` (module docstring)."""
    import numpy as np

    return np.random.SeedSequence(seed, spawn_key=(FOURIER_STREAM,))


def motion_note(record: RunRecord) -> str:
    """``"motion fourier, "`` for the command's summary line; ``""`` for the joint table's sines."""
    motion = record.attributes.get("motion", "sine")
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


def _grid(overrides: dict[str, Any], stored: RunRecord | None) -> tuple[float, float]:
    """The run's duration [s] and rate [Hz]: given, else stored, else the defaults."""
    from aaria_pin.core.trajectory import DEFAULT_DURATION, DEFAULT_RATE

    attributes = stored.attributes if stored is not None else {}
    duration = overrides.get("duration", attributes.get("duration", DEFAULT_DURATION))
    rate = overrides.get("rate", attributes.get("rate", DEFAULT_RATE))
    return float(duration), float(rate)


def motion_overrides(
    params: dict[str, Any],
    overrides: dict[str, Any],
    stored: RunRecord | None,
    joint_names: tuple[str, ...],
    moving: list[int],
    fourier: Callable[[float, float, dict[str, Any]], Any],
    followers: dict[int, tuple[int, float, float]] | None = None,
) -> dict[str, Any]:
    """The producer's ``motion`` (and the time grid of a trajectory file) from the options.

    Args:
        params: the option values of ``aaria simulate``
        overrides: the producer's keyword arguments so far (``duration``, ``rate``, ...)
        stored: the record of ``--from``, if given
        joint_names: the motion's columns (a DH arm's six modules, a URDF robot's joints)
        moving: the columns a file must give (the arm's modules, the joints no mimic)
        fourier: ``(duration, rate, settings) -> FourierExcitation`` of the robot
        followers: mimic joints, column → (leader column, multiplier, offset)

    Returns:
        ``motion`` (None: back to the joint table's sines) and, for a trajectory file, its
        ``duration`` and ``rate`` where not given; nothing when the options leave the motion
        as stored (or as the default sines).

    Raises:
        click.UsageError: options that do not go together.
        InputFileError: a trajectory file that does not fit the robot.
    """
    kind = _check_flags(params)
    if kind is None:
        return {}
    if kind == "sine":
        return {"motion": None}
    if kind == "fourier":
        from aaria_pin.core.trajectory import MAX_STREAMED_SAMPLES

        duration, rate = _grid(overrides, stored)
        seed = overrides.get("seed", stored.attributes.get("seed", 0) if stored else 0)
        settings = {
            "base_frequency": params.get("base_frequency"),
            "harmonics": params.get("harmonics"),
            "seed": fourier_seed(int(seed)),
            "max_samples": MAX_STREAMED_SAMPLES,
        }
        return {"motion": fourier(duration, rate, settings)}
    return _trajectory_overrides(params, overrides, stored, joint_names, moving, followers or {})


def _trajectory_overrides(
    params: dict[str, Any],
    overrides: dict[str, Any],
    stored: RunRecord | None,
    joint_names: tuple[str, ...],
    moving: list[int],
    followers: dict[int, tuple[int, float, float]],
) -> dict[str, Any]:
    """``motion``, duration and rate from ``--trajectory FILE`` (:func:`motion_overrides`)."""
    import numpy as np

    from aaria_pin.core.sampled_motion import trajectory_from_samples
    from aaria_pin.core.trajectory import JointTrajectory, sample_count
    from aaria_pin.errors import InputFileError, ParameterError
    from aaria_pin.files.trajectory_file import read_trajectory_file

    path: Path = params["trajectory"]
    time, q, qd, qdd, names = read_trajectory_file(path)
    columns = _file_columns(path, q.shape[1], names, joint_names, moving)
    result: dict[str, Any] = {}
    if "rate" in overrides:
        rate = float(overrides["rate"])
    else:
        steps = np.diff(time)
        uniform = np.ptp(steps) <= _UNIFORM * np.mean(steps)
        rate = (time.size - 1) / float(time[-1] - time[0]) if uniform else _grid({}, stored)[1]
        result["rate"] = rate
    try:
        given = trajectory_from_samples(
            time, q, qd, qdd, rate=rate, smoothing=params.get("smoothing") or 0.0
        )
    except ParameterError as exc:
        raise InputFileError(f"{path}: {exc}", element=str(path)) from None
    samples = given.q.shape[0]
    if "duration" in overrides:
        wanted = sample_count(float(overrides["duration"]), rate, None)
        if wanted > samples:
            span = float(time[-1] - time[0])
            raise ParameterError(
                parameter="duration",
                value=overrides["duration"],
                allowed=f"at most {span:g} s, the span of {path}",
            )
        samples = wanted
    else:
        result["duration"] = float(time[-1] - time[0])
    full = [np.zeros((samples, len(joint_names))) for _ in range(3)]
    for target, source in zip(full, (given.q, given.qd, given.qdd), strict=True):
        target[:, columns] = source[:samples]
    for column, (leader, multiplier, offset) in followers.items():
        if column not in columns:
            for target in full:
                target[:, column] = multiplier * target[:, leader]
            full[0][:, column] += offset
    result["motion"] = JointTrajectory(given.time[:samples], *full)
    return result


def _file_columns(
    path: Path,
    n_columns: int,
    names: tuple[str, ...] | None,
    joint_names: tuple[str, ...],
    moving: list[int],
) -> list[int]:
    """The motion's column of each column of a trajectory file.

    By name when the file names its joints (every joint of ``moving`` named, no other name);
    else all the motion's columns in order, or those of ``moving`` in order.

    Raises:
        InputFileError: the file's columns do not fit the robot, in one line.
    """
    from aaria_pin.errors import InputFileError

    wanted = ", ".join(joint_names[j] for j in moving)
    if names is not None:
        unknown = [name for name in names if name not in joint_names]
        if unknown:
            allowed = f"the robot's joints ({', '.join(joint_names)})"
            raise InputFileError(
                f"{path}: joint {unknown[0]!r} is not the robot's; allowed: {allowed}",
                allowed=allowed,
                element=str(path),
            )
        columns = [joint_names.index(name) for name in names]
        missing = [joint_names[j] for j in moving if j not in columns]
        if missing:
            raise InputFileError(
                f"{path}: has no column for joint {missing[0]}; allowed: a column for each of "
                f"{wanted}",
                allowed=wanted,
                element=str(path),
            )
        return columns
    if n_columns == len(joint_names):
        return list(range(n_columns))
    if n_columns == len(moving):
        return list(moving)
    counts = sorted({len(joint_names), len(moving)})
    allowed = " or ".join(str(c) for c in counts) + f" joint columns ({wanted})"
    raise InputFileError(
        f"{path}: has {n_columns} joint columns; allowed: {allowed}",
        allowed=allowed,
        element=str(path),
    )


def dh_motion_overrides(
    params: dict[str, Any], overrides: dict[str, Any], stored: RunRecord | None, dh_table: Any
) -> dict[str, Any]:
    """:func:`motion_overrides` for a DH arm (six module columns)."""
    from aaria_pin.aaria.dh import chain_from_aaria
    from aaria_pin.aaria.sensen import JOINT_NAMES
    from aaria_pin.aaria.simulate import dh_fourier_excitation

    if _check_flags(params) is None:
        return {}
    moving = [joint.module - 1 for joint in chain_from_aaria(dh_table).joints]

    def fourier(duration: float, rate: float, settings: dict[str, Any]) -> Any:
        return dh_fourier_excitation(dh_table, duration, rate, **settings)

    return motion_overrides(params, overrides, stored, JOINT_NAMES, moving, fourier)


def urdf_motion_overrides(
    params: dict[str, Any],
    overrides: dict[str, Any],
    stored: RunRecord | None,
    load: Callable[[], UrdfRobot],
) -> dict[str, Any]:
    """:func:`motion_overrides` for a URDF robot (``load`` gives it, called only if needed)."""
    from aaria_pin.core.urdf_run import urdf_fourier_excitation

    if _check_flags(params) is None:
        return {}
    loaded = load()
    from aaria_pin.core.urdf_robot import mimic_followers

    names = tuple(joint.name for joint in loaded.joints)
    moving = [j for j, joint in enumerate(loaded.joints) if joint.mimic is None]
    followers = mimic_followers(loaded.joints)

    def fourier(duration: float, rate: float, settings: dict[str, Any]) -> Any:
        return urdf_fourier_excitation(loaded, duration, rate, **settings)

    return motion_overrides(params, overrides, stored, names, moving, fourier, followers)
