"""Joint motions that excite a robot for identification, and joint motions from given samples.

- :func:`fourier_motion`: per joint a finite Fourier series, the excitation of Swevers, Ganseman,
  Tükel, De Schutter and Van Brussel (IEEE Trans. Robotics and Automation 13(5), 1997):
  ``q(t) = q0 + sum_l (a_l / (l·w)) sin(l·w·t) - (b_l / (l·w)) cos(l·w·t)``, ``w = 2π·f``,
  with exact derivatives. The coefficients are drawn, then scaled so that the position,
  velocity and acceleration stay within their limits at every sample; the motion is periodic
  over the run when the run holds a whole number of base periods (the default frequency is
  chosen so).

A user's motion given as samples is :mod:`aaria_pin.core.sampled_motion`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, TypedDict, Unpack

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.core.arguments import checked
from aaria_pin.core.oscillation import RANGE_TOLERANCE
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import (
    MAX_SAMPLES,
    JointTrajectory,
    piece_times,
    sample_count,
    sample_times,
)
from aaria_pin.errors import ParameterError

__all__ = [
    "DEFAULT_EXCITATION_FREQUENCY",
    "DEFAULT_HARMONICS",
    "PEAK_PIECE",
    "FourierExcitation",
    "FourierLimits",
    "check_joint_range",
    "default_base_frequency",
    "fourier_excitation",
    "fourier_motion",
    "fourier_series",
]

DEFAULT_EXCITATION_FREQUENCY = 0.1
"""Lowest base frequency of the default Fourier excitation [Hz] (a 10 s period, as Swevers et
al. used); :func:`fourier_motion` raises it to fit a whole number of periods into the run."""

DEFAULT_HARMONICS = 5
"""Harmonics per joint of the default Fourier excitation."""

DEFAULT_FILL = 0.95
"""Fraction of the tightest limit the scaled Fourier motion reaches."""

PEAK_PIECE = 100_000
"""Samples per piece over which :func:`fourier_excitation` finds the series' peaks."""


class FourierLimits(TypedDict, total=False):
    """The shape and limits of a Fourier excitation (every key optional; defaults below).

    Attributes:
        base_frequency: the base frequency [Hz]; default the lowest frequency of at least
            :data:`DEFAULT_EXCITATION_FREQUENCY` that fits a whole number of periods into the
            run
        harmonics: L, harmonics per joint, >= 1 (default :data:`DEFAULT_HARMONICS`); the
            highest, ``L·base_frequency``, must be below half the rate
        q_limits: position range (lower, upper), or one row per joint [rad or m]; default
            (-1, 1)
        qd_limits: largest |velocity|, one value or one per joint [rad/s or m/s]; default 1.5
        qdd_limits: largest |acceleration|, one value or one per joint [rad/s² or m/s²];
            default 5
        fill: fraction of the tightest limit reached, 0 < fill <= 1 (default
            :data:`DEFAULT_FILL`)
    """

    base_frequency: float | None
    harmonics: int
    q_limits: ArrayLike
    qd_limits: ArrayLike
    qdd_limits: ArrayLike
    fill: float


def _per_joint(value: ArrayLike, n_joints: int, name: str, positive: bool) -> Array:
    """A scalar or one value per joint, as (n,); finite (and > 0 when ``positive``)."""
    array = np.asarray(value, dtype=float)
    if array.ndim == 0:
        array = np.full(n_joints, float(array))
    if array.shape != (n_joints,) or not np.all(np.isfinite(array)):
        raise ParameterError(
            parameter=name,
            value=np.shape(value) if array.shape != (n_joints,) else value,
            allowed=f"a finite number or {n_joints} finite numbers",
        )
    if positive and not np.all(array > 0):
        raise ParameterError(parameter=name, value=value, allowed="> 0")
    return array


def _position_limits(q_limits: ArrayLike, n_joints: int) -> tuple[Array, Array]:
    """Lower and upper position limits, (n,) each, from a (2,) or (n, 2) array."""
    limits = np.asarray(q_limits, dtype=float)
    if limits.shape == (2,):
        limits = np.broadcast_to(limits, (n_joints, 2))
    if limits.shape != (n_joints, 2) or not np.all(np.isfinite(limits)):
        raise ParameterError(
            parameter="q_limits",
            value=np.shape(q_limits),
            allowed=f"(lower, upper) or {n_joints} rows of (lower, upper), finite",
        )
    if not np.all(limits[:, 0] < limits[:, 1]):
        raise ParameterError(parameter="q_limits", value=q_limits, allowed="lower < upper")
    return limits[:, 0].copy(), limits[:, 1].copy()


