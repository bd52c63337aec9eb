"""The run pipeline every robot shares: IMUs, tool pose, torques and base wrench over a run.

A producer (an Aaria DH arm, a URDF robot, the wrist) builds its model, its joint trajectory
and its base motion, then calls :func:`simulate_series`: IMU kinematics over the whole time grid
in one compiled pass (:func:`~aaria_pin.core.kinematics.trajectory_signals`), ADIS16485-like
noise if asked (:func:`~aaria_pin.core.imu_noise.add_imu_noise`), torques and the base wrench
by Pinocchio's batched RNEA (:func:`~aaria_pin.core.dynamics.inverse_dynamics`). The result goes
into the one :class:`~aaria_pin.core.record.RunRecord` with :func:`sampling_attributes`.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from aaria_pin.core.imu_noise import ADIS16485, ImuNoiseModel, ImuNoiseStream, noise_attributes
from aaria_pin.core.model import GRAVITY, RobotModel
from aaria_pin.core.record import SERIES, RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.core.seeds import seed_attributes, stored_seed
from aaria_pin.core.trajectory import DEFAULT_DURATION, DEFAULT_RATE, BaseMotion, JointTrajectory

__all__ = [
    "CHUNK_SAMPLES",
    "DEFAULT_DURATION",
    "DEFAULT_RATE",
    "UNITS",
    "RunSeries",
    "chunk_bounds",
    "join_chunks",
    "noise_stream",
    "run_length",
    "sampling_attributes",
    "simulate_series",
    "stored_sampling",
]

UNITS = {
    "time": "s",
    "q": "rad (revolute) or m (prismatic)",
    "angular_velocity": "rad/s",
    "specific_force": "m/s^2",
    "tau": "N*m (revolute) or N (prismatic)",
    "base_wrench": "N (force), N*m (moment about the base origin), world-aligned axes",
    "length": "m",
}
"""The ``units`` attribute of a run (the units of each quantity)."""

CHUNK_SAMPLES = 20_000
"""Samples per piece of a long run computed in time chunks (:func:`chunk_bounds`).

