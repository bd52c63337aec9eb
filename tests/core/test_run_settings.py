"""RunSettings' gravity and dtype: checked once, applied by the engine, recorded, read back."""

from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.aaria.arm_run import preset_arm
from aaria_pin.core.run import RunSettings, simulate
from aaria_pin.errors import InputFileError, ParameterError

EARTH = (0.0, 0.0, -9.81)
MOON = (0.0, 0.0, -1.62)
NONE = (0.0, 0.0, 0.0)


def _run(gravity: tuple[float, float, float], dtype: str = "float64"):
    settings = RunSettings(duration=0.5, rate=40.0, noise=False, gravity=gravity, dtype=dtype)
    return simulate(preset_arm("aaria-fig2"), settings=settings)


@pytest.mark.parametrize(
    ("kwargs", "parameter"),
    [
        ({"gravity": (0.0, -9.81)}, "gravity"),
        ({"gravity": (0.0, 0.0, np.nan)}, "gravity"),
        ({"gravity": "down"}, "gravity"),
        ({"dtype": "float16"}, "dtype"),
    ],
)
def test_bad_gravity_or_dtype_is_refused_naming_it(kwargs, parameter):
    with pytest.raises(ParameterError) as error:
        RunSettings(**kwargs)
    assert error.value.parameter == parameter
    assert "\n" not in str(error.value)


def test_gravity_enters_torques_wrench_and_specific_force_linearly():
    """RNEA and the specific force a - Rᵀg are affine in g: the part due to gravity scales."""
    earth, moon, none = _run(EARTH), _run(MOON), _run(NONE)
    scale = MOON[2] / EARTH[2]
    for name in ("tau", "base_wrench", "imu"):
        due_earth = getattr(earth, name) - getattr(none, name)
        due_moon = getattr(moon, name) - getattr(none, name)
        np.testing.assert_allclose(due_moon, scale * due_earth, rtol=1e-9, atol=1e-9)
        assert np.abs(due_earth).max() > 1.0  # gravity does enter each series
    # An accelerometer's gravity part is -R_world_imuᵀ g: |·| = 9.81 in every existing slot.
    used = np.abs(earth.imu).sum(axis=(0, 2)) > 0
    part = earth.imu[:, used, 3:] - none.imu[:, used, 3:]
    np.testing.assert_allclose(np.linalg.norm(part, axis=-1), 9.81, rtol=1e-12)
    np.testing.assert_array_equal(earth.q, none.q)  # the motion does not depend on g


def test_gravity_is_recorded_read_back_and_the_model_is_left_as_found():
    robot = preset_arm("aaria-fig2")
    before = np.array(robot.model.model.gravity.linear)
    record = simulate(robot, settings=RunSettings(duration=0.2, rate=20.0, gravity=MOON))
    np.testing.assert_array_equal(robot.model.model.gravity.linear, before)
    assert record.attributes["gravity"] == list(MOON)
    assert RunSettings.from_attributes(record.attributes).gravity == MOON
    assert RunSettings.from_attributes({"duration": 1.0, "rate": 10.0}).gravity == EARTH
    with pytest.raises(InputFileError) as error:
        RunSettings.from_attributes({"duration": 1.0, "rate": 10.0, "gravity": "down"})
    assert error.value.parameter == "gravity"


def test_the_default_gravity_is_the_one_runs_always_had():
    default = simulate(preset_arm("aaria-fig2"), settings=RunSettings(duration=0.5, rate=40.0))
    assert default.attributes["gravity"] == list(EARTH)
    np.testing.assert_array_equal(default.tau, _run(EARTH).tau)


def test_float32_dtype_rounds_the_series_as_a_float32_data_set_stores_them():
    exact, rounded = _run(EARTH), _run(EARTH, "float32")
    for name in ("time", "q", "qd", "qdd", "tau", "base_wrench", "tool_pose", "imu"):
        values = getattr(rounded, name)
        assert values.dtype == np.float64
        # every value is a float32 number, and the nearest one to the exact value
        np.testing.assert_array_equal(values.astype(np.float32).astype(np.float64), values)
        spacing = np.spacing(np.abs(getattr(exact, name)).astype(np.float32)).astype(np.float64)
        assert (np.abs(values - getattr(exact, name)) <= spacing / 2 + 1e-300).all()


def test_the_hardware_models_are_recorded_and_read_back() -> None:
    import dataclasses

    from aaria_pin.core.imu_noise import ADIS16485
    from aaria_pin.core.joint_sensors import ActuatorModel, EncoderModel, TorqueSensorModel

    imu = dataclasses.replace(ADIS16485, bias_correlation_time=30.0)
    models = {
        "encoder": EncoderModel(counts_per_revolution=4096.0, noise=(1e-5, 2e-5, 3e-5)),
        "torque_sensor": TorqueSensorModel(noise=0.1, scale_error=0.01),
        "actuator": ActuatorModel(viscous=0.5, gear_ratio=50.0),
    }
    settings = RunSettings(duration=0.5, rate=40.0, noise_model=imu, **models)
    attributes = settings.attributes(3)
    assert attributes["encoder"]["noise"] == [1e-5, 2e-5, 3e-5]  # plain values, per joint
    assert attributes["actuator"]["gear_ratio"] == 50.0
    back = RunSettings.from_attributes(attributes)
    assert back.noise_model == imu
    assert (back.encoder, back.torque_sensor, back.actuator) == tuple(models.values())


def test_a_run_without_hardware_attributes_reads_back_today_s_defaults() -> None:
    from aaria_pin.core.imu_noise import ADIS16485

    attributes = RunSettings(duration=0.5, rate=40.0).attributes(0)
    assert not {"encoder", "torque_sensor", "actuator"} & set(attributes)  # as runs before
    del attributes["noise_parameters"]  # a file written before any noise model was recorded
    back = RunSettings.from_attributes(attributes)
    assert back.noise_model == ADIS16485
    assert back.encoder is None and back.torque_sensor is None and back.actuator is None


def test_a_stored_model_that_is_not_a_table_is_an_input_file_error() -> None:
    attributes = {**RunSettings(duration=0.5, rate=40.0).attributes(0), "encoder": 3.0}
    with pytest.raises(InputFileError, match=r"attribute 'encoder' is 3.0; allowed: a table"):
        RunSettings.from_attributes(attributes)