def fourier_series(
    a: Array, b: Array, offset: Array, base_frequency: float, time: Array
) -> tuple[Array, Array, Array]:
    """A finite Fourier series per joint and its exact derivatives.

    ``q_j(t) = offset_j + sum_l (a_jl / (l·w)) sin(l·w·t) - (b_jl / (l·w)) cos(l·w·t)``,
    ``w = 2π·base_frequency``, l = 1 … L.

    The harmonics are summed one after the other with element-wise operations (no matrix
    product), so each sample's value depends only on its own time: a run computed in time
    pieces gets bit for bit the samples of the run computed whole.

    Args:
        a: sine coefficients, (n, L) [rad/s or m/s]
        b: cosine coefficients, (n, L) [rad/s or m/s]
        offset: the mean value of each joint, (n,) [rad or m]
        base_frequency: the base frequency [Hz]
        time: sample times, (T,) [s] (complex times too, for complex-step derivatives)

    Returns:
        q, qd, qdd, each (T, n).
    """
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    times = np.asarray(time)[:, None]
    dtype = np.result_type(times.dtype, float)
    shape = (times.shape[0], a.shape[0])
    q = np.zeros(shape, dtype=dtype)
    qd, qdd = np.zeros(shape, dtype=dtype), np.zeros(shape, dtype=dtype)
    for harmonic in range(a.shape[1]):
        w = 2.0 * np.pi * base_frequency * (harmonic + 1)
        angle = times * w
        s, c = np.sin(angle), np.cos(angle)
        a_l, b_l = a[:, harmonic], b[:, harmonic]
        q += s * (a_l / w) - c * (b_l / w)
        qd += c * a_l + s * b_l
        qdd += c * (b_l * w) - s * (a_l * w)
    q += np.asarray(offset, dtype=float)
    return q, qd, qdd


@dataclass(frozen=True)
class FourierExcitation:
    """The coefficients of a Fourier excitation (:func:`fourier_series`): a motion on any times.

    Attributes:
        a: sine coefficients, (n, L) [rad/s or m/s]
        b: cosine coefficients, (n, L) [rad/s or m/s]
        offset: the mean value of each joint, (n,) [rad or m]
        base_frequency: the base frequency [Hz]
        settings: how the coefficients were drawn (base frequency, harmonics, limits, fill,
            seed), JSON-ready: a run stores it as its ``fourier`` attribute
    """

    a: Array
    b: Array
    offset: Array
    base_frequency: float
    settings: dict[str, Any] = field(default_factory=dict)

    @property
    def n_joints(self) -> int:
        """n, the joints moved."""
        return int(self.a.shape[0])

    @property
    def harmonics(self) -> int:
        """L, the harmonics per joint."""
        return int(self.a.shape[1])

    def trajectory(self, time: Array) -> JointTrajectory:
        """The motion on the sample times ``time`` (T,) [s]: q, qd, qdd (T, n)."""
        q, qd, qdd = fourier_series(self.a, self.b, self.offset, self.base_frequency, time)
        return JointTrajectory(np.asarray(time), q, qd, qdd)

    def check_range(
        self,
        samples: int,
        rate: float,
        limits: tuple[ArrayLike, ArrayLike],
        joint_names: tuple[str, ...],
    ) -> None:
        """Refuse the motion when a joint leaves its limits at a run's sample.

        Evaluated over the run's samples in pieces of :data:`PEAK_PIECE`
        (:func:`check_joint_range`).

        Args:
            samples: T, the run's samples
            rate: the run's sample rate [Hz]
            limits: each joint's lowest and highest position, (n,) each [rad or m]
            joint_names: the n joints, in row order

        Raises:
            ParameterError: (``motion``) the first sample where a joint is outside its limits.
        """
        for start in range(0, samples, PEAK_PIECE):
            time = piece_times(start, min(start + PEAK_PIECE, samples), rate)
            q, _, _ = fourier_series(self.a, self.b, self.offset, self.base_frequency, time)
            check_joint_range(time, q, limits, joint_names, "motion")

    def table(self) -> Array:
        """The coefficients as one n × (1 + 2L) table: ``offset, a_1 … a_L, b_1 … b_L``."""
        return np.column_stack([self.offset, self.a, self.b])

    @classmethod
    def from_table(
        cls, table: ArrayLike, base_frequency: float, settings: dict[str, Any] | None = None
    ) -> FourierExcitation:
        """The excitation of a coefficient table (:meth:`table`) and its base frequency.

        Raises:
            ParameterError: not an n × (1 + 2L) table of finite numbers, or a base frequency
                that is not > 0.
        """
        array = np.asarray(table, dtype=float)
        if (
            array.ndim != 2
            or array.shape[1] < 3
            or array.shape[1] % 2 == 0
            or not np.all(np.isfinite(array))
        ):
            raise ParameterError(
                parameter="fourier_coefficients",
                value=array.shape,
                allowed="n × (1 + 2L) finite numbers (offset, a_1 … a_L, b_1 … b_L)",
            )
        if not (np.isfinite(base_frequency) and base_frequency > 0):
            raise ParameterError(parameter="base_frequency", value=base_frequency, allowed="> 0 Hz")
        harmonics = (array.shape[1] - 1) // 2
        return cls(
            a=array[:, 1 : 1 + harmonics].copy(),
            b=array[:, 1 + harmonics :].copy(),
            offset=array[:, 0].copy(),
            base_frequency=float(base_frequency),
            settings=dict(settings or {}),
        )


