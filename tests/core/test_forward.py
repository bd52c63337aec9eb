from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from click.testing import CliRunner

from aaria_pin.aaria.dh_robot import build_dh_robot
from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.cli import main
from aaria_pin.core.forward import forward_simulate
from aaria_pin.core.trajectory import BaseMotion, sample_times
from aaria_pin.errors import ParameterError
from aaria_pin.files.runfile import write_run


@pytest.mark.parametrize("name", ["aaria-fig2", "aaria-fig3"])
def test_feeding_back_rnea_torques_reproduces_the_motion(name: str) -> None:
    preset = get_preset(name)
    settings = {"duration": 1.0, "rate": 500.0, "noise": False}
    prescribed = simulate_run(preset.table, preset.joint_table, preset.base_table, **settings)
    driven = simulate_run(
        preset.table, preset.joint_table, preset.base_table, torques=prescribed.tau, **settings
    )
    # RK4, 4 steps per sample, torques and base linear between samples: bound over 1 s
    np.testing.assert_allclose(driven.q, prescribed.q, atol=2e-3)
    np.testing.assert_allclose(driven.qd, prescribed.qd, atol=2e-2)
    assert driven.attributes["drive"] == "torque"
    np.testing.assert_allclose(driven.tau, prescribed.tau, atol=1e-6)  # RNEA of the result


def _energy(model: pin.Model, q: np.ndarray, v: np.ndarray) -> np.ndarray:
    data = model.createData()
    return np.array(
        [
            pin.computeKineticEnergy(model, data, qk, vk)
            + pin.computePotentialEnergy(model, data, qk)
            for qk, vk in zip(q, v, strict=True)
        ]
    )


@pytest.mark.slow
@pytest.mark.parametrize("gravity", [False, True])
def test_energy_is_conserved_without_torques(gravity: bool) -> None:
    robot = build_dh_robot(get_preset("aaria-fig3").table).model(moving_base=True)
    if not gravity:
        robot.model.gravity.linear = np.zeros(3)
    time = sample_times(10.0, 200)
    base = BaseMotion.resting(time.size)
    q0 = np.array([0.0, 0.02, -0.03, 0.3, -0.5])
    v0 = np.array([0.05, -0.1, 0.08, 0.6, 0.9])
    run = forward_simulate(robot, base, np.zeros((time.size, 5)), time, q0, v0)
    full = np.hstack([np.tile([0, 0, 0, 0, 0, 0, 1.0], (time.size, 1)), run.q])
    energy = _energy(robot.model, full, np.hstack([np.zeros((time.size, 6)), run.qd]))
    drift = np.abs(energy - energy[0]).max() / max(abs(energy[0]), 1.0)
    assert drift < 1e-4, drift  # stated bound: 0.01 % over 10 s at 200 Hz, 4 RK4 steps each


def test_bad_torque_tables() -> None:
    preset = get_preset("aaria-fig2")
    settings = {"duration": 0.1, "rate": 100.0, "noise": False}
    with pytest.raises(ParameterError, match=r"shape \(11, 5\); allowed: \(11 samples, 6 joints\)"):
        simulate_run(preset.table, torques=np.zeros((11, 5)), **settings)
    with pytest.raises(ParameterError, match=r"shape \(10, 6\)"):
        simulate_run(preset.table, torques=np.zeros((10, 6)), **settings)
    bad = np.zeros((11, 6))
    bad[3, 2] = np.nan
    with pytest.raises(ParameterError, match="sample 3, joint 3 is nan"):
        simulate_run(preset.table, torques=bad, **settings)


def test_cli_drive_torque(tmp_path: Path) -> None:
    preset = get_preset("aaria-fig3")
    record = simulate_run(
        preset.table, preset.joint_table, preset.base_table, duration=0.2, rate=100.0, noise=False
    )
    write_run(tmp_path / "ref.h5", record)
    np.save(tmp_path / "tau.npy", record.tau)
    for source in ("ref.h5", "tau.npy"):
        result = CliRunner().invoke(
            main,
            [
                "simulate",
                "--preset",
                "aaria-fig3",
                "--duration",
                "0.2",
                "--rate",
                "100",
                "--no-noise",
                "--drive",
                "torque",
                "--torques",
                str(tmp_path / source),
                "-o",
                str(tmp_path / f"driven_{source}.h5"),
            ],
        )
        assert result.exit_code == 0, result.output
    missing = CliRunner().invoke(
        main,
        ["simulate", "--preset", "aaria-fig3", "--drive", "torque", "-o", str(tmp_path / "x.h5")],
    )
    assert missing.exit_code == 2 and "--torques FILE" in missing.stderr


