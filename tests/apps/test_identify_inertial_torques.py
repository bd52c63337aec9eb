"""Which torques the dynamic identification fits: the sources a run gives, their noise, and the
one-line refusals."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from conftest import run_cli, simulated_with_hardware

from aaria_pin.apps.identify import identify_dynamics
from aaria_pin.apps.identify.inertial_torques import TorqueSource, joint_torques
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


CURRENTS = (
    "[actuator]\nviscous = 0.5\ngear_ratio = [100.0, 100.0, 100.0, 80.0, 80.0, 80.0]\n"
    "[current_sensor]\ntorque_constant = 0.12\nnoise = 0.02\nresolution = 0.004\n"
)
RATIOS = np.array([100.0, 100.0, 100.0, 80.0, 80.0, 80.0])


@pytest.fixture(scope="module")
def currents(tmp_path_factory: pytest.TempPathFactory) -> RunRecord:
    return _run(tmp_path_factory.mktemp("currents"), CURRENTS)


def test_auto_takes_the_currents_times_kt_and_the_gear_ratio(currents: RunRecord) -> None:
    torques = joint_torques(currents)  # no torque sensor: the currents before tau_motor
    assert torques.source == "current" and torques.with_friction
    amperes = np.asarray(currents.tables["current_measured"], float)
    assert np.allclose(torques.values, amperes * 0.12 * RATIOS, rtol=1e-12)
    # the reading's noise in amperes (white and step²/12), times k_t·N
    expected = np.sqrt(0.02**2 + 0.004**2 / 12) * 0.12 * RATIOS
    assert torques.noise is not None
    assert np.allclose(torques.noise, expected)
    # within its noise of the motor's exact torque
    error = torques.values - np.asarray(currents.tables["tau_motor"], float)
    assert np.all(np.abs(error.std(axis=0) / expected - 1) < 0.2)
    assert joint_torques(currents, "motor").source == "motor"


def test_a_torque_constant_given_wins_over_the_runs(currents: RunRecord) -> None:
    given = joint_torques(currents, TorqueSource("current", torque_constant=0.24))
    assert np.allclose(given.values, 2 * joint_torques(currents, "current").values)
    ratio = joint_torques(currents, TorqueSource("current", 0.12, gear_ratio=50.0))
    amperes = np.asarray(currents.tables["current_measured"], float)
    assert np.allclose(ratio.values, amperes * 6.0)


def test_currents_without_a_torque_constant_are_one_line_naming_it(currents: RunRecord) -> None:
    attributes = {k: v for k, v in currents.attributes.items() if k != "current_sensor"}
    recording = replace(currents, attributes=attributes)  # a recording: no sensor model
    with pytest.raises(ParameterError) as info:
        joint_torques(recording, "current")
    assert info.value.parameter == "torque_constant"
    assert "\n" not in str(info.value) and "no torque_constant" in str(info.value)
    values = joint_torques(recording, TorqueSource("current", torque_constant=0.12))
    assert values.noise is None  # not known without the sensor's model: weighed by the RMS
    with pytest.raises(ParameterError) as info:
        joint_torques(currents, TorqueSource("current", torque_constant=-1.0))
    assert info.value.parameter == "torque_constant"


def test_a_torque_constant_per_joint_may_be_an_array(currents: RunRecord) -> None:
    # a 1-D float array is one value per joint, as a list is (refused once by @checked)
    array = joint_torques(currents, TorqueSource("current", torque_constant=np.full(6, 0.24)))
    listed = joint_torques(currents, TorqueSource("current", torque_constant=[0.24] * 6))
    assert np.array_equal(array.values, listed.values)
    assert array.from_currents and not joint_torques(currents, "motor").from_currents


FRICTION = {
    # joints 1 and 5 of aaria-fig2 slide (N·s/m, N; a ball screw of 600 rad/m, 10.5 mm a turn)
    "ur5": "viscous = 0.8\ncoulomb = 2.0\ngear_ratio = 100.0\n",
    "aaria-fig2": (
        "viscous = [20.0, 0.8, 0.8, 0.8, 20.0, 0.8]\ncoulomb = [10.0, 2.0, 2.0, 2.0, 10.0, 2.0]\n"
        "gear_ratio = [600.0, 100.0, 100.0, 100.0, 600.0, 100.0]\n"
    ),
}


@pytest.fixture(scope="module", params=["ur5", "aaria-fig2"])
def logged(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> RunRecord:
    """10 s of Fourier motion at 200 Hz with friction, logged by current sensors of 3 mA.

    Quieter than the default (18.9 mA): 30 s at the default noise give the figures of
    docs/guide/identify-dynamics.md, 10 s at 3 mA fit within 2 % (σ ∝ noise/√T).
    """
    folder = tmp_path_factory.mktemp("logged")
    hardware = (
        f"[actuator]\nrotor_inertia = 3e-5\n{FRICTION[request.param]}\n"
        "[current_sensor]\nnoise = 0.003\n"
    )
    return open_record(simulated_with_hardware(folder, request.param, hardware, 10.0), None)


def test_currents_give_physical_bodies_friction_and_torques_at_the_noise(
    logged: RunRecord,
) -> None:
    result = identify_dynamics(logged, consistent=True)  # auto: the currents, no noise added
    report = result.to_json()
    assert report["torques"] == "current"
    assert all(body["pseudo_inertia_min_eigenvalue"] > 0 for body in report["bodies"])
    stored = logged.attributes["actuator"]
    for k, row in enumerate(report["friction"]):
        assert row["Fc"] == pytest.approx(np.broadcast_to(stored["coulomb"], 6)[k], rel=0.02)
        assert row["Fv"] == pytest.approx(np.broadcast_to(stored["viscous"], 6)[k], rel=0.02)
    joints = [i for i, name in enumerate(result.signals) if not name.startswith("base_")]
    noise = np.asarray(report["torque_noise"])
    ratio = result.holdout_rms[joints] / noise
    assert np.sqrt(np.mean(ratio**2)) == pytest.approx(1.0, rel=0.1)


def test_each_signal_is_weighed_by_its_own_residual_noise(logged: RunRecord) -> None:
    """With the base wrench in the fit each signal is weighed by 1/σ of its own residual."""
    result = identify_dynamics(logged)
    report = result.to_json()
    joints = [i for i, name in enumerate(result.signals) if not name.startswith("base_")]
    wrench = [i for i, name in enumerate(result.signals) if name.startswith("base_")]
    assert wrench  # a fixed base whose mount load is recorded
    estimated = np.asarray(report["signal_noise"])
    # the joints' residual is the current sensors' noise (3 mA times k_t·N)
    assert np.allclose(estimated[joints], report["torque_noise"], rtol=0.1)
    # the simulated load cell is exact: weighed by its (small) residual, it is fitted far
    # tighter than with 1/RMS weights (about 1e-4 of the signal on ur5's run, 3e-7 now)
    assert np.all(result.train_relative_rms[wrench] < 1e-5)


def test_each_friction_coefficient_carries_its_sigma(logged: RunRecord) -> None:
    """The σ of Fv and Fc (each a base parameter alone) covers their error, and is shown."""
    from aaria_pin.apps.identify.inertial_result import dynamics_summary

    report = identify_dynamics(logged).to_json()
    for row in report["friction"]:
        for key in ("Fv", "Fc"):
            sigma = row["std"][key]
            assert sigma is not None and sigma > 0
            assert abs(row[key] - row["model"][key]) < 5 * sigma
    lines = dynamics_summary(report)
    shown = [line for line in lines if line.startswith("friction ") and " ± " in line]
    assert len(shown) == 6
    assert not any("loosely" in line for line in lines)  # 10 s at 3 mA: all within 1 %
    row = report["friction"][4]
    row["std"]["Fv"] = 0.015 * row["Fv"]  # as aaria-fig2's sliding joint at the default noise
    said = [line for line in dynamics_summary(report) if "loosely" in line]
    assert len(said) == 1 and f"Fv {row['joint']} 1.5 %" in said[0]


def test_without_friction_the_torque_constant_is_not_checked(logged: RunRecord) -> None:
    """The scale column would take up the motor's friction the currents hold: no check."""
    from aaria_pin.apps.identify.inertial_result import dynamics_summary

    report = identify_dynamics(logged, friction=False).to_json()
    assert report["torque_scale"] == []
    said = [line for line in dynamics_summary(report) if line.startswith("torque constant")]
    assert len(said) == 1 and "not checked, the friction is not fitted" in said[0]


def test_a_current_offset_is_not_read_as_a_wrong_torque_constant(logged: RunRecord) -> None:
    """A constant offset of each current (a drive's zero, 20 mA): k_t·N is still found right."""
    from aaria_pin.apps.identify.inertial_scale import scale_off

    tables = dict(logged.tables)
    tables["current_measured"] = np.asarray(tables["current_measured"], float) + np.linspace(
        -0.02, 0.02, 6
    )
    report = identify_dynamics(replace(logged, tables=tables)).to_json()
    assert report["torque_scale"] and scale_off(report["torque_scale"]) == []
    for row in report["torque_scale"]:
        if row["std"] is not None and row["std"] < 0.01:
            assert abs(row["scale"] - 1) < 4 * row["std"]
