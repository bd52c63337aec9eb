"""Friction and armature in the dynamic identification (issue 26).

The friction columns against the simulator's own friction law (:mod:`aaria_pin.core.actuator`),
then runs made by ``aaria simulate`` with a torque sensor and friction on ur5 and aaria-fig2
(Fourier motion, 10 s at 200 Hz): every body's pseudo-inertia positive definite, the friction
within 2 % of the run's hardware file, the held-out torque RMS within 10 % of the noise's.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from conftest import simulated_with_hardware

from aaria_pin.apps.identify import identify_dynamics
from aaria_pin.apps.identify.inertial_friction import friction_names, friction_regressor
from aaria_pin.core.actuator import ActuatorModel, actuator_torques
from aaria_pin.core.record import RunRecord
from aaria_pin.errors import ParameterError
from aaria_pin.files.source import open_record

SIGMA = 0.02  # the torque noise, 1σ [N·m or N]

HARDWARE = {
    # joints 1 and 5 of aaria-fig2 are prismatic: N·s/m, N, kg
    "ur5": {"viscous": [0.8] * 6, "coulomb": [2.0] * 6, "gear_ratio": [100.0] * 6},
    "aaria-fig2": {
        "viscous": [20.0, 0.8, 0.8, 0.8, 20.0, 0.8],
        "coulomb": [10.0, 2.0, 2.0, 2.0, 10.0, 2.0],
        "gear_ratio": [600.0, 100.0, 100.0, 100.0, 600.0, 100.0],
    },
}
ROTOR_INERTIA = 3e-5


def _toml(values: dict[str, list[float]]) -> str:
    lines = [f"[torque_sensor]\nnoise = {SIGMA}\n\n[actuator]\nrotor_inertia = {ROTOR_INERTIA}"]
    lines += [f"{key} = {value}" for key, value in values.items()]
    return "\n".join(lines) + "\n"


@pytest.fixture(scope="module", params=["ur5", "aaria-fig2"])
def run(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> RunRecord:
    folder = tmp_path_factory.mktemp("friction")
    path = simulated_with_hardware(folder, request.param, _toml(HARDWARE[request.param]), 10.0)
    return open_record(path, None)


def _with_noisy_motor(record: RunRecord) -> RunRecord:
    """The run with white noise of σ on its motor torques (a motor current's noise)."""
    noise = SIGMA * np.random.default_rng(11).standard_normal(record.tau.shape)
    motor = np.asarray(record.tables["tau_motor"], dtype=float) + noise
    return replace(record, tables={**record.tables, "tau_motor": motor})


def _joint_rows(signals: tuple[str, ...]) -> list[int]:
    return [i for i, name in enumerate(signals) if not name.startswith("base_")]


def test_friction_columns_are_the_simulators_friction_law() -> None:
    rng = np.random.default_rng(2)
    qd, qdd = rng.normal(scale=0.3, size=(50, 3)), rng.normal(size=(50, 3))
    model = ActuatorModel(
        viscous=(0.5, 1.0, 2.0),
        coulomb=(1.0, 0.2, 3.0),
        coulomb_velocity=(0.01, 0.05, 0.02),
        rotor_inertia=(1e-4, 2e-4, 3e-4),
        gear_ratio=(50.0, 100.0, 10.0),
    )
    parts = actuator_torques(model, qd, qdd)
    # [Fv, Fc, Ia] per joint; armature = rotor inertia · gear ratio²
    values = np.array([[0.5, 1.0, 0.25], [1.0, 0.2, 2.0], [2.0, 3.0, 0.03]]).reshape(-1)
    Y = friction_regressor(qd, qdd, np.array([0.01, 0.05, 0.02]), rows=9, first=6)
    assert Y.shape == (50, 9, 9)
    assert np.all(Y[:, :6] == 0)  # no friction in the base wrench rows
    assert np.allclose(Y[:, 6:] @ values, parts.armature + parts.friction, rtol=1e-12)
    assert friction_names(["a"]) == ("Fv_a", "Fc_a", "Ia_a")


def test_motor_torques_with_noise_give_friction_within_two_percent(run: RunRecord) -> None:
    result = identify_dynamics(_with_noisy_motor(run), torques="motor", consistent=True)
    report = result.to_json()
    assert report["torques"] == "motor"
    assert min(body["pseudo_inertia_min_eigenvalue"] for body in report["bodies"]) > 0
    stored = run.attributes["actuator"]
    for k, row in enumerate(report["friction"]):
        assert row["Fv"] == pytest.approx(stored["viscous"][k], rel=0.02)
        assert row["Fc"] == pytest.approx(stored["coulomb"][k], rel=0.02)
        armature = ROTOR_INERTIA * stored["gear_ratio"][k] ** 2
        assert row["model"]["Ia"] == pytest.approx(armature)
        if row["determined"]["Ia"]:
            assert row["Ia"] == pytest.approx(armature, rel=0.05)
    joints = _joint_rows(result.signals)
    held_out = np.sqrt(np.mean(np.square(result.holdout_rms[joints])))
    assert held_out == pytest.approx(SIGMA, rel=0.1)


def test_measured_torques_fit_at_the_sensor_noise_with_physical_bodies(run: RunRecord) -> None:
    result = identify_dynamics(run, consistent=True)  # auto: the torque sensors
    report = result.to_json()
    assert report["torques"] == "measured"
    assert report["friction"] == []  # the sensor is on the link side: no friction in it
    assert all(body["pseudo_inertia_min_eigenvalue"] > 0 for body in report["bodies"])
    assert all(body["mass"] > 0 for body in report["bodies"])
    joints = _joint_rows(result.signals)
    held_out = np.sqrt(np.mean(np.square(result.holdout_rms[joints])))
    assert held_out == pytest.approx(SIGMA, rel=0.1)
    assert result.total_mass == pytest.approx(result.total_mass_model, rel=1e-3)


def test_friction_of_torques_without_it_is_refused(run: RunRecord) -> None:
    with pytest.raises(ParameterError, match="friction") as info:
        identify_dynamics(run, torques="measured", friction=True)
    assert info.value.parameter == "friction"


def test_text_summary_names_the_friction(run: RunRecord, tmp_path: Path) -> None:
    from aaria_pin.apps.identify.inertial_result import dynamics_summary

    report = identify_dynamics(run, torques="motor").to_json()
    lines = dynamics_summary(report)
    assert "torques fitted: motor" in lines
    assert sum(line.startswith("friction ") for line in lines) == len(run.joint_names)