def test_the_actuator_adds_its_armature_and_friction_as_pinocchio_does() -> None:
    """The first acceleration equals Pinocchio's ABA with ``model.armature`` set."""
    from aaria_pin.core.joint_sensors import ActuatorModel

    robot = build_dh_robot(get_preset("aaria-fig3").table).model(moving_base=False)
    motors = ActuatorModel(rotor_inertia=[1e-5, 2e-5, 3e-5, 1e-5, 2e-5], gear_ratio=60.0,
                           viscous=0.7, coulomb=0.2, coulomb_velocity=0.5)  # fmt: skip
    time = sample_times(0.01, 100)
    q0 = np.array([0.01, 0.02, -0.03, 0.3, -0.5])
    v0 = np.array([0.05, -0.1, 0.08, 0.6, 0.9])
    tau = np.tile([1.0, -2.0, 0.5, 0.3, -0.1], (time.size, 1))
    run = forward_simulate(robot, BaseMotion.resting(time.size), tau, time, q0, v0, actuator=motors)
    model = pin.Model(robot.model)
    armature = np.array([1e-5, 2e-5, 3e-5, 1e-5, 2e-5]) * 60.0**2
    model.armature = armature
    friction = 0.7 * v0 + 0.2 * np.tanh(v0 / 0.5)
    expected = pin.aba(model, model.createData(), q0, v0, tau[0] - friction)
    np.testing.assert_allclose(run.qdd[0], expected, rtol=1e-10, atol=1e-12)
    assert np.array_equal(robot.model.armature, np.zeros(5))  # the shared model is left alone


def test_viscous_friction_takes_the_energy_it_dissipates() -> None:
    """No torque: the energy, rotors included, falls by ``∫ viscous·qd² dt``."""
    from aaria_pin.core.joint_sensors import ActuatorModel

    robot = build_dh_robot(get_preset("aaria-fig3").table).model(moving_base=False)
    motors = ActuatorModel(rotor_inertia=2e-5, gear_ratio=50.0, viscous=0.05)
    time = sample_times(2.0, 200)
    q0 = np.array([0.0, 0.02, -0.03, 0.3, -0.5])
    v0 = np.array([0.05, -0.1, 0.08, 0.6, 0.9])
    zeros = np.zeros((time.size, 5))
    run = forward_simulate(
        robot, BaseMotion.resting(time.size), zeros, time, q0, v0, actuator=motors
    )
    energy = _energy(robot.model, run.q, run.qd) + 0.5 * (2e-5 * 50.0**2 * run.qd**2).sum(axis=1)
    power = 0.05 * (run.qd**2).sum(axis=1)
    dissipated = np.concatenate([[0.0], np.cumsum((power[1:] + power[:-1]) / 2 * np.diff(time))])
    assert dissipated[-1] > 1e-3  # the friction matters over the run
    np.testing.assert_allclose(energy[0] - energy, dissipated, atol=1e-3 * dissipated[-1])


def test_a_motor_saturates_at_its_torque_limit() -> None:
    """Torques beyond a motor's limit act as the limit itself: a drive cannot give more."""
    from aaria_pin.core.joint_sensors import ActuatorModel

    robot = build_dh_robot(get_preset("aaria-fig3").table).model(moving_base=False)
    limit = np.array([3.0, 2.0, 1.0, 2.0, 1.0])
    motors = ActuatorModel(viscous=0.1, torque_limit=tuple(limit))
    time = sample_times(0.2, 100)
    q0, v0 = np.zeros(5), np.zeros(5)
    base = BaseMotion.resting(time.size)
    pushed = np.tile(10.0 * limit * np.array([1, -1, 1, -1, 1]), (time.size, 1))
    at_limit = np.tile(limit * np.array([1, -1, 1, -1, 1]), (time.size, 1))
    run = forward_simulate(robot, base, pushed, time, q0, v0, actuator=motors)
    expected = forward_simulate(robot, base, at_limit, time, q0, v0, actuator=motors)
    np.testing.assert_array_equal(run.q, expected.q)
    free = forward_simulate(robot, base, pushed, time, q0, v0)  # no motor: no limit
    assert np.abs(free.q - run.q).max() > 1e-3
