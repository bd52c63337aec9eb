from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from aaria_pin.core.imu_noise import (
    ADIS16485,
    DATASHEET_ROWS,
    ImuNoiseModel,
    SensorNoise,
    add_imu_noise,
    allan_deviation,
    noise_attributes,
)
from aaria_pin.errors import ParameterError

G = 9.80665
GYRO, ACCEL = ADIS16485.gyro, ADIS16485.accel
RATE = 200.0


def _resting(duration: float, rate: float, n_imu: int = 1) -> np.ndarray:
    """A resting IMU: no rotation, gravity along +z (specific force (0, 0, 9.81))."""
    signals = np.zeros((int(duration * rate), n_imu, 6))
    signals[..., 5] = 9.81
    return signals


def _naive_adev(x: np.ndarray, rate: float, m: int) -> float:
    """Overlapping Allan deviation from cluster averages, written as a plain loop."""
    means = [x[k : k + m].mean() for k in range(len(x) - m + 1)]
    diffs = [means[k + m] - means[k] for k in range(len(means) - m)]
    return float(np.sqrt(0.5 * np.mean(np.square(diffs))))


@pytest.fixture(scope="module")
def resting_noisy() -> tuple[np.ndarray, np.ndarray]:
    truth = _resting(400.0, RATE)  # 80 000 samples
    return truth, add_imu_noise(truth, RATE, np.random.default_rng(2024))


def test_si_values_from_the_datasheet() -> None:
    deg = np.pi / 180
    assert GYRO.range == pytest.approx(7.853981634)
    assert GYRO.lsb == pytest.approx(3.490658504e-4)
    assert GYRO.noise_density == pytest.approx(1.151917306e-4)
    assert GYRO.bias_stability == pytest.approx(6.25 * deg / 3600)
    assert GYRO.random_walk == pytest.approx(0.3 * deg / 60)
    assert ACCEL.range == pytest.approx(49.03325)
    assert ACCEL.lsb == pytest.approx(2.4516625e-3)
    assert ACCEL.noise_density == pytest.approx(6.5704555e-4)
    assert ACCEL.bias_stability == pytest.approx(3.138128e-4)
    assert ACCEL.random_walk == pytest.approx(3.8333333e-4)
    rows = {name: value for name, value, _ in DATASHEET_ROWS}
    assert rows["gyro range"] * deg == pytest.approx(GYRO.range)
    assert rows["accel noise density"] * 1e-3 * G == pytest.approx(ACCEL.noise_density)
    assert all(isinstance(unit, str) and unit for _, _, unit in DATASHEET_ROWS)


def test_allan_deviation_recovers_noise_density(
    resting_noisy: tuple[np.ndarray, np.ndarray],
) -> None:
    _, noisy = resting_noisy
    taus = np.array([0.05, 0.1, 0.2, 0.5])
    # Overlapping AVAR of white noise over N samples at m = τ·rate has ≈ 3N/(2m) degrees of
    # freedom: at the worst point (τ = 0.5 s, m = 100, N = 80 000) that is 1200, a relative
    # standard deviation of the deviation of 0.5·√(2/1200) ≈ 2 %. 10 % is 5σ per axis. The
    # bias (Gauss–Markov, T = 100 s) adds < 0.1 % there and quantisation (lsb/√12 per sample)
    # < 0.5 %.
    for axis in range(6):
        density = GYRO.noise_density if axis < 3 else ACCEL.noise_density
        adev = allan_deviation(noisy[:, 0, axis], RATE, taus)
        np.testing.assert_allclose(adev * np.sqrt(2 * taus), density, rtol=0.10)


def test_noise_density_agrees_with_the_random_walk_figures() -> None:
    # one-sided density N sampled over rate/2: random walk coefficient N/√2 [unit/√s]
    np.testing.assert_allclose(GYRO.noise_density / np.sqrt(2), GYRO.random_walk, rtol=0.10)
    np.testing.assert_allclose(ACCEL.noise_density / np.sqrt(2), ACCEL.random_walk, rtol=0.25)


def test_long_run_mean_is_bias_bounded(resting_noisy: tuple[np.ndarray, np.ndarray]) -> None:
    truth, noisy = resting_noisy
    # The mean of the bias over 400 s (T = 100 s) has std ≈ σ·√(2T/400) ≈ 0.71σ, the white
    # noise's mean < 0.2σ: 6σ is a > 8-sigma event.
    error = np.abs((noisy - truth).mean(axis=0)[0])
    bound = 6 * np.repeat([GYRO.bias_stability, ACCEL.bias_stability], 3)
    assert np.all(error < bound), error / bound


