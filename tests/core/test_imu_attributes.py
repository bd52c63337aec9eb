"""An IMU model read back from a run's noise_parameters (core/imu_attributes.py)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

import aaria_pin as ap
from aaria_pin.core.imu_attributes import noise_model_from_attributes
from aaria_pin.core.imu_noise import noise_attributes
from aaria_pin.core.imu_presets import ADIS16485, IMU_PRESETS

OLD_KEYS = (  # the 13 keys every file of 0.1 to 0.3 records
    "gyro_range_rad_s", "gyro_lsb_rad_s", "gyro_noise_density_rad_s_sqrtHz",
    "gyro_bias_stability_rad_s", "gyro_random_walk_rad_sqrts", "accel_range_m_s2",
    "accel_lsb_m_s2", "accel_noise_density_m_s2_sqrtHz", "accel_bias_stability_m_s2",
    "accel_random_walk_m_s_sqrts", "bandwidth_hz", "internal_rate_hz", "bias_correlation_time_s",
)  # fmt: skip


@pytest.mark.parametrize("preset", sorted(IMU_PRESETS))
def test_every_preset_reads_back(preset: str) -> None:
    model = IMU_PRESETS[preset]
    assert noise_model_from_attributes(noise_attributes(model)) == model


def test_a_file_of_before_reads_as_its_numbers_with_the_new_terms_off() -> None:
    old = {key: value for key, value in noise_attributes(ADIS16485).items() if key in OLD_KEYS}
    old["gyro_noise_density_rad_s_sqrtHz"] = 2e-4
    model = noise_model_from_attributes(old)
    assert model.gyro.noise_density == 2e-4 and not model.new_terms
    assert noise_model_from_attributes(None) is ADIS16485
    assert noise_model_from_attributes({}) is ADIS16485


def test_a_written_run_records_every_term(tmp_path: Path) -> None:
    turned = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    gyro = dataclasses.replace(ADIS16485.gyro, scale_error=0.01, alignment=turned)
    model = dataclasses.replace(ADIS16485, gyro=gyro, time_offset=0.002, decimation=2)
    settings = ap.RunSettings(duration=0.2, rate=100.0, noise_model=model)
    path = tmp_path / "run.h5"
    ap.write_run(path, ap.simulate(ap.preset_arm("aaria-fig2"), settings=settings))
    stored = ap.open_record(path).attributes["noise_parameters"]
    assert noise_model_from_attributes(stored) == model
    assert stored["gyro_alignment_matrix"] == pytest.approx(turned.ravel())
