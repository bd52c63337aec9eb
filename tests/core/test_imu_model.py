"""The IMU model's fields and their checks (core/imu_model.py): each bad value, one line."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from aaria_pin.core.imu_model import ImuNoiseModel, check_rotation
from aaria_pin.core.imu_presets import ADIS16485
from aaria_pin.errors import ParameterError

GYRO, ACCEL = ADIS16485.gyro, ADIS16485.accel


def _refused(make: object, parameter: str, allowed: str) -> None:
    with pytest.raises(ParameterError) as caught:
        make()  # type: ignore[operator]
    message = str(caught.value)
    assert caught.value.parameter == parameter
    assert message.startswith(parameter) and f"allowed: {allowed}" in message
    assert "\n" not in message


def test_negative_noise_density() -> None:
    _refused(lambda: dataclasses.replace(GYRO, noise_density=-1e-4), "noise_density", "a finite")


def test_negative_bias_random_walk() -> None:
    _refused(lambda: dataclasses.replace(ACCEL, bias_random_walk=-1.0), "bias_random_walk", "a")


def test_scale_error_of_one() -> None:
    _refused(lambda: dataclasses.replace(GYRO, scale_error=1.0), "scale_error", "a finite number")


def test_alignment_that_is_not_a_rotation() -> None:
    sheared = [[1.0, 0.1, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    _refused(lambda: dataclasses.replace(GYRO, alignment=sheared), "alignment", "a 3 × 3 rotation")
    mirrored = np.diag([1.0, 1.0, -1.0])  # orthogonal, det -1
    _refused(lambda: dataclasses.replace(ACCEL, alignment=mirrored), "alignment", "a 3 × 3")
    _refused(lambda: check_rotation("alignment", [[1.0, 0.0]]), "alignment", "a 3 × 3")


def test_a_rotation_is_taken() -> None:
    c, s = np.cos(0.01), np.sin(0.01)
    turned = dataclasses.replace(GYRO, alignment=[[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    assert turned.alignment is not None and turned.alignment[1][0] == s and turned.matrix_terms


def test_g_sensitivity_on_an_accelerometer() -> None:
    accel = dataclasses.replace(ACCEL, g_sensitivity=1e-4)  # the sensor alone cannot tell
    with pytest.raises(ParameterError, match=r"^accel.g_sensitivity is 0.0001; allowed: 0 "):
        ImuNoiseModel(GYRO, accel)


@pytest.mark.parametrize(
    ("field", "value", "allowed"),
    [("jitter", -1e-6, "a finite number >= 0"), ("time_offset_sigma", float("nan"), "a finite"),
     ("decimation", 0, "a whole number 1 to 4096"), ("decimation", 2.5, "a whole number"),
     ("decimation_order", 4, "1, 2, 3")],
)  # fmt: skip
def test_bad_timing_fields(field: str, value: float, allowed: str) -> None:
    _refused(lambda: dataclasses.replace(ADIS16485, **{field: value}), field, allowed)


def test_time_offset_is_finite_of_either_sign() -> None:
    assert dataclasses.replace(ADIS16485, time_offset=-0.01).needs_whole_run
    _refused(lambda: dataclasses.replace(ADIS16485, time_offset=float("inf")), "time_offset", "a")


def test_which_terms_need_the_whole_run() -> None:
    """Scale and axes are per sample (a run in pieces keeps them); timing and RRW are not."""
    scaled = dataclasses.replace(ADIS16485, gyro=dataclasses.replace(GYRO, scale_error=0.01))
    assert scaled.new_terms and not scaled.needs_whole_run
    walking = dataclasses.replace(ADIS16485, accel=dataclasses.replace(ACCEL, bias_random_walk=1))
    assert walking.needs_whole_run
    assert dataclasses.replace(ADIS16485, decimation=4).needs_whole_run
    assert not ADIS16485.new_terms and not ADIS16485.needs_whole_run