def test_bias_is_stationary_gauss_markov() -> None:
    # No white noise, a negligible LSB: the output minus the truth is the bias alone.
    def pure(noise: SensorNoise) -> SensorNoise:
        return dataclasses.replace(noise, noise_density=0.0, lsb=1e-12)

    model = dataclasses.replace(ADIS16485, gyro=pure(GYRO), accel=pure(ACCEL))
    rate, n_imu = 10.0, 600
    truth = _resting(100.1, rate, n_imu)  # 1001 samples: lag 0 to one correlation time
    bias = add_imu_noise(truth, rate, np.random.default_rng(7), model) - truth
    for sensor, sigma in ((slice(0, 3), GYRO.bias_stability), (slice(3, 6), ACCEL.bias_stability)):
        start, end = bias[0, :, sensor].ravel(), bias[-1, :, sensor].ravel()
        # 1800 series: the sample std has a relative std of 1/√3600 ≈ 1.7 %; 10 % is 6σ.
        assert np.std(start) == pytest.approx(sigma, rel=0.10)
        assert np.std(end) == pytest.approx(sigma, rel=0.10)
        # Correlation after one correlation time is e⁻¹; its estimate has std ≈ 0.02.
        assert np.corrcoef(start, end)[0, 1] == pytest.approx(np.exp(-1.0), abs=0.10)


def test_saturation_clips_to_the_range() -> None:
    signals = np.zeros((50, 2, 6))
    signals[:, 0, :3], signals[:, 0, 3:] = 20.0, -200.0
    signals[:, 1, :3], signals[:, 1, 3:] = -1e6, 1e6
    out = add_imu_noise(signals, RATE, np.random.default_rng(0))
    full_scale = np.repeat([GYRO.range, ACCEL.range], 3)
    lsb = np.repeat([GYRO.lsb, ACCEL.lsb], 3)
    expected = np.sign(signals) * full_scale
    assert np.all(np.abs(out - expected) <= lsb)


@settings(max_examples=25, deadline=None)
@given(
    arrays(np.float64, (5, 2, 6), elements=st.floats(-60.0, 60.0, allow_nan=False)),
    st.integers(0, 2**32 - 1),
)
def test_outputs_are_whole_lsbs_within_range(signals: np.ndarray, seed: int) -> None:
    out = add_imu_noise(signals, RATE, np.random.default_rng(seed))
    lsb = np.repeat([GYRO.lsb, ACCEL.lsb], 3)
    steps = out / lsb
    np.testing.assert_allclose(steps, np.round(steps), rtol=0, atol=1e-6)
    assert np.all(np.abs(out) <= np.repeat([GYRO.range, ACCEL.range], 3) + 0.5 * lsb)


def test_seed_determinism_and_input_untouched() -> None:
    signals = _resting(2.0, RATE, 3)
    signals[:, :, 0] = np.linspace(-1, 1, len(signals))[:, None]
    before = signals.copy()
    a = add_imu_noise(signals, RATE, np.random.default_rng(11))
    b = add_imu_noise(signals, RATE, np.random.default_rng(11))
    c = add_imu_noise(signals, RATE, np.random.default_rng(12))
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)
    np.testing.assert_array_equal(signals, before)
    assert a is not signals and a.shape == signals.shape and a.dtype == np.float64


@pytest.mark.parametrize(
    ("signals", "rate"),
    [
        (np.zeros((10, 1, 6)), 0.0),
        (np.zeros((10, 1, 6)), -100.0),
        (np.zeros((10, 1, 6)), float("nan")),
        (np.zeros((10, 1, 6)), float("inf")),
        (np.zeros((10, 6)), 100.0),
        (np.zeros((10, 1, 3)), 100.0),
        (np.zeros((0, 1, 6)), 100.0),
        (np.full((10, 1, 6), np.nan), 100.0),
        (np.full((10, 1, 6), np.inf), 100.0),
    ],
)
def test_bad_input_raises(signals: np.ndarray, rate: float) -> None:
    with pytest.raises(ParameterError, match="allowed") as info:
        add_imu_noise(signals, rate, np.random.default_rng(0))
    assert "\n" not in str(info.value)


def test_bad_model_parameters_raise() -> None:
    with pytest.raises(ParameterError, match="allowed"):
        dataclasses.replace(GYRO, lsb=0.0)
    with pytest.raises(ParameterError, match="allowed"):
        dataclasses.replace(ACCEL, noise_density=-1.0)
    with pytest.raises(ParameterError, match="allowed"):
        ImuNoiseModel(GYRO, ACCEL, bias_correlation_time=float("nan"))


