"""The overlapping Allan deviation (core/allan.py) against exact discrete results."""

from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.core.allan import allan_deviation, check_rate
from aaria_pin.core.imu_noise import allan_deviation as re_exported
from aaria_pin.errors import ParameterError

N = 400_000
M = np.array([1, 2, 5, 10, 50, 200])


def _tolerance(m: np.ndarray) -> np.ndarray:
    """5σ of the estimated deviation: EDF ≈ 3N/(2m) (white), relative σ ≈ 1/√(2·EDF)."""
    return 5.0 / np.sqrt(2 * 1.5 * N / m) + 1e-3


def test_white_noise_is_sigma_squared_over_m() -> None:
    """i.i.d. white noise of per-sample σ: AVAR(m) = σ²/m exactly (for any rate)."""
    sigma, rate = 0.3, 50.0
    x = np.random.default_rng(1).normal(0.0, sigma, N)
    adev = allan_deviation(x, rate, M / rate)
    expected = sigma / np.sqrt(M)
    assert np.all(np.abs(adev / expected - 1) < _tolerance(M))


def test_random_walk_is_the_discrete_formula() -> None:
    """b_k = b_{k-1} + q·w_k: AVAR(m) = q²(2m² + 1)/(6m) (→ q²m/3, rate random walk)."""
    q, rate = 0.01, 1.0
    x = np.cumsum(np.random.default_rng(2).normal(0.0, q, N))
    m = np.array([1, 2, 5, 10, 30])
    adev = allan_deviation(x, rate, m / rate)
    expected = q * np.sqrt((2 * m**2 + 1) / (6 * m))
    # a random walk's ADEV estimate has fewer degrees of freedom (EDF ≈ N/m·(…)): 5 % here
    np.testing.assert_allclose(adev, expected, rtol=0.05)


def test_constant_and_ramp() -> None:
    """A constant has ADEV 0; a rate ramp R·t has R·τ/√2 (exact, no noise)."""
    rate = 10.0
    assert np.allclose(allan_deviation(np.full(1000, 3.0), rate, np.array([0.1, 5.0])), 0.0)
    ramp = 0.2 * np.arange(1000) / rate
    taus = np.array([0.5, 2.0, 10.0])
    np.testing.assert_allclose(allan_deviation(ramp, rate, taus), 0.2 * taus / np.sqrt(2))


def test_against_cluster_averages_and_re_exported() -> None:
    """The cumulative-sum formula equals the cluster-average definition written as a loop."""
    x = np.random.default_rng(3).normal(size=500)
    for m in (1, 3, 17):
        means = [x[k : k + m].mean() for k in range(len(x) - m + 1)]
        diffs = [means[k + m] - means[k] for k in range(len(means) - m)]
        naive = np.sqrt(0.5 * np.mean(np.square(diffs)))
        assert allan_deviation(x, 1.0, np.array([m]))[0] == pytest.approx(naive, rel=1e-12)
    assert re_exported is allan_deviation


@pytest.mark.parametrize(
    ("x", "rate", "taus", "parameter"),
    [(np.ones(10), 0.0, [1.0], "rate"), (np.ones((2, 5)), 1.0, [1.0], "x"),
     (np.array([1.0, np.nan, 2.0]), 1.0, [1.0], "x"), (np.ones(10), 1.0, [6.0], "taus"),
     (np.ones(10), 1.0, [0.2], "taus")],
)  # fmt: skip
def test_refusals(x: np.ndarray, rate: float, taus: list[float], parameter: str) -> None:
    with pytest.raises(ParameterError) as caught:
        allan_deviation(x, rate, np.array(taus))
    assert caught.value.parameter == parameter and "\n" not in str(caught.value)


def test_check_rate() -> None:
    check_rate(1e-3)
    with pytest.raises(ParameterError, match="allowed: a finite rate > 0"):
        check_rate(float("inf"))
