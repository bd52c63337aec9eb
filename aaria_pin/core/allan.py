"""Overlapping Allan deviation, the usual check of a sensor's noise terms.

With ``θ`` the cumulative integral of a rate signal ``x`` (``θ_0 = 0``, N + 1 values) and
``m = τ·rate`` samples per cluster (IEEE Std 952-1997 Annex C, NIST SP 1065 §5.2.4)::

    σ²(τ) = Σ_k (θ_{k+2m} - 2θ_{k+m} + θ_k)² / (2τ²(N + 1 - 2m))

Exact discrete references (``tests/core/test_allan.py``): i.i.d. white noise of per-sample
standard deviation σ gives ``σ²/m``; a random walk ``b_k = b_{k-1} + q·w_k`` gives
``q²(2m² + 1)/(6m)``.
"""

from __future__ import annotations

import numpy as np

from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = ["allan_deviation", "check_rate"]


def check_rate(rate: float) -> None:
    """Refuse a sample rate that is not a finite number > 0 [Hz] (parameter ``rate``)."""
    if not (np.isfinite(rate) and rate > 0.0):
        raise ParameterError(
            f"sample rate is {rate!r} Hz; allowed: a finite rate > 0",
            parameter="rate",
            value=rate,
            allowed="a finite rate > 0 Hz",
        )


def allan_deviation(x: Array, rate: float, taus: Array) -> Array:
    """Overlapping Allan deviation of a rate signal.

    Args:
        x: 1-D rate signal (N samples) [u]
        rate: sample rate [Hz]
        taus: averaging times [s], each rounded to a whole number m >= 1 of samples with
            2m <= N; the value returned is for ``m/rate``

    Returns:
        Allan deviation at each averaging time [u], shape of ``taus``.

    Raises:
        ParameterError: the rate, the signal or an averaging time is out of range.
    """
    check_rate(rate)
    signal = np.asarray(x, dtype=np.float64)
    if signal.ndim != 1 or not np.isfinite(signal).all():
        raise ParameterError(
            f"Allan deviation signal has shape {signal.shape}; allowed: a finite 1-D array",
            parameter="x",
        )
    n = signal.size
    theta = np.concatenate(([0.0], np.cumsum(signal) / rate))
    tau_array = np.asarray(taus, dtype=np.float64)
    out = np.empty(tau_array.shape)
    for index, tau in np.ndenumerate(tau_array):
        m = int(np.rint(tau * rate)) if np.isfinite(tau) else 0
        if m < 1 or 2 * m > n:
            raise ParameterError(
                f"averaging time {tau!r} s is {m} samples; allowed: 1 to {n // 2} samples "
                f"({1.0 / rate:g} to {(n // 2) / rate:g} s)",
                parameter="taus",
            )
        d = theta[2 * m :] - 2.0 * theta[m:-m] + theta[: -2 * m]
        out[index] = np.sqrt(np.mean(d * d) / 2.0) * rate / m
    return out
