"""Which torques the dynamic identification fits: the sources a run gives, their noise, and the
one-line refusals."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import run_cli

from aaria_pin.apps.identify import identify_dynamics
from aaria_pin.apps.identify.inertial_torques import joint_torques
from aaria_pin.core.record import RunRecord
from aaria_pin.errors import ParameterError
from aaria_pin.files.source import open_record


def _run(folder: Path, hardware: str | None) -> RunRecord:
    options = []
    if hardware is not None:
        (folder / "hw.toml").write_text(hardware)
        options = ["--hardware", str(folder / "hw.toml")]
    code, _, err = run_cli(
        "simulate", "--robot", "ur5", "--duration", "1", "--rate", "100", "--no-noise",
        *options, "-o", str(folder / "run.h5"),
    )  # fmt: skip
    assert code == 0, err
    return open_record(folder / "run.h5", None)


@pytest.fixture(scope="module")
def sensed(tmp_path_factory: pytest.TempPathFactory) -> RunRecord:
    hardware = "[torque_sensor]\nnoise = [0.1, 0.2, 0.3, 0.1, 0.1, 0.1]\nresolution = 0.6\n"
    hardware += "[actuator]\nviscous = 0.5\n"
    return _run(tmp_path_factory.mktemp("sensed"), hardware)


@pytest.fixture(scope="module")
def plain(tmp_path_factory: pytest.TempPathFactory) -> RunRecord:
    return _run(tmp_path_factory.mktemp("plain"), None)


def test_auto_takes_the_torque_sensors_and_their_noise(sensed: RunRecord) -> None:
    torques = joint_torques(sensed)
    assert torques.source == "measured"
    assert np.array_equal(torques.values, np.asarray(sensed.tables["tau_measured"], float))
    # white noise and the quantisation's step²/12
    expected = np.sqrt(np.array([0.1, 0.2, 0.3, 0.1, 0.1, 0.1]) ** 2 + 0.6**2 / 12)
    assert torques.noise is not None
    assert np.allclose(torques.noise, expected)
    assert not torques.with_friction


def test_motor_and_rigid_torques(sensed: RunRecord, plain: RunRecord) -> None:
    motor = joint_torques(sensed, "motor")
    assert motor.with_friction and motor.noise is None
    assert np.allclose(motor.values - np.asarray(sensed.tau), 0.5 * np.asarray(sensed.qd))
    rigid = joint_torques(plain)  # a run without joint hardware
    assert rigid.source == "rigid"
    assert np.array_equal(rigid.values, np.asarray(plain.tau, float))


def test_torques_a_run_does_not_have_are_one_line(plain: RunRecord) -> None:
    with pytest.raises(ParameterError) as info:
        identify_dynamics(plain, torques="motor")
    assert info.value.parameter == "torques"
    assert str(info.value) == "torques is 'motor' but the run has no tau_motor; allowed: rigid"
    with pytest.raises(ParameterError) as info:
        joint_torques(plain, "currents")
    assert info.value.parameter == "torques"
    assert "\n" not in str(info.value)


def test_a_run_without_hardware_fits_as_before(plain: RunRecord) -> None:
    auto = identify_dynamics(plain).to_json()
    rigid = identify_dynamics(plain, torques="rigid", friction=False).to_json()
    assert auto == rigid
    assert auto["torques"] == "rigid" and auto["friction"] == []
    assert "bodies" not in auto  # not constrained: no physical bodies claimed