While a piece is computed the process holds about 4.6 kB per sample of it (5.7 kB with noise:
the record, the IMU kinematics, the noise, RNEA's work arrays) on top of about 235 MB of
imports and model (280 MB with noise when these figures were taken: scipy.signal, since
dropped). Measured on ``aaria-fig2`` at 100 kHz, 1 M samples (2 cores,
``benchmarks/bench_memory.py``'s child), peak RSS and wall time by piece length:

========= ================== ==================
piece     noise off          noise on
========= ================== ==================
10,000    283 MB, 4.0 s      344 MB, 10.3 s
20,000    328 MB, 4.8 s      402 MB, 9.9 s
50,000    465 MB, 4.9 s      570 MB, 9.3 s
100,000   681 MB, 5.7 s      979 MB, 9.6 s
========= ================== ==================

20,000 keeps a run of any length near 400 MB, well inside the 600 MB goal, at a speed within
the spread of these figures (the per-piece work outside the arrays is a few milliseconds);
50,000 would brush the goal with noise on. A run of at most this many samples is one piece:
computed and written whole, as before. With this length a 2 M-sample run peaks at 317 MB
(noise off) and 354 MB (noise on; 359 MB to a ``.mat`` v7.3), 3 to 15 MB above a
200,000-sample run (``benchmarks/bench_memory.py``; each piece makes its own sample times and
the noise's bias knots are drawn piece by piece, so nothing is held for the whole run).
"""


def chunk_bounds(samples: int, chunk: int | None = CHUNK_SAMPLES) -> list[tuple[int, int]]:
    """The pieces ``[(start, stop), ...]`` of a run of ``samples`` in chunks of ``chunk``.

    Args:
        samples: T, the run's number of samples
        chunk: samples per piece (the last may be shorter); None: one piece

    Raises:
        ParameterError: ``chunk`` < 1.
    """
    from aaria_pin.errors import ParameterError

    if chunk is None or samples <= chunk:
        return [(0, samples)]
    if chunk < 1:
        raise ParameterError(
            f"chunk is {chunk!r} samples; allowed: >= 1",
            parameter="chunk",
            value=chunk,
            allowed=">= 1",
        )
    return [(start, min(start + chunk, samples)) for start in range(0, samples, chunk)]


def run_length(record: RunRecord) -> int:
    """T, the samples of the whole run a record (or a piece of it) belongs to.

    From its ``duration`` [s] and ``rate`` [Hz] attributes (:func:`sampling_attributes`), as
    :func:`~aaria_pin.core.trajectory.sample_count` counts them; the record's own length if
    it has none.
    """
    from aaria_pin.core.trajectory import sample_count

    attributes = record.attributes
    if "duration" not in attributes or "rate" not in attributes:
        return record.n_samples
    return sample_count(float(attributes["duration"]), float(attributes["rate"]), None)


def noise_stream(
    samples: int,
    n_imu: int,
    rate: float,
    seed: int | np.random.SeedSequence,
    noise: bool,
    noise_model: ImuNoiseModel,
    pieces: int,
) -> ImuNoiseStream | None:
    """The noise of a run computed in ``pieces`` (None if one piece, no noise or no IMU)."""
    if pieces <= 1 or not noise or n_imu < 1:
        return None
    return ImuNoiseStream(samples, n_imu, rate, np.random.default_rng(seed), noise_model)


def join_chunks(chunks: Iterable[RunRecord]) -> RunRecord:
    """One record of a run from its pieces in time order (the last piece's other fields).

    A single piece is returned as it is; the attributes, tables, views and names come from
    the last piece, whose attributes cover the whole run.
    """
    from dataclasses import replace

    pieces = list(chunks)
    if len(pieces) == 1:
        return pieces[0]
    series: dict[str, Any] = {
        name: np.concatenate([getattr(p, name) for p in pieces]) for name in SERIES
    }
    return replace(pieces[-1], **series)


def sampling_attributes(
    rate: float,
    duration: float,
    seed: int | np.random.SeedSequence,
    noise: bool,
    noise_model: ImuNoiseModel,
) -> dict[str, Any]:
    """The attributes every run records: rate, duration, seed, noise, gravity, units.

    Args:
        rate: sample rate [Hz]
        duration: run length [s]
        seed: seed of the IMU noise (or a data set run's ``SeedSequence``)
        noise: whether the IMU signals carry noise
        noise_model: the IMU noise parameters
    """
    return {
        "rate": float(rate),
        "duration": float(duration),
        **seed_attributes(seed),
        "noise": bool(noise),
        "noise_parameters": noise_attributes(noise_model),
        "gravity": GRAVITY.tolist(),
        "units": UNITS,
    }


def stored_sampling(attributes: dict[str, Any]) -> dict[str, Any]:
    """The ``duration`` [s], ``rate`` [Hz], ``seed`` and ``noise`` a record's attributes hold.

    The inverse of :func:`sampling_attributes`, as keyword arguments of a producer, for
    re-making a run from its record (defaults where an attribute is missing).
    """
    return {
        "duration": _stored_number(attributes, "duration", DEFAULT_DURATION, "s"),
        "rate": _stored_number(attributes, "rate", DEFAULT_RATE, "Hz"),
        "seed": stored_seed(attributes),
        "noise": bool(attributes.get("noise", True)),
    }


def _stored_number(attributes: dict[str, Any], name: str, default: float, unit: str) -> float:
    """A stored positive number, or one line naming the attribute (a damaged or edited file)."""
    from aaria_pin.errors import InputFileError

    value = attributes.get(name, default)
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = math.nan
    if not (math.isfinite(number) and number > 0):
        raise InputFileError(
            f"the run's attribute {name!r} is {value!r}; allowed: a positive number of {unit}"
        )
    return number


@dataclass(frozen=True)
class RunSeries:
    """The computed series of a run (the record's arrays beyond the joint motion).

    Attributes:
        imu: IMU signals ``[wx wy wz fx fy fz]``, T × S × 6 [rad/s, m/s²] (zeros in empty slots)
        tool_pose: ``T_world_tool``, T × 4 × 4 [m]
        tau: joint torques [N·m] or forces [N], T × n, model order
        base_wrench: wrench the base mount applies, T × 6 ``[fx fy fz mx my mz]``, world-aligned
            axes, about the base origin [N, N·m]
        base_pose: ``T_world_base``, T × 4 × 4 [m]
    """

    imu: Array
    tool_pose: Array
    tau: Array
    base_wrench: Array
    base_pose: Array


def simulate_series(
    robot: RobotModel,
    base: BaseMotion,
    trajectory: JointTrajectory,
    *,
    imu_frames: Sequence[str],
    imu_slots: Sequence[int] | None = None,
    n_slots: int | None = None,
    rate: float,
    seed: int | np.random.SeedSequence = 0,
    noise: bool = True,
    noise_model: ImuNoiseModel = ADIS16485,
    threads: int = 1,
    noise_stream: ImuNoiseStream | None = None,
    start: int = 0,
) -> RunSeries:
    """IMU signals, tool pose, torques, base wrench and base pose over a whole trajectory.

    Args:
        robot: the model (with ``moving_base`` the base follows ``base``; a free-flyer held at
            rest gives the fixed mount's load as the base wrench)
        base: the base motion at the sample times
        trajectory: the joint motion, columns in model order
        imu_frames: the model frames of the IMUs that exist
        imu_slots: the slot of ``imu`` each of ``imu_frames`` fills (default 0, 1, …); the
            other slots stay zero (empty slots)
        n_slots: S, the number of IMU slots (default ``len(imu_frames)``)
        rate: sample rate [Hz] (for the noise)
        seed: seed of the IMU noise
        noise: add IMU noise (``False`` gives the exact signals)
        noise_model: IMU noise parameters
        threads: worker threads of the batched RNEA
        noise_stream: for a piece of a longer run (:func:`chunk_bounds`), the run's noise
            (:class:`~aaria_pin.core.imu_noise.ImuNoiseStream`, over the existing IMUs); the
            piece's measurements are then those of the whole run (``seed`` is not used)
        start: the index of the piece's first sample in the run (with ``noise_stream``)

    Returns:
        The series.
    """
    from aaria_pin.core.dynamics import inverse_dynamics
    from aaria_pin.core.imu_noise import add_imu_noise
    from aaria_pin.core.kinematics import trajectory_signals

    samples = trajectory.q.shape[0]
    slots = list(range(len(imu_frames))) if imu_slots is None else list(imu_slots)
    n_imu_slots = len(imu_frames) if n_slots is None else n_slots
    # No empty slot: the noisy measurements are the record's array as they come (no zeros, no
    # scatter: a 6.7 MB copy and its page faults, 1–1.5 ms of a 10,000-sample run of 14 IMUs),
    # and no array is made for them beforehand.
    every_slot = slots == list(range(n_imu_slots))
    measured_is_record = noise and every_slot and bool(slots)
    shape = (samples, n_imu_slots, 6)
    record_imu: Array | None = None
    if not measured_is_record:
        record_imu = np.empty(shape) if every_slot and not noise else np.zeros(shape)
    exact, tool_pose = trajectory_signals(
        robot,
        base,
        trajectory,
        imu_frames,
        [robot.tool_frame],
        imu_out=None if noise else record_imu,  # noise-free: straight into the record's array
        imu_slots=None if noise else slots,
    )
    imu = exact if record_imu is None else record_imu
    if noise and slots:
        if noise_stream is not None:
            measured = noise_stream.measure(exact, start)
        else:
            measured = add_imu_noise(exact, rate, np.random.default_rng(seed), noise_model)
        if record_imu is None:
            imu = measured  # a new (T, S, 6) array: the record's, without a copy
        else:
            record_imu[:, slots] = measured
    tau, base_wrench = inverse_dynamics(robot, base, trajectory, threads)
    if robot.moving_base:
        base_pose = base.T_world_base()
    else:
        base_pose = np.broadcast_to(np.eye(4), (samples, 4, 4)).copy()
    return RunSeries(
        imu,
        tool_pose[:, 0],
        np.ascontiguousarray(tau),
        base_wrench,
        np.ascontiguousarray(base_pose),
    )
