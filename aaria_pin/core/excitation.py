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

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import MAX_SAMPLES, JointTrajectory, sample_times
from aaria_pin.errors import ParameterError

__all__ = [
    "DEFAULT_EXCITATION_FREQUENCY",
    "DEFAULT_HARMONICS",
    "fourier_motion",
    "fourier_series",
    "trajectory_from_samples",
]

DEFAULT_EXCITATION_FREQUENCY = 0.1
"""Lowest base frequency of the default Fourier excitation [Hz] (a 10 s period, as Swevers et
al. used); :func:`fourier_motion` raises it to fit a whole number of periods into the run."""

DEFAULT_HARMONICS = 5
"""Harmonics per joint of the default Fourier excitation."""

DEFAULT_FILL = 0.95
"""Fraction of the tightest limit the scaled Fourier motion reaches."""


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

    Args:
        a: sine coefficients, (n, L) [rad/s or m/s]
        b: cosine coefficients, (n, L) [rad/s or m/s]
        offset: the mean value of each joint, (n,) [rad or m]
        base_frequency: the base frequency [Hz]
        time: sample times, (T,) [s] (complex times too, for complex-step derivatives)

    Returns:
        q, qd, qdd, each (T, n).
    """
    harmonics = np.arange(1, a.shape[1] + 1)
    w = 2.0 * np.pi * base_frequency * harmonics  # (L,)
    angle = np.multiply.outer(np.asarray(time), w)  # (T, L)
    s, c = np.sin(angle), np.cos(angle)
    q = s @ (a / w).T - c @ (b / w).T + offset
    qd = c @ a.T + s @ b.T
    qdd = -s @ (a * w).T + c @ (b * w).T
    return q, qd, qdd


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

    Returns:
        The joint trajectory on the run's time grid.

    Raises:
        ParameterError: a value outside the ranges above.
    """
    if isinstance(n_joints, bool) or not isinstance(n_joints, int | np.integer) or n_joints < 1:
        raise ParameterError(parameter="n_joints", value=n_joints, allowed="an integer >= 1")
    if isinstance(harmonics, bool) or not isinstance(harmonics, int | np.integer) or harmonics < 1:
        raise ParameterError(parameter="harmonics", value=harmonics, allowed="an integer >= 1")
    if not (np.isfinite(fill) and 0 < fill <= 1):
        raise ParameterError(parameter="fill", value=fill, allowed="0 < fill <= 1")
    time = sample_times(duration, rate)
    if base_frequency is None:
        base_frequency = math.ceil(DEFAULT_EXCITATION_FREQUENCY * duration - 1e-9) / duration
    if not (np.isfinite(base_frequency) and base_frequency > 0):
        raise ParameterError(parameter="base_frequency", value=base_frequency, allowed="> 0 Hz")
    if harmonics * base_frequency >= rate / 2:
        raise ParameterError(
            parameter="harmonics",
            value=harmonics,
            allowed=f"harmonics × base frequency below half the rate ({rate / 2:g} Hz)",
        )
    lower, upper = _position_limits(q_limits, n_joints)
    qd_max = _per_joint(qd_limits, n_joints, "qd_limits", positive=True)
    qdd_max = _per_joint(qdd_limits, n_joints, "qdd_limits", positive=True)
    rng = np.random.default_rng(seed)
    a = rng.standard_normal((n_joints, harmonics))
    b = rng.standard_normal((n_joints, harmonics))
    centre, half_range = (lower + upper) / 2, (upper - lower) / 2
    q, qd, qdd = fourier_series(a, b, np.zeros(n_joints), base_frequency, time)
    peaks = np.stack(
        [
            np.max(np.abs(q), axis=0) / half_range,
            np.max(np.abs(qd), axis=0) / qd_max,
            np.max(np.abs(qdd), axis=0) / qdd_max,
        ]
    ).max(axis=0)
    scale = fill / np.where(peaks > 0, peaks, 1.0)
    # Scaling the coefficients scales the series exactly: recompute rather than rescale the
    # arrays, so q, qd and qdd are the series of the returned coefficients.
    q, qd, qdd = fourier_series(
        a * scale[:, None], b * scale[:, None], centre, base_frequency, time
    )
    return JointTrajectory(time, q, qd, qdd)


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
