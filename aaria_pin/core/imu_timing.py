"""When an IMU samples: a time offset, sample-time jitter and decimation with the part's filter.

The record keeps one time axis (the run's sample times ``t_k = k/rate``); an IMU whose clock is
off samples the exact signals at other instants and reports them at ``t_k``. Output sample k
of IMU i is::

    y_k = Σ_j h_j · x(t_k + δ_i + ε_ki - j/(D·rate))

with ``δ_i`` the IMU's time offset, ``ε_ki`` its jitter, ``D`` the decimation and ``h`` the
decimation filter (:func:`decimation_filter`; ``h = [1]`` without decimation). The exact
signals ``x`` at instants off the run's grid come from a cubic spline through the run's exact
samples (``scipy.interpolate.CubicSpline``, not-a-knot ends, extrapolated past them): the
engine's motions are smooth, and ``tests/core/test_imu_timing.py`` measures the spline's error
against exact signals computed at the shifted instants. Instants before the run's first sample
(a negative offset, the filter's window of the first outputs: ``order·(D - 1)/(D·rate)`` s) or
after its last extrapolate the spline's end pieces. The filter's white noise is drawn at
the internal rate ``D·rate`` (:func:`filtered_white_noise`), so the Allan deviation of the
output at τ much longer than the filter is the part's ``N/√(2τ)``.
"""

from __future__ import annotations

import numpy as np

from aaria_pin.core.se3 import Array

__all__ = ["BLOCK_NUMBERS", "decimation_filter", "filtered_white_noise", "sampled_signals"]


def decimation_filter(decimation: int, order: int) -> Array:
    """The decimation filter: ``order`` cascaded D-sample moving averages (DC gain 1).

    ``order`` 1 is the boxcar of an averaging decimation (ADIS16485's DEC_RATE), 2 the
    Bartlett (triangular) window of the ADIS1647x; 3 a smoother, nearly Gaussian low-pass.

    Args:
        decimation: D >= 1
        order: 1, 2 or 3

    Returns:
        The taps ``h_j``, j = 0 … order·(D - 1), summing to 1.
    """
    box = np.full(decimation, 1.0 / decimation)
    taps = np.ones(1)
    for _ in range(order):
        taps = np.convolve(taps, box)
    return taps


BLOCK_NUMBERS = 2**21
"""Numbers per block (16 MiB of float64) when a run's samples are filtered a block at a time."""


def sampled_signals(
    exact: Array,
    rate: float,
    offsets: Array,
    jitter: Array | None,
    taps: Array,
    decimation: int,
) -> Array:
    """The exact signals as the IMUs sample them: shifted, jittered and filtered.

    Each output sample is its own window of L = ``taps.size`` spline values (a jittered
    output's window moves with it), evaluated in blocks of at most :data:`BLOCK_NUMBERS`
    numbers: the memory does not grow with D, the time grows as T·L.

    Args:
        exact: the exact signals at the run's samples, (T, n_imu, 6), T >= 4
        rate: the run's sample rate [Hz]
        offsets: each IMU's time offset δ_i, (n_imu,) [s]
        jitter: each sample's jitter ε_ki, (T, n_imu) [s] (None: none)
        taps: the decimation filter (:func:`decimation_filter`)
        decimation: D, the internal samples per output sample

    Returns:
        ``y`` of the module docstring, (T, n_imu, 6) [rad/s, m/s²].
    """
    from scipy.interpolate import CubicSpline

    samples, n_imu = exact.shape[:2]
    times = np.arange(samples) / rate
    lags = np.arange(taps.size) / (decimation * rate)
    block = max(1, BLOCK_NUMBERS // (6 * taps.size))
    out = np.empty_like(exact)
    for imu in range(n_imu):
        spline = CubicSpline(times, exact[:, imu], axis=0)
        instants = times + offsets[imu]
        if jitter is not None:
            instants = instants + jitter[:, imu]
        for first in range(0, samples, block):
            at = instants[first : first + block]
            window = spline((at[:, None] - lags[None, :]).ravel()).reshape(at.size, taps.size, 6)
            out[first : first + at.size, imu] = np.einsum("j,tjc->tc", taps, window)
    return out


def _moving_average(values: Array, width: int) -> Array:
    """The ``width``-sample moving average along axis 0, "valid" part (len - width + 1 rows)."""
    total = np.concatenate([np.zeros((1, *values.shape[1:])), np.cumsum(values, axis=0)])
    return (total[width:] - total[:-width]) / width


def filtered_white_noise(
    rng: np.random.Generator,
    shape: tuple[int, int],
    density: Array,
    rate: float,
    decimation: int,
    order: int,
) -> Array:
    """White noise drawn at the internal rate ``D·rate``, filtered and decimated.

    The internal samples are drawn in time order (L - 1 before the run's first output, then D
    per output, L = ``order·(D - 1) + 1``), a block of outputs at a time (:data:`BLOCK_NUMBERS`),
    and filtered by ``order`` moving averages of D samples (:func:`decimation_filter`'s taps).

    Args:
        rng: the generator
        shape: (T, n_imu)
        density: the noise density of each of the six axes, (6,) [u/√Hz], one-sided
        rate: the output rate [Hz]
        decimation: D
        order: the filter's order

    Returns:
        The output noise, (T, n_imu, 6): per internal sample ``N·√(D·rate/2)``, filtered, and
        output k the filter's value at internal sample ``k·D`` (time ``t_k``).
    """
    samples, n_imu = shape
    held = rng.standard_normal((order * (decimation - 1), n_imu, 6))
    block = max(1, BLOCK_NUMBERS // (decimation * n_imu * 6))
    out = np.empty((samples, n_imu, 6))
    for first in range(0, samples, block):
        count = min(block, samples - first)
        internal = np.concatenate([held, rng.standard_normal((count * decimation, n_imu, 6))])
        held = internal[internal.shape[0] - held.shape[0] :]
        filtered = internal
        for _ in range(order):
            filtered = _moving_average(filtered, decimation)
        out[first : first + count] = filtered[::decimation]
    out *= density * np.sqrt(decimation * rate / 2.0)
    return out