def test_allan_deviation_of_white_noise() -> None:
    rate, sigma = 100.0, 0.3
    x = np.random.default_rng(5).normal(0.0, sigma, 50_000)
    taus = np.array([0.01, 0.1, 1.0])
    adev = allan_deviation(x, rate, taus)
    # Worst point τ = 1 s (m = 100): ≈ 750 degrees of freedom, 2.6 % std; 12 % is > 4.5σ.
    np.testing.assert_allclose(adev, sigma / np.sqrt(rate * taus), rtol=0.12)
    short = x[:600]
    for m in (1, 7, 300):
        assert allan_deviation(short, rate, np.array([m / rate]))[0] == pytest.approx(
            _naive_adev(short, rate, m), rel=1e-9
        )
    with pytest.raises(ParameterError, match="allowed"):
        allan_deviation(short, rate, np.array([10.0]))


def test_noise_attributes() -> None:
    attributes = noise_attributes()
    assert attributes["gyro_noise_density_rad_s_sqrtHz"] == GYRO.noise_density
    assert attributes["accel_bias_stability_m_s2"] == ACCEL.bias_stability
    assert attributes["accel_random_walk_m_s_sqrts"] == ACCEL.random_walk
    assert attributes["bias_correlation_time_s"] == 100.0
    # 0.3's 13 keys; a term of 0.4 only when it is on (files of 0.3 are made again exactly)
    assert len(attributes) == 13
    turned_on = dataclasses.replace(
        ADIS16485, gyro=dataclasses.replace(GYRO, scale_error=0.01), jitter=1e-5, decimation=2
    )
    more = noise_attributes(turned_on)
    assert set(more) - set(attributes) == {"gyro_scale_error_frac", "jitter_s", "decimation"}
    assert more["gyro_scale_error_frac"] == 0.01 and more["decimation"] == 2.0
    assert all(isinstance(value, float) for value in attributes.values())


# --- the bias knots drawn piece by piece (constant memory) -----------------------------------


def test_bias_knots_are_the_gauss_markov_recursion() -> None:
    """Against scipy's ``lfilter`` on the same standard normals (an independent recursion)."""
    from scipy.signal import lfilter

    from aaria_pin.core.imu_noise import _bias_knots

    rate, n_imu, samples = 3.9, 2, 50  # every sample a knot
    knots = _bias_knots(np.random.default_rng(3), samples, n_imu, rate, ADIS16485)
    assert knots.shape == (samples + 1, n_imu * 6)
    phi = np.exp(-1.0 / (rate * ADIS16485.bias_correlation_time))
    drawn = np.random.default_rng(3).standard_normal((samples + 1, n_imu * 6))
    drawn[1:] *= np.sqrt(1.0 - phi**2)
    sigma = np.tile(np.repeat([GYRO.bias_stability, ACCEL.bias_stability], 3), n_imu)
    expected = lfilter([1.0], [1.0, -phi], drawn, axis=0) * sigma
    np.testing.assert_allclose(knots, expected, rtol=1e-12, atol=0.0)


@pytest.mark.parametrize("sizes", [[7, 1, 30, 13], [1] * 51, [51]])
def test_bias_knots_drawn_in_pieces_are_the_knots_drawn_at_once(sizes: list[int]) -> None:
    from aaria_pin.core.imu_noise import _BiasKnots

    whole = _BiasKnots(np.random.default_rng(8), 3, 3.9, ADIS16485).draw(sum(sizes))
    knots = _BiasKnots(np.random.default_rng(8), 3, 3.9, ADIS16485)
    assert np.array_equal(np.concatenate([knots.draw(n) for n in sizes]), whole)


@pytest.mark.parametrize(("rate", "piece"), [(3.9, 97), (3.9, 1), (150.0, 40), (10_000.0, 333)])
def test_a_stream_holds_only_its_pieces_knots_and_gives_the_whole_runs_noise(
    rate: float, piece: int
) -> None:
    """A day at 3.9 Hz has a knot per sample: the stream keeps those of one piece, not 336,962."""
    from aaria_pin.core.imu_noise import ImuNoiseStream

    samples = 1201
    exact = np.random.default_rng(5).normal(0.0, 2.0, (samples, 4, 6))
    whole = add_imu_noise(exact, rate, np.random.default_rng(17))
    stream = ImuNoiseStream(samples, 4, rate, np.random.default_rng(17))
    step = max(1, int(rate * ADIS16485.bias_correlation_time / 200))
    pieces = []
    for start in range(0, samples, piece):
        pieces.append(stream.measure(exact[start : start + piece], start))
        spanned = (piece + step - 2) // step + 2  # knots a piece of this length can lie between
        assert stream._window.shape[0] <= spanned  # the piece's knots only
    assert np.array_equal(np.concatenate(pieces), whole)
