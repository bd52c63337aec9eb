"""The IMU errors drawn once per run (core/imu_errors.py): stored, recovered, off by default."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

import aaria_pin as ap
from aaria_pin.core.allan import allan_deviation
from aaria_pin.core.imu_errors import TERMS, draw_imu_errors, imu_error_shapes
from aaria_pin.core.imu_model import ImuNoiseModel, SensorNoise
from aaria_pin.core.imu_presets import ADIS16485, IMU_PRESETS
from aaria_pin.core.seeds import sensor_sequence

RATE = 100.0


def _clean(full_scale: float = 1e6, **terms: float) -> SensorNoise:
    """A sensor with no noise, no bias, no saturation and quantisation below 1e-12 [u]."""
    return SensorNoise(range=full_scale, lsb=1e-13, noise_density=0.0, bias_stability=0.0,
                       random_walk=0.0, **terms)  # fmt: skip


def _run(model: ImuNoiseModel | None, seed: int = 7, duration: float = 2.0) -> ap.RunRecord:
    settings = ap.RunSettings(duration=duration, rate=RATE, noise=model is not None,
                              noise_model=model or ADIS16485)  # fmt: skip
    return ap.simulate(ap.preset_arm("aaria-fig2"), settings=settings, seeds=seed)


def _fit(ideal: np.ndarray, measured: np.ndarray) -> np.ndarray:
    """Least squares ``measured ≈ X·ideal`` per IMU: X (n_imu, 3, k) from (T, n_imu, k) signals."""
    return np.stack([np.linalg.lstsq(ideal[:, i], measured[:, i], rcond=None)[0].T
                     for i in range(ideal.shape[1])])  # fmt: skip


def _slots(ideal: np.ndarray) -> np.ndarray:
    """The record slots that hold an IMU (the others are zero)."""
    return np.flatnonzero(np.abs(ideal).sum(axis=(0, 2)) > 0)


def test_scale_cross_axis_and_misalignment_recovered_from_the_file(tmp_path: Path) -> None:
    """Fit the axis matrices from the ideal and measured signals; compare with the stored ones."""
    gyro = _clean(scale_error=0.02, cross_axis=0.01, misalignment=0.02)
    accel = _clean(scale_error=0.01, cross_axis=0.005, misalignment=0.01)
    path = tmp_path / "run.h5"
    ap.write_run(path, _run(ImuNoiseModel(gyro, accel), duration=10.0))
    stored = ap.open_record(path)
    ideal = _run(None, duration=10.0).imu
    matrix = stored.tables["imu_error_matrix"]  # S × 2 × 3 × 3 (gyroscope, accelerometer)
    slots = _slots(ideal)
    for sensor in range(2):
        axes = slice(3 * sensor, 3 * sensor + 3)
        fit = _fit(ideal[:, slots, axes], stored.imu[:, slots, axes])
        np.testing.assert_allclose(fit, matrix[slots, sensor], rtol=0, atol=1e-9)
    # The stored parts multiply to the stored matrix: M = (I + diag(s))·C·R.
    scale = 1.0 + stored.tables["imu_error_scale"][slots].reshape(-1, 2, 3)
    product = scale[..., None] * stored.tables["imu_error_cross_axis"][slots]
    product = product @ stored.tables["imu_error_misalignment"][slots]
    np.testing.assert_allclose(product, matrix[slots], rtol=0, atol=1e-15)
    rotation = stored.tables["imu_error_misalignment"][slots]
    np.testing.assert_allclose(rotation @ np.swapaxes(rotation, -1, -2),
                               np.broadcast_to(np.eye(3), rotation.shape), atol=1e-12)  # fmt: skip


def test_g_sensitivity_recovered_with_the_gyro_matrix(tmp_path: Path) -> None:
    """One joint fit of ``[M_g G]`` on ``[ω f]``, on the IMUs whose six signals are not collinear.

    The base IMUs see almost only gravity (condition number of ``[ω f]`` near 1e6 over 10 s):
    their fit is not determined to 1e-9, so the IMUs with a condition number < 1e4 are fitted.
    """
    model = ImuNoiseModel(_clean(misalignment=0.02, g_sensitivity=1e-3), _clean())
    path = tmp_path / "run.h5"
    ap.write_run(path, _run(model, duration=10.0))
    stored, ideal = ap.open_record(path), _run(None, duration=10.0).imu
    slots = [i for i in _slots(ideal) if np.linalg.cond(ideal[:, i]) < 1e4]
    assert len(slots) >= 8
    fit = _fit(ideal[:, slots], stored.imu[:, slots, :3])
    np.testing.assert_allclose(fit[..., :3], stored.tables["imu_error_matrix"][slots, 0], atol=1e-9)
    sensitivity = stored.tables["imu_error_g_sensitivity"][slots]
    np.testing.assert_allclose(fit[..., 3:], sensitivity, rtol=0, atol=1e-9)


def test_nothing_is_drawn_with_every_new_term_off() -> None:
    """A model whose 0.4 terms are 0 is the ADIS16485 of 0.3: the same record, no new table."""
    spelled = dataclasses.replace(
        ADIS16485, gyro=dataclasses.replace(ADIS16485.gyro, scale_error=0.0, bias_offset=0.0),
        time_offset=0.0, jitter=0.0, decimation=1)  # fmt: skip
    assert not spelled.new_terms and not spelled.needs_whole_run
    a, b = _run(ADIS16485, duration=0.5), _run(spelled, duration=0.5)
    assert np.array_equal(a.imu, b.imu)
    assert not [name for name in b.tables if name.startswith("imu_error")]
    assert draw_imu_errors(spelled, sensor_sequence(7, "imu"), 50, RATE, (0,), 1) is None


def test_turn_on_bias_and_nonlinearity_are_the_stored_values() -> None:
    """With only b0 and k2 on, measured - ideal is k2·ideal² + b0 to rounding."""
    model = ImuNoiseModel(_clean(100.0, bias_offset=0.01, nonlinearity=0.002),
                          _clean(100.0, bias_offset=0.1, nonlinearity=0.005))  # fmt: skip
    record, ideal = _run(model, duration=0.5), _run(None, duration=0.5).imu
    k2, b0 = record.tables["imu_error_nonlinearity"], record.tables["imu_error_bias_offset"]
    slots = _slots(ideal)
    expected = ideal[:, slots] + k2[slots] * ideal[:, slots] ** 2 + b0[slots]
    np.testing.assert_allclose(record.imu[:, slots], expected, rtol=0, atol=1e-12)
    k2_of_the_datasheet = 1.5 * np.repeat([0.002, 0.005], 3) / 100.0  # 1.5·NL/FS
    np.testing.assert_allclose(np.abs(k2[slots]), np.broadcast_to(k2_of_the_datasheet, (14, 6)))
    assert (k2[slots] > 0).any() and (k2[slots] < 0).any()  # random signs


def test_each_term_draws_from_its_own_stream() -> None:
    """Turning a term on does not change the values of another (own child stream each)."""
    alone = ImuNoiseModel(_clean(bias_offset=0.01), _clean())
    both = ImuNoiseModel(_clean(bias_offset=0.01, scale_error=0.01), _clean())
    first = draw_imu_errors(alone, sensor_sequence(3, "imu"), 10, RATE, (0, 2), 3)
    second = draw_imu_errors(both, sensor_sequence(3, "imu"), 10, RATE, (0, 2), 3)
    assert first is not None and second is not None
    offset = first.tables["imu_error_bias_offset"]
    assert np.array_equal(offset, second.tables["imu_error_bias_offset"])
    assert not offset[1].any() and offset[[0, 2], :3].all()  # slot 1 is empty
    assert len(TERMS) == len(set(TERMS))


def test_bias_random_walk_has_its_allan_slope() -> None:
    """ADEV of the stored walk is K·√(τ/3) (rate random walk), within its EDF at 5 %."""
    walk = 1e-4
    model = dataclasses.replace(ImuNoiseModel(_clean(bias_random_walk=walk), _clean()))
    assert model.needs_whole_run
    errors = draw_imu_errors(model, sensor_sequence(1, "imu"), 200_000, RATE, (0,), 1)
    assert errors is not None
    table = errors.tables["imu_error_bias_random_walk"]  # T × 6S
    series = table.reshape(table.shape[0], -1, 6)[:, 0, :3]
    taus = np.array([1.0, 3.0, 10.0])
    adev = np.mean([allan_deviation(series[:, a], RATE, taus) for a in range(3)], axis=0)
    # discrete random walk q = K/√rate: AVAR(m) = q²(2m² + 1)/(6m), i.e. K²τ/3 for m >> 1
    np.testing.assert_allclose(adev, walk * np.sqrt(taus / 3.0), rtol=0.05)


@pytest.mark.parametrize("term", ["scale_error", "cross_axis", "nonlinearity"])
def test_a_fraction_of_one_or_more_is_refused(term: str) -> None:
    with pytest.raises(ap.ParameterError, match=rf"^{term} is 1.0; allowed: .*< 1") as caught:
        _clean(**{term: 1.0})
    assert caught.value.parameter == term


def test_a_run_in_pieces_is_the_run_held_whole() -> None:
    """Per-sample terms (axes, biases) keep a run in pieces bit for bit the whole run's."""
    model = IMU_PRESETS["mpu6050"]
    assert model.new_terms and not model.needs_whole_run
    seeds = ap.RunSeeds(9, run=2)  # a data set's run: its noise seed is a SeedSequence
    settings = ap.RunSettings(duration=1.0, rate=100.0, noise_model=model, chunk=17)
    arm = ap.preset_arm("aaria-fig2")
    pieces = list(ap.simulate_pieces(arm, settings=settings, seeds=seeds))
    whole = ap.simulate(arm, settings=settings, seeds=seeds)
    assert len(pieces) == 6
    assert np.array_equal(np.concatenate([p.imu for p in pieces]), whole.imu)
    assert np.array_equal(pieces[0].tables["imu_error_matrix"], whole.tables["imu_error_matrix"])


def test_the_shapes_a_layout_declares_are_those_drawn() -> None:
    """imu_error_shapes (what a data set's layout needs before a run) against a drawn run."""
    everything = ImuNoiseModel(
        _clean(scale_error=0.01, cross_axis=0.01, misalignment=0.01, g_sensitivity=1e-4,
               nonlinearity=0.001, bias_offset=0.01, bias_random_walk=1e-4),
        _clean(alignment=np.eye(3)), time_offset=0.001, jitter=1e-5, decimation=2,
    )  # fmt: skip
    for model in (everything, *IMU_PRESETS.values()):
        errors = draw_imu_errors(model, sensor_sequence(5, "imu"), 30, RATE, (0, 1, 3), 4)
        shapes = imu_error_shapes(model, 30, 4)
        drawn = {} if errors is None else {k: v.shape for k, v in errors.tables.items()}
        assert list(drawn.items()) == list(shapes.items())
    assert len(imu_error_shapes(everything, 30, 4)) == 10
