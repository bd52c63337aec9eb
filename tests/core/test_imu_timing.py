"""When an IMU samples (core/imu_timing.py): time offset, jitter and decimation."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import aaria_pin as ap
from aaria_pin.core.allan import allan_deviation
from aaria_pin.core.imu_presets import ADIS16485
from aaria_pin.core.imu_timing import decimation_filter, filtered_white_noise, sampled_signals

ARM = "aaria-fig2"


def _run(rate: float, duration: float, model: ap.ImuNoiseModel | None = None) -> ap.RunRecord:
    settings = ap.RunSettings(duration=duration, rate=rate, noise=model is not None,
                              noise_model=model or ADIS16485, chunk=100)  # fmt: skip
    return ap.simulate(ap.preset_arm(ARM), settings=settings, seeds=11)


def test_spline_shift_error_against_exact_signals() -> None:
    """Half a sample (the worst shift) of a 100 Hz run against the exact 200 Hz samples.

    Measured: 8.5e-7 rad/s or m/s² at most (8e-8 of each channel's peak), 1e-7 away from the
    run's ends: 1/400 of the ADIS16485's gyroscope LSB.
    """
    fast = _run(200.0, 5.0).imu
    shifted = sampled_signals(fast[::2], 100.0, np.full(14, 0.005), None, np.ones(1), 1)
    error = np.abs(shifted[:-1] - fast[1::2])
    assert error.max() < 1e-6
    assert (error.max(axis=0) / np.abs(fast).max(axis=0)).max() < 1e-6


def test_time_offset_recovered_by_cross_correlation() -> None:
    """Each IMU's drawn offset is the lag of best correlation, to one sample."""
    model = dataclasses.replace(ADIS16485, time_offset_sigma=0.05)
    assert ap.RunSettings(noise_model=model).needs_whole_run
    rate = 100.0
    measured = _run(rate, 10.0, model)
    ideal = _run(rate, 10.0).imu
    offsets = measured.tables["imu_error_time_offset"]
    assert offsets.shape == (14,) and np.abs(offsets).max() > 2.0 / rate  # several samples
    lags = np.arange(-20, 21)
    inner = slice(20, -20)
    for imu in range(14):
        # The peak of the cross-correlation Σ y·x_lag less half the shifted window's energy,
        # i.e. the lag of least Σ (y - x_lag)²: a plain correlation of this slow motion (periods
        # of seconds) is flat over tens of samples and its finite window tilts it.
        x, y = ideal[:, imu], measured.imu[:, imu]
        score = [np.sum(y[inner] * np.roll(x, -lag, axis=0)[inner])
                 - 0.5 * np.sum(np.roll(x, -lag, axis=0)[inner] ** 2) for lag in lags]  # fmt: skip
        best = lags[int(np.argmax(score))]
        assert abs(best - offsets[imu] * rate) <= 1.0  # y_k ≈ x(t_k + δ) = x[k + δ·rate]


def test_jitter_is_stored_and_whole_run() -> None:
    model = dataclasses.replace(ADIS16485, jitter=1e-4)
    record = _run(100.0, 1.0, model)
    jitter = record.tables["imu_error_jitter"]
    assert jitter.shape == (101, 14) and jitter.dtype == np.float64
    assert 0.8e-4 < jitter.std() < 1.2e-4


@pytest.mark.parametrize(("decimation", "order"), [(4, 1), (4, 2), (3, 3)])
def test_decimation_filter_of_a_sine_is_its_moving_average(decimation: int, order: int) -> None:
    """A sine through the filter: against the closed form of cascaded moving averages."""
    rate, f = 100.0, 7.0
    t = np.arange(400) / rate
    exact = np.zeros((400, 1, 6))
    exact[:, 0, :] = np.sin(2 * np.pi * f * t)[:, None]
    taps = decimation_filter(decimation, order)
    assert taps.size == order * (decimation - 1) + 1 and taps.sum() == pytest.approx(1.0)
    got = sampled_signals(exact, rate, np.zeros(1), None, taps, decimation)
    # A D-sample average at D·rate has gain sin(πfD/fi)/(D·sin(πf/fi)) and delay (D-1)/(2 fi).
    fi = decimation * rate
    gain = (np.sin(np.pi * f * decimation / fi) / (decimation * np.sin(np.pi * f / fi))) ** order
    delay = order * (decimation - 1) / (2 * fi)
    want = gain * np.sin(2 * np.pi * f * (t - delay))
    np.testing.assert_allclose(got[20:-20, 0, 0], want[20:-20], atol=2e-4)


@pytest.mark.parametrize("order", [1, 2, 3])
def test_decimated_white_noise_keeps_its_allan_deviation(order: int) -> None:
    """At τ much longer than the filter the ADEV is N/√(2τ) for every filter (unity DC gain)."""
    rate, density = 50.0, np.full(6, 1e-3)
    noise = filtered_white_noise(np.random.default_rng(order), (40_000, 1), density, rate, 8,
                                 order)  # fmt: skip
    taus = np.array([2.0, 5.0])
    adev = np.mean([allan_deviation(noise[:, 0, a], rate, taus) for a in range(6)], axis=0)
    np.testing.assert_allclose(adev, 1e-3 / np.sqrt(2 * taus), rtol=0.05)
    # per-sample σ: N·√(D·rate/2)·√(Σh²); the boxcar's Σh² = 1/D keeps σ as without decimation
    taps = decimation_filter(8, order)
    expected = 1e-3 * np.sqrt(8 * rate / 2 * np.sum(taps**2))
    assert noise.std() == pytest.approx(expected, rel=0.02)


def test_decimated_noise_in_blocks_is_the_filter_of_one_draw(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Against the taps applied to one whole draw of the same standard normals."""
    from aaria_pin.core import imu_timing

    decimation, order, samples = 5, 3, 50
    taps = decimation_filter(decimation, order)
    normals = np.random.default_rng(4).standard_normal((samples * decimation + taps.size - 1, 2, 6))
    want = np.zeros((samples, 2, 6))
    last = taps.size - 1
    for j, h in enumerate(taps):  # output k is Σ_j h_j · w[k·D + L - 1 - j]
        want += h * normals[last - j : last - j + samples * decimation : decimation]
    want *= np.sqrt(decimation * 10.0 / 2.0)
    monkeypatch.setattr(imu_timing, "BLOCK_NUMBERS", 7 * decimation * 2 * 6)  # 7 per block
    got = filtered_white_noise(np.random.default_rng(4), (samples, 2), np.ones(6), 10.0,
                               decimation, order)  # fmt: skip
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12)


def test_a_decimated_run_keeps_one_time_axis() -> None:
    model = dataclasses.replace(ADIS16485, decimation=10, decimation_order=2)
    record = _run(100.0, 1.0, model)
    assert record.imu.shape == (101, 14, 6) and record.time.shape == (101,)
    ideal = _run(100.0, 1.0).imu
    assert np.abs(record.imu - ideal).max() < 0.5  # noise and the filter's lag, not garbage
    assert record.attributes["noise_parameters"]["decimation"] == 10.0
