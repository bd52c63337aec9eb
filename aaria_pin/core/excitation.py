"""Joint motions that excite a robot for identification, and joint motions from given samples.

- :func:`fourier_motion`: per joint a finite Fourier series, the excitation of Swevers, Ganseman,
  Tükel, De Schutter and Van Brussel (IEEE Trans. Robotics and Automation 13(5), 1997):
  ``q(t) = q0 + sum_l (a_l / (l·w)) sin(l·w·t) - (b_l / (l·w)) cos(l·w·t)``, ``w = 2π·f``,
  with exact derivatives. The coefficients are drawn, then scaled so that the position,
  velocity and acceleration stay within their limits at every sample; the motion is periodic
  over the run when the run holds a whole number of base periods (the default frequency is
  chosen so).
- :func:`trajectory_from_samples`: a user's motion given as samples of q (and optionally qd,
  qdd): derivatives by a spline through (or, with ``smoothing``, near) the samples, resampled
  on a run's time grid when the given times are not already one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import (
    MAX_SAMPLES,
    JointTrajectory,
    piece_times,
    sample_count,
    sample_times,
)
from aaria_pin.errors import InputFileError, ParameterError

__all__ = [
    "DEFAULT_EXCITATION_FREQUENCY",
    "DEFAULT_HARMONICS",
    "MOTIONS",
    "PEAK_PIECE",
    "FourierExcitation",
    "check_trajectory",
    "default_base_frequency",
    "fourier_excitation",
    "fourier_motion",
    "fourier_series",
    "motion_attributes",
    "motion_slice",
    "stored_motion",
    "trajectory_from_samples",
]

MOTIONS = ("sine", "fourier", "trajectory")
"""The ``motion`` attribute of a run: the joint table's sines, a Fourier excitation
(:class:`FourierExcitation`, table ``fourier_coefficients``, attribute ``fourier``), or a given
trajectory (table ``joint_trajectory``: time, q, qd, qdd)."""

DEFAULT_EXCITATION_FREQUENCY = 0.1
"""Lowest base frequency of the default Fourier excitation [Hz] (a 10 s period, as Swevers et
al. used); :func:`fourier_motion` raises it to fit a whole number of periods into the run."""

DEFAULT_HARMONICS = 5
"""Harmonics per joint of the default Fourier excitation."""

DEFAULT_FILL = 0.95
"""Fraction of the tightest limit the scaled Fourier motion reaches."""

PEAK_PIECE = 100_000
"""Samples per piece over which :func:`fourier_excitation` finds the series' peaks."""


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
    base_frequency: float | None = None,
    harmonics: int = DEFAULT_HARMONICS,
    q_limits: ArrayLike = (-1.0, 1.0),
    qd_limits: ArrayLike = 1.5,
    qdd_limits: ArrayLike = 5.0,
    seed: int | np.random.SeedSequence | None = 0,
    fill: float = DEFAULT_FILL,
    max_samples: int | None = MAX_SAMPLES,
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
        base_frequency: the base frequency [Hz]; default the lowest frequency of at least
            :data:`DEFAULT_EXCITATION_FREQUENCY` that fits a whole number of periods into the
            run
        harmonics: L, harmonics per joint, >= 1; the highest, ``L·base_frequency``, must be
            below half the rate
        q_limits: position range (lower, upper), or one row per joint [rad or m]
        qd_limits: largest |velocity|, one value or one per joint [rad/s or m/s]
        qdd_limits: largest |acceleration|, one value or one per joint [rad/s² or m/s²]
        seed: seed of the coefficients (``numpy.random.default_rng``)
        fill: fraction of the tightest limit reached, 0 < fill <= 1
        max_samples: most samples of the run (:func:`~aaria_pin.core.trajectory.sample_count`:
            :data:`~aaria_pin.core.trajectory.MAX_STREAMED_SAMPLES` for a run in pieces); the
            peaks are found over the run's samples :data:`PEAK_PIECE` at a time, so memory
            does not grow with the run

    Returns:
        The coefficients (:meth:`FourierExcitation.trajectory` evaluates them on any times),
        their ``settings`` the arguments.

    Raises:
        ParameterError: a value outside the ranges above.
    """
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
        raise ParameterError(  # two parameters (and the rate): named in words, no one flag
            f"harmonics × base_frequency is {harmonics} × {base_frequency:g} Hz = "
            f"{harmonics * base_frequency:g} Hz; allowed: below half the rate ({rate / 2:g} Hz): "
            "fewer harmonics, a lower base frequency or a higher rate"
        )
    lower, upper = _position_limits(q_limits, n_joints)
    qd_max = _per_joint(qd_limits, n_joints, "qd_limits", positive=True)
    qdd_max = _per_joint(qdd_limits, n_joints, "qdd_limits", positive=True)
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


def fourier_motion(
    n_joints: int,
    duration: float,
    rate: float,
    *,
    base_frequency: float | None = None,
    harmonics: int = DEFAULT_HARMONICS,
    q_limits: ArrayLike = (-1.0, 1.0),
    qd_limits: ArrayLike = 1.5,
    qdd_limits: ArrayLike = 5.0,
    seed: int | np.random.SeedSequence | None = 0,
    fill: float = DEFAULT_FILL,
) -> JointTrajectory:
    """A random Fourier excitation of each joint within its position, speed and acceleration limits.

    :func:`fourier_excitation`'s coefficients evaluated on the run's time grid
    (:func:`~aaria_pin.core.trajectory.sample_times`); the arguments are its.

    Returns:
        The joint trajectory on the run's time grid.

    Raises:
        ParameterError: a value outside the ranges of :func:`fourier_excitation`.
    """
    excitation = fourier_excitation(
        n_joints,
        duration,
        rate,
        base_frequency=base_frequency,
        harmonics=harmonics,
        q_limits=q_limits,
        qd_limits=qd_limits,
        qdd_limits=qdd_limits,
        seed=seed,
        fill=fill,
    )
    return excitation.trajectory(sample_times(duration, rate))


def _column_matrix(values: ArrayLike, n_samples: int, name: str) -> Array:
    """(T,) or (T, n) finite values as (T, n)."""
    array = np.asarray(values, dtype=float)
    if array.ndim == 1:
        array = array[:, None]
    if array.ndim != 2 or array.shape[0] != n_samples or array.shape[1] < 1:
        raise ParameterError(
            parameter=name, value=np.shape(values), allowed=f"({n_samples}, n) with n >= 1"
        )
    if not np.all(np.isfinite(array)):
        row = int(np.argwhere(~np.isfinite(array))[0, 0])
        raise ParameterError(
            parameter=name, value="not finite", allowed="finite numbers", element=f"row {row}"
        )
    return array


def trajectory_from_samples(
    time: ArrayLike,
    q: ArrayLike,
    qd: ArrayLike | None = None,
    qdd: ArrayLike | None = None,
    *,
    rate: float,
    smoothing: float = 0.0,
) -> JointTrajectory:
    """A joint trajectory on a run's time grid from samples of q (and optionally qd, qdd).

    The output grid starts at 0 and steps by ``1/rate`` over the samples' span
    (:func:`~aaria_pin.core.trajectory.sample_times` of ``time[-1] - time[0]``); it is the
    given times shifted to start at 0 when those are already such a grid (within 1e-9 of a
    step), and the given values are then returned as they are. Derivatives not given come from
    a quintic spline of q: through every sample when ``smoothing`` is 0 (scipy's
    ``make_interp_spline``), else the smoothest whose residuals have an RMS of ``smoothing``
    (``UnivariateSpline`` with ``s = T·smoothing²``, which FITPACK meets within 0.1 %). Given
    derivatives on other times are resampled by a cubic spline through them.

    Args:
        time: sample times, (T,), strictly increasing [s]
        q: joint values, (T,) or (T, n) [rad or m]
        qd: joint velocities, same shape, or None [rad/s or m/s]
        qdd: joint accelerations, same shape, or None [rad/s² or m/s²]
        rate: the output sample rate [Hz]
        smoothing: RMS of the noise of q allowed to be smoothed away [rad or m], >= 0

    Returns:
        The trajectory.

    Raises:
        ParameterError: times not strictly increasing or not finite, fewer than 6 samples
            (a quintic spline needs 6), shapes that do not match, values not finite, a
            negative smoothing, a rate or span :func:`sample_times` refuses.
    """
    from scipy.interpolate import UnivariateSpline, make_interp_spline

    times = np.asarray(time, dtype=float)
    if times.ndim != 1 or times.size < 6:
        raise ParameterError(
            parameter="time", value=np.shape(time), allowed="(T,) with T >= 6 samples"
        )
    if times.size > MAX_SAMPLES:
        raise ParameterError(
            parameter="time", value=times.size, allowed=f"at most {MAX_SAMPLES} samples"
        )
    if not np.all(np.isfinite(times)):
        raise ParameterError(parameter="time", value="not finite", allowed="finite times")
    steps = np.diff(times)
    if not np.all(steps > 0):
        row = int(np.argmax(steps <= 0)) + 1
        raise ParameterError(
            parameter="time",
            value=float(times[row]),
            allowed="strictly increasing times",
            element=f"row {row}",
        )
    if not (np.isfinite(smoothing) and smoothing >= 0):
        raise ParameterError(parameter="smoothing", value=smoothing, allowed=">= 0")
    n_samples = times.size
    values = _column_matrix(q, n_samples, "q")
    given = {
        name: None if x is None else _column_matrix(x, n_samples, name)
        for name, x in (("qd", qd), ("qdd", qdd))
    }
    for name, x in given.items():
        if x is not None and x.shape != values.shape:
            raise ParameterError(parameter=name, value=x.shape, allowed=f"{values.shape} as q")
    grid = sample_times(float(times[-1] - times[0]), rate)
    same_grid = grid.size == n_samples and np.allclose(
        times - times[0], grid, rtol=0.0, atol=1e-9 / rate
    )
    at = times[0] + grid
    if smoothing == 0:
        spline = make_interp_spline(times, values, k=5, axis=0)
        derivatives = [spline.derivative(1), spline.derivative(2)]
        q_out = values.copy() if same_grid else spline(at)
        qd_out, qdd_out = (d(at) for d in derivatives)
    else:
        s = n_samples * smoothing**2
        splines = [UnivariateSpline(times, column, k=5, s=s) for column in values.T]
        q_out = np.column_stack([sp(at) for sp in splines])
        qd_out = np.column_stack([sp.derivative(1)(at) for sp in splines])
        qdd_out = np.column_stack([sp.derivative(2)(at) for sp in splines])
    outputs = {"qd": qd_out, "qdd": qdd_out}
    for name, x in given.items():
        if x is not None:
            outputs[name] = x.copy() if same_grid else make_interp_spline(times, x, k=3)(at)
    return JointTrajectory(grid, np.asarray(q_out), outputs["qd"], outputs["qdd"])


# --- a run's motion: checked, stored, sliced into pieces, re-made ---------------------------------


def check_trajectory(
    trajectory: JointTrajectory,
    samples: int,
    rate: float,
    lower: ArrayLike,
    upper: ArrayLike,
    joint_names: tuple[str, ...] | list[str],
) -> JointTrajectory:
    """A given joint trajectory checked against a run: its samples, columns, finite numbers, range.

    Args:
        trajectory: the motion, q, qd and qdd each (T, n)
        samples: T, the run's number of samples
        rate: the run's sample rate [Hz]
        lower: each joint's lowest position, (n,) [rad or m] (-inf: unchecked)
        upper: each joint's highest position, (n,) [rad or m] (inf: unchecked)
        joint_names: the n joints, in column order

    Returns:
        The trajectory as C-ordered float arrays, ``time`` the run's time grid.

    Raises:
        ParameterError: (``trajectory``) another shape, a value not finite, or a joint that
            leaves its range, in one line naming the joint.
    """
    n_joints = len(joint_names)
    arrays = {}
    for name in ("q", "qd", "qdd"):
        array = np.ascontiguousarray(getattr(trajectory, name), dtype=float)
        if array.shape != (samples, n_joints):
            raise ParameterError(
                parameter="trajectory",
                value=f"{name} of shape {array.shape}",
                allowed=f"({samples}, {n_joints}): the run's samples × its joints",
            )
        if not np.all(np.isfinite(array)):
            row, column = (int(i) for i in np.argwhere(~np.isfinite(array))[0])
            raise ParameterError(
                parameter="trajectory",
                value="not finite",
                allowed="finite numbers",
                element=f"{name} row {row}, joint {joint_names[column]}",
            )
        arrays[name] = array
    low = np.broadcast_to(np.asarray(lower, dtype=float), (n_joints,))
    high = np.broadcast_to(np.asarray(upper, dtype=float), (n_joints,))
    q_min, q_max = arrays["q"].min(axis=0), arrays["q"].max(axis=0)
    outside = (q_min < low - 1e-12) | (q_max > high + 1e-12)
    if np.any(outside):
        j = int(np.argmax(outside))
        raise ParameterError(
            f"trajectory joint {joint_names[j]} moves over [{q_min[j]:.4g}, {q_max[j]:.4g}]; "
            f"allowed: within its range [{low[j]:.4g}, {high[j]:.4g}]",
            parameter="trajectory",
            value=[float(f"{q_min[j]:.4g}"), float(f"{q_max[j]:.4g}")],
            allowed=f"within [{low[j]:.4g}, {high[j]:.4g}]",
            element=joint_names[j],
        )
    return JointTrajectory(piece_times(0, samples, rate), arrays["q"], arrays["qd"], arrays["qdd"])


def motion_attributes(
    motion: JointTrajectory | FourierExcitation | None, n_joints: int
) -> tuple[dict[str, Array], dict[str, Any]]:
    """The tables and attributes a run stores about its joint motion (:data:`MOTIONS`).

    Args:
        motion: None (the joint table's sines), a checked trajectory (:func:`check_trajectory`)
            or a Fourier excitation
        n_joints: the joints (or module columns) of the run's motion

    Returns:
        ``(tables, attributes)``: ``joint_trajectory`` (T × (1 + 3n): time, q, qd, qdd) or
        ``fourier_coefficients`` (n × (1 + 2L), :meth:`FourierExcitation.table`); ``motion``
        and, for a Fourier excitation, ``fourier`` (its settings and base frequency).

    Raises:
        ParameterError: (``motion``) a Fourier excitation of another number of joints, or
            something else.
    """
    if motion is None:
        return {}, {"motion": "sine"}
    if isinstance(motion, JointTrajectory):
        table = np.column_stack([motion.time, motion.q, motion.qd, motion.qdd])
        return {"joint_trajectory": table}, {"motion": "trajectory"}
    if not isinstance(motion, FourierExcitation):
        raise ParameterError(
            parameter="motion",
            value=type(motion).__name__,
            allowed="None, a JointTrajectory or a FourierExcitation",
        )
    if motion.n_joints != n_joints:
        raise ParameterError(
            f"motion is a Fourier excitation of {motion.n_joints} joints; allowed: {n_joints}",
            parameter="motion",
            value=motion.n_joints,
            allowed=f"{n_joints} joints",
        )
    settings = {**motion.settings, "base_frequency": float(motion.base_frequency)}
    return {"fourier_coefficients": motion.table()}, {"motion": "fourier", "fourier": settings}


def motion_slice(
    motion: JointTrajectory | FourierExcitation,
    start: int,
    stop: int,
    time: Array,
    columns: list[int] | None = None,
) -> JointTrajectory:
    """Samples ``start`` … ``stop - 1`` of a run's given motion, on the piece's ``time``.

    A trajectory is sliced; a Fourier excitation is evaluated on ``time`` (each sample
    depends only on its own time: :func:`fourier_series`), so pieces put together are the
    whole run's motion bit for bit.

    Args:
        motion: a checked trajectory of the whole run, or a Fourier excitation
        start: the piece's first sample
        stop: one past its last sample
        time: its sample times [s]
        columns: the columns kept (e.g. an Aaria arm's non-empty modules); None: all
    """
    if isinstance(motion, FourierExcitation):
        whole = motion.trajectory(time)
        q, qd, qdd = whole.q, whole.qd, whole.qdd
    else:
        q, qd, qdd = (x[start:stop] for x in (motion.q, motion.qd, motion.qdd))
    if columns is not None:
        q, qd, qdd = (np.ascontiguousarray(x[:, columns]) for x in (q, qd, qdd))
    return JointTrajectory(time, q, qd, qdd)


def stored_motion(
    tables: dict[str, Array], attributes: dict[str, Any]
) -> JointTrajectory | FourierExcitation | None:
    """The joint motion a run record stores (:func:`motion_attributes`), to re-make the run.

    Returns:
        None for a run of sines (``motion`` ``sine`` or no ``motion`` attribute: a run written
        before motions were stored), else the trajectory or the Fourier excitation.

    Raises:
        InputFileError: another ``motion``, or one whose table or settings are missing.
    """
    kind = attributes.get("motion", "sine")
    if kind == "sine":
        return None
    needed = {"fourier": "fourier_coefficients", "trajectory": "joint_trajectory"}.get(kind)
    if needed is None:
        raise InputFileError(
            parameter="motion", value=kind, allowed=", ".join(MOTIONS), element="run"
        )
    if needed not in tables:
        raise InputFileError(
            f"run has motion {kind!r} but no table {needed}; allowed: a run written by this "
            "toolkit",
            element="run",
        )
    table = np.asarray(tables[needed], dtype=float)
    if kind == "fourier":
        settings = attributes.get("fourier")
        if not isinstance(settings, dict) or "base_frequency" not in settings:
            raise InputFileError(
                "run has motion 'fourier' but no attribute fourier with its base_frequency; "
                "allowed: a run written by this toolkit",
                element="run",
            )
        return FourierExcitation.from_table(table, float(settings["base_frequency"]), settings)
    if table.ndim != 2 or (table.shape[1] - 1) % 3 or table.shape[1] < 4:
        raise InputFileError(
            f"run table joint_trajectory has shape {table.shape}; allowed: T × (1 + 3n)",
            element="run",
        )
    n = (table.shape[1] - 1) // 3
    return JointTrajectory(
        table[:, 0].copy(),
        np.ascontiguousarray(table[:, 1 : 1 + n]),
        np.ascontiguousarray(table[:, 1 + n : 1 + 2 * n]),
        np.ascontiguousarray(table[:, 1 + 2 * n :]),
    )