def check_joint_range(
    time: Array,
    q: Array,
    limits: tuple[ArrayLike, ArrayLike],
    joint_names: tuple[str, ...],
    parameter: str = "motion",
) -> None:
    """The rule of a prescribed motion: every joint within its position limits at every sample.

    The limits are the robot model's (``RunRobot.limits``); a value beyond one by more than
    :data:`~aaria_pin.core.oscillation.RANGE_TOLERANCE` is refused.

    Args:
        time: the sample times, (T,) [s]
        q: the joint values, (T, n) [rad or m]
        limits: each joint's lowest and highest position, (n,) each [rad or m] (±inf: none)
        joint_names: the n joints, in column order
        parameter: the parameter the error names

    Raises:
        ParameterError: one line naming the first sample's joint, time, value and limit.
    """
    n = len(joint_names)
    low, high = (np.broadcast_to(np.asarray(x, dtype=float), (n,)) for x in limits)
    outside = (q < low - RANGE_TOLERANCE) | (q > high + RANGE_TOLERANCE)
    if not outside.any():
        return
    row, j = (int(i) for i in np.argwhere(outside)[0])
    value = float(q[row, j])
    side, limit = ("lower", low[j]) if value < low[j] else ("upper", high[j])
    raise ParameterError(
        f"{parameter} takes joint {joint_names[j]} to {value:.6g} at t = {time[row]:.6g} s; "
        f"allowed: within its limits [{low[j]:.6g}, {high[j]:.6g}] (beyond its {side} limit "
        f"{limit:.6g})",
        parameter=parameter,
        value=value,
        allowed=f"within [{low[j]:.6g}, {high[j]:.6g}]",
        element=joint_names[j],
    )


def default_base_frequency(duration: float) -> float:
    """The default base frequency of a Fourier excitation of a run of ``duration`` [s], in Hz.

    The lowest frequency of at least :data:`DEFAULT_EXCITATION_FREQUENCY` that fits a whole
    number of periods into the run.
    """
    return math.ceil(DEFAULT_EXCITATION_FREQUENCY * duration - 1e-9) / duration


def _seed_setting(seed: int | np.random.SeedSequence | None) -> Any:
    """A seed as JSON: an int, None, or ``{"entropy", "spawn_key"}`` of a ``SeedSequence``."""
    if isinstance(seed, np.random.SeedSequence):
        entropy = seed.entropy
        if entropy is not None and not isinstance(entropy, int | np.integer):
            entropy = [int(x) for x in entropy]
        elif entropy is not None:
            entropy = int(entropy)
        return {"entropy": entropy, "spawn_key": [int(k) for k in seed.spawn_key]}
    return None if seed is None else int(seed)


