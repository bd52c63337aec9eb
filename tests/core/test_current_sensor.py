"""Motor current sensors: the reading is the motor's torque over ``k_t·N`` (the actuator's
recorded ``tau_motor`` divided by the torque constant and the gear ratio), its noise passes a χ²
test at 1 % (all joints together) against the configured σ, the stored bias and scale
reproduce its mean, its draws come from a stream of its own (the other sensors read the same
with it on), and a current sensor without an actuator is one line naming it."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
import pytest
from scipy.stats import chi2

import aaria_pin as ap
from aaria_pin.core.current_sensor import amperes_to_torque
from aaria_pin.core.joint_sensors import ActuatorModel, CurrentSensorModel, TorqueSensorModel
from aaria_pin.core.record import RunRecord
from aaria_pin.core.run import RunSettings, simulate
from aaria_pin.errors import ParameterError

SIGMA = 0.01  # the reading's noise [A]
RATIO = np.array([600.0, 100.0, 100.0, 80.0, 600.0, 50.0])  # aaria-fig2: joints 1, 5 slide
K_T = np.array([0.02, 0.1, 0.1, 0.08, 0.02, 0.05])  # N/A on the sliding joints
ACTUATOR = ActuatorModel(
    rotor_inertia=2e-5, gear_ratio=tuple(RATIO), viscous=0.8, coulomb=1.0, coulomb_velocity=0.02
)
TORQUE_SENSOR = TorqueSensorModel(noise=0.05, bias=0.2, resolution=0.01, scale_error=0.01)


def _run(current: CurrentSensorModel, **others: Any) -> RunRecord:
    settings = RunSettings(2.0, 500.0, noise=False, actuator=ACTUATOR, current_sensor=current)
    return simulate(ap.preset_arm("aaria-fig2"), settings=replace(settings, **others), seeds=11)


def test_a_noise_free_reading_is_the_motor_torque_over_kt_times_the_gear_ratio() -> None:
    record = _run(CurrentSensorModel(torque_constant=tuple(K_T), noise=0.0, resolution=0.0))
    assert record.attributes["current_sensor"]["torque_constant"] == pytest.approx(list(K_T))
    expected = record.tables["tau_motor"] / (K_T * RATIO)
    np.testing.assert_allclose(record.tables["current_measured"], expected, rtol=1e-12)
    assert np.all(record.tables["current_sensor_bias"] == 0)
    assert record.tables["current_measured"].shape == (record.n_samples, 6)
    assert amperes_to_torque(K_T, RATIO) == pytest.approx(K_T * RATIO)


@pytest.mark.parametrize("resolution", [0.0, SIGMA / 2])
def test_the_noise_passes_a_chi2_test_and_the_bias_and_scale_reproduce_the_mean(
    resolution: float,
) -> None:
    model = CurrentSensorModel(
        torque_constant=tuple(K_T), noise=SIGMA, bias=0.05, resolution=resolution, scale_error=0.02
    )
    record = _run(model)
    scale = record.tables["current_sensor_scale"]
    bias = record.tables["current_sensor_bias"]
    assert np.all(bias != 0) and np.all(scale != 0)  # drawn per run and joint
    truth = record.tables["tau_motor"] / (K_T * RATIO)
    residual = record.tables["current_measured"] - (1 + scale) * truth - bias
    variance = SIGMA**2 + resolution**2 / 12  # Sheppard: rounding adds Δ²/12
    n = residual.shape[0]
    alpha = 0.01 / residual.shape[1]  # 1 % over the joints together (Bonferroni)
    low, high = chi2.ppf([alpha / 2, 1 - alpha / 2], n - 1)
    for column in residual.T:
        statistic = (n - 1) * column.var(ddof=1) / variance
        assert low < statistic < high
        assert abs(column.mean()) < 4 * np.sqrt(variance / n)


def test_its_draws_leave_the_other_sensors_reading_the_same() -> None:
    with_it = _run(CurrentSensorModel(), torque_sensor=TORQUE_SENSOR)
    settings = RunSettings(2.0, 500.0, noise=False, actuator=ACTUATOR, torque_sensor=TORQUE_SENSOR)
    without = simulate(ap.preset_arm("aaria-fig2"), settings=settings, seeds=11)
    for name in ("tau_measured", "torque_sensor_bias", "tau_motor"):
        np.testing.assert_array_equal(with_it.tables[name], without.tables[name])
    assert "current_measured" not in without.tables


def test_a_current_sensor_without_an_actuator_is_refused_naming_it() -> None:
    settings = RunSettings(0.2, 100.0, noise=False, current_sensor=CurrentSensorModel())
    with pytest.raises(ParameterError) as caught:
        simulate(ap.preset_arm("aaria-fig2"), settings=settings, seeds=1)
    assert caught.value.parameter == "current_sensor"
    assert "no actuator" in str(caught.value) and "\n" not in str(caught.value)


@pytest.mark.parametrize(
    ("field", "value"), [("torque_constant", 0.0), ("noise", -1.0), ("scale_error", 1.0)]
)
def test_a_bad_value_is_refused_naming_its_field(field: str, value: float) -> None:
    with pytest.raises(ParameterError) as caught:
        CurrentSensorModel(**{field: value})
    assert caught.value.parameter == field
