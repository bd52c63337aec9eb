"""Trajectories as arrays over time: joint motions and the prescribed motion of the base.

Everything here is computed for the whole time grid at once. Sine motions follow Simulink's
Sine Wave block, ``x(t) = A·sin(w·t + phase) + bias`` with w in rad/s, and their exact first
and second derivatives.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = [
    "DEFAULT_DURATION",
    "DEFAULT_RATE",
    "MAX_DURATION",
    "MAX_RATE",
    "MAX_SAMPLES",
    "MAX_STREAMED_SAMPLES",
    "BaseMotion",
    "JointTrajectory",
    "check_rate",
    "piece_times",
    "sample_count",
    "sample_times",
    "sine_motion",
]

DEFAULT_DURATION = 10.0
"""Default run length [s]."""
DEFAULT_RATE = 100.0
"""Default sample rate [Hz]."""
MAX_DURATION = 86_400.0
"""Longest run [s]."""
MAX_RATE = 100_000.0
"""Highest sample rate [Hz]."""
MAX_SAMPLES = 2_000_000
"""Most samples of a run held whole in memory: a record (``simulate_run``, a run driven by
torques, whose forward dynamics integrate the whole run), a data set's run. Such a run peaks at
about 2.6 kB per sample noise off, 4.7 kB noise on (5 to 9 GB at this bound)."""
MAX_STREAMED_SAMPLES = 1_000_000_000
"""Most samples of a run computed and written in time pieces (``aaria simulate -o``: the
producers' ``*_chunks`` generators, written by ``write_run_pieces``). Its memory does not grow
with its length (the time grid too is made piece by piece), so what bounds it is the file and
the time: 10⁹ samples of ``aaria-fig2`` make a 1.2 TB ``.h5`` (1,176 bytes a sample; a
``.mat`` adds the 728 of ``senSen``) and take about 2 h with noise (7.7 µs a sample on the
project's machine, ``benchmarks/bench_memory.py``). That is 10,000 s (2.8 h) at the highest
rate, a whole day (:data:`MAX_DURATION`) up to 11.5 kHz; the bound is there against a slip of
the fingers (``--duration 86400 --rate 100000`` would be 8.6 × 10⁹ samples, 10 TB), not
against memory."""


def check_rate(rate: float) -> None:
    """Refuse a sample rate outside ``0 < rate <=`` :data:`MAX_RATE`.

    The one bound of every run and model: ``simulate``, ``dataset``, ``wrist simulate``,
    :class:`~aaria_pin.core.run.RunSettings` and the MJCF's timestep ``1/rate``.

    Args:
        rate: sample rate [Hz]

    Raises:
        ParameterError: a rate that is not a finite number in that range (``parameter="rate"``).
    """
    if not (np.isfinite(rate) and 0 < rate <= MAX_RATE):
        raise ParameterError(parameter="rate", value=rate, allowed=f"0 < rate <= {MAX_RATE:g} Hz")


def sample_count(duration: float, rate: float, max_samples: int | None = MAX_SAMPLES) -> int:
    """The number of samples of a run: ``⌊D·f⌋ + 1`` (see :func:`sample_times`), checked.

    Args:
        duration: run length [s], 0 < duration <= 86,400
        rate: sample rate [Hz], 0 < rate <= 100,000
        max_samples: most samples allowed (:data:`MAX_SAMPLES` for a run held whole,
            :data:`MAX_STREAMED_SAMPLES` for one computed in pieces); None: no bound beyond
            those of the duration and the rate (the length of a run that exists)

    Raises:
        ParameterError: a value outside those limits, more than ``max_samples`` samples, or
            fewer than two.
    """
    if not (np.isfinite(duration) and 0 < duration <= MAX_DURATION):
        raise ParameterError(
            parameter="duration",
            value=duration,
            allowed=f"0 < duration <= {MAX_DURATION:g} s",
        )
    check_rate(rate)
    n = math.floor(duration * rate + 1e-9) + 1
    if max_samples is not None and n > max_samples:
        held = {MAX_SAMPLES: " held in memory", MAX_STREAMED_SAMPLES: " written in pieces"}.get(
            max_samples, ""
        )
        raise ParameterError(
            f"duration × rate gives {n} samples; allowed: at most {max_samples} per run{held}",
            parameter="duration",
            value=duration,
            allowed=f"at most {max_samples} samples per run{held} (duration × rate)",
        )
    if n < 2:
        raise ParameterError(
            f"duration {duration} s at {rate} Hz gives 1 sample; allowed: >= 2",
            parameter="duration",
            value=duration,
            allowed=f">= {2 / rate:g} s at {rate:g} Hz (two samples)",
        )
    return n


def sample_times(duration: float, rate: float, max_samples: int | None = MAX_SAMPLES) -> Array:
    """The time grid of a run: from 0 to ``duration`` inclusive in steps of ``1/rate``.

    Like Simulink's fixed-step output, a run of duration D at rate f has ``⌊D·f⌋ + 1``
    samples (``D·f`` within 1e-9 of an integer counts as that integer): the first at 0, the last
    at or just before D.

    Args:
        duration: run length [s], 0 < duration <= 86,400
        rate: sample rate [Hz], 0 < rate <= 100,000
        max_samples: as in :func:`sample_count` (default: a run held whole, 2,000,000)

    Returns:
        Sample times [s].

    Raises:
        ParameterError: as :func:`sample_count`.
    """
    return piece_times(0, sample_count(duration, rate, max_samples), rate)


def piece_times(start: int, stop: int, rate: float) -> Array:
    """Samples ``start`` … ``stop - 1`` of the time grid (:func:`sample_times`) [s].

    The same numbers as ``sample_times(...)[start:stop]`` (each is its index divided by the
    rate), without making the whole grid: a run in pieces holds only its piece's times.
    """
    return np.arange(start, stop) / rate


def sine_motion(
    amplitude: ArrayLike, bias: ArrayLike, frequency: ArrayLike, phase: ArrayLike, time: Array
) -> tuple[Array, Array, Array]:
    """Sine motions and their exact derivatives, one column per motion.

    One compiled pass (``_kinematics_kernel.sine_columns``) evaluates the numpy array
    expressions it replaced per sample, with the same numbers: 0.9–1.2 ms against 1.5–2.6 ms
    for 10,000 samples of six motions (one pass, no temporaries; the range is with and
    without the commands' malloc settings). What is left is the trigonometry itself, about
    15–20 ns per sine and cosine pair. Parameters of any broadcastable shape (e.g. scalars)
    are flattened for it and the results shaped as ``np.multiply.outer(time, frequency)``.

    Args:
        amplitude: amplitudes, shape (k,) [rad or m]
        bias: offsets, shape (k,) [rad or m]
        frequency: angular frequencies, shape (k,) [rad/s]
        phase: phases, shape (k,) [rad]
        time: sample times, shape (T,) [s]

    Returns:
        Value, first and second time derivative, each shape (T, k).
    """
    from aaria_pin.core._kinematics_kernel import sine_columns

    columns = [np.asarray(x, dtype=float) for x in (amplitude, bias, frequency, phase)]
    times = np.asarray(time, dtype=float)
    shape = np.broadcast_shapes(*(c.shape for c in columns))
    A, b, w, p = (np.ascontiguousarray(np.broadcast_to(c, shape)).reshape(-1) for c in columns)
    flat_times = np.ascontiguousarray(times).reshape(-1)
    value, velocity, acceleration = (np.empty((flat_times.size, A.size)) for _ in range(3))
    sine_columns(A, b, w, p, flat_times, value, velocity, acceleration)
    out_shape = times.shape + shape  # as ``np.multiply.outer(time, w)``
    return value.reshape(out_shape), velocity.reshape(out_shape), acceleration.reshape(out_shape)


@dataclass(frozen=True)
class JointTrajectory:
    """Joint values over time, one column per actuated joint in model order.

    Attributes:
        time: sample times, shape (T,) [s]
        q: joint values, shape (T, n) [rad or m]
        qd: joint velocities, shape (T, n) [rad/s or m/s]
        qdd: joint accelerations, shape (T, n) [rad/s² or m/s²]
        tables: what the motion recorded as it was made, one column per joint in model order
            (a closed-loop drive's reference, commands and gains; empty for the others)
    """

    time: Array
    q: Array
    qd: Array
    qdd: Array
    tables: Mapping[str, Array] = field(default_factory=dict, kw_only=True)


@dataclass(frozen=True)
class BaseMotion:
    """Prescribed motion of the base frame in the world, over time.

    Attributes:
        position: base origin in the world, shape (T, 3) [m]
        velocity: its velocity, world axes, shape (T, 3) [m/s]
        acceleration: its acceleration, world axes, shape (T, 3) [m/s²]
        rotation: ``R_world_base``, shape (T, 3, 3)
        omega: angular velocity in base axes, shape (T, 3) [rad/s]
        omega_dot: its time derivative, base axes, shape (T, 3) [rad/s²]
    """

    position: Array
    velocity: Array
    acceleration: Array
    rotation: Array
    omega: Array
    omega_dot: Array

    @classmethod
    def resting(cls, n_samples: int) -> BaseMotion:
        """A base at rest at the world origin, world-aligned."""
        zeros = np.zeros((n_samples, 3))
        rotation = np.broadcast_to(np.eye(3), (n_samples, 3, 3)).copy()
        return cls(zeros, zeros.copy(), zeros.copy(), rotation, zeros.copy(), zeros.copy())

    def T_world_base(self) -> Array:
        """Base poses, shape (T, 4, 4)."""
        T = np.zeros((self.position.shape[0], 4, 4))
        T[:, :3, :3] = self.rotation
        T[:, :3, 3] = self.position
        T[:, 3, 3] = 1.0
        return T