def fourier_excitation(
    n_joints: int,
    duration: float,
    rate: float,
    *,
    seed: int | np.random.SeedSequence | None = 0,
    max_samples: int | None = MAX_SAMPLES,
    **limits: Unpack[FourierLimits],
) -> FourierExcitation:
    """Coefficients of a random Fourier excitation within position, speed and acceleration limits.

    Each joint's 2·L coefficients are drawn from a standard normal distribution; the series is
    centred in the joint's position range and scaled so that, over the run's samples, the
    largest of ``|q - centre| / half range``, ``|qd| / qd_max`` and ``|qdd| / qdd_max`` is
    ``fill``. The motion is periodic over the run when ``duration·base_frequency`` is an
    integer: q, qd and qdd at the last sample then equal those at the first.

    Args:
        n_joints: number of joints, >= 1
        duration: run length [s] (:func:`~aaria_pin.core.trajectory.sample_times`)
        rate: sample rate [Hz]
        seed: seed of the coefficients (``numpy.random.default_rng``)
        max_samples: most samples of the run (:func:`~aaria_pin.core.trajectory.sample_count`:
            :data:`~aaria_pin.core.trajectory.MAX_STREAMED_SAMPLES` for a run in pieces); the
            peaks are found over the run's samples :data:`PEAK_PIECE` at a time, so memory
            does not grow with the run
        **limits: the excitation's shape and limits (:class:`FourierLimits`)

    Returns:
        The coefficients (:meth:`FourierExcitation.trajectory` evaluates them on any times),
        their ``settings`` the arguments.

    Raises:
        ParameterError: a value outside the ranges above.
    """
    base_frequency = limits.get("base_frequency")
    harmonics = limits.get("harmonics", DEFAULT_HARMONICS)
    fill = limits.get("fill", DEFAULT_FILL)
    if isinstance(n_joints, bool) or not isinstance(n_joints, int | np.integer) or n_joints < 1:
        raise ParameterError(parameter="n_joints", value=n_joints, allowed="an integer >= 1")
    if isinstance(harmonics, bool) or not isinstance(harmonics, int | np.integer) or harmonics < 1:
        raise ParameterError(parameter="harmonics", value=harmonics, allowed="an integer >= 1")
    if not (np.isfinite(fill) and 0 < fill <= 1):
        raise ParameterError(parameter="fill", value=fill, allowed="0 < fill <= 1")
    samples = sample_count(duration, rate, max_samples)
    if base_frequency is None:
        base_frequency = default_base_frequency(duration)
    if not (np.isfinite(base_frequency) and base_frequency > 0):
        raise ParameterError(parameter="base_frequency", value=base_frequency, allowed="> 0 Hz")
    if harmonics * base_frequency >= rate / 2:
        raise ParameterError(  # two parameters (and the rate): the message names all three
            f"harmonics × base_frequency is {harmonics} × {base_frequency:g} Hz = "
            f"{harmonics * base_frequency:g} Hz; allowed: below half the rate ({rate / 2:g} Hz): "
            "fewer harmonics, a lower base frequency or a higher rate",
            parameter="harmonics",
            value=harmonics,
        )
    lower, upper = _position_limits(limits.get("q_limits", (-1.0, 1.0)), n_joints)
    qd_max = _per_joint(limits.get("qd_limits", 1.5), n_joints, "qd_limits", positive=True)
    qdd_max = _per_joint(limits.get("qdd_limits", 5.0), n_joints, "qdd_limits", positive=True)
    rng = np.random.default_rng(seed)
    a = rng.standard_normal((n_joints, harmonics))
    b = rng.standard_normal((n_joints, harmonics))
    centre, half_range = (lower + upper) / 2, (upper - lower) / 2
    zero = np.zeros(n_joints)
    peaks = np.zeros(n_joints)
    for start in range(0, samples, PEAK_PIECE):
        time = piece_times(start, min(start + PEAK_PIECE, samples), rate)
        q, qd, qdd = fourier_series(a, b, zero, base_frequency, time)
        piece_peaks = np.stack(
            [
                np.max(np.abs(q), axis=0) / half_range,
                np.max(np.abs(qd), axis=0) / qd_max,
                np.max(np.abs(qdd), axis=0) / qdd_max,
            ]
        ).max(axis=0)
        np.maximum(peaks, piece_peaks, out=peaks)
    scale = fill / np.where(peaks > 0, peaks, 1.0)
    # Scaling the coefficients scales the series exactly: the motion is evaluated from the
    # scaled coefficients, so q, qd and qdd are the series of the returned coefficients.
    settings = {
        "base_frequency": float(base_frequency),
        "harmonics": int(harmonics),
        "q_limits": np.column_stack([lower, upper]).tolist(),
        "qd_limits": qd_max.tolist(),
        "qdd_limits": qdd_max.tolist(),
        "fill": float(fill),
        "seed": _seed_setting(seed),
    }
    return FourierExcitation(
        a * scale[:, None], b * scale[:, None], centre, float(base_frequency), settings
    )


@checked
def fourier_motion(
    n_joints: int,
    duration: float,
    rate: float,
    *,
    seed: int | np.random.SeedSequence | None = 0,
    **limits: Unpack[FourierLimits],
) -> JointTrajectory:
    """A random Fourier excitation of each joint within its position, speed and acceleration limits.

    :func:`fourier_excitation`'s coefficients evaluated on the run's time grid
    (:func:`~aaria_pin.core.trajectory.sample_times`); the arguments are its.

    Returns:
        The joint trajectory on the run's time grid.

    Raises:
        ParameterError: a value outside the ranges of :func:`fourier_excitation`.
    """
    excitation = fourier_excitation(n_joints, duration, rate, seed=seed, **limits)
    return excitation.trajectory(sample_times(duration, rate))
