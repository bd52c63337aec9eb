"""The wrist's run with joint hardware, its re-make, and the wrist's joint limits (issue 24)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import run_cli

from aaria_pin.apps.wrist.run import simulate_wrist, wrist_record, wrist_robot
from aaria_pin.core.excitation import FourierExcitation
from aaria_pin.core.record import JOINT_RUN_TABLES, JOINT_SERIES, SERIES
from aaria_pin.core.run import FourierMotion, RunSettings, simulate
from aaria_pin.errors import ParameterError
from aaria_pin.files.runfile import read_run

HARDWARE = """\
[encoder]
counts_per_revolution = 4096
noise = 1.0e-4
offset = 1.0e-3
[torque_sensor]
noise = 0.01
bias = 0.02
resolution = 0.001
[actuator]
rotor_inertia = 1.0e-4
gear_ratio = 50.0
viscous = 0.1
coulomb = 0.2
"""
"""A hardware file with every joint model on (armature 1e-4·50² = 0.25 kg·m²)."""


def expected_actuator(qd: np.ndarray, qdd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """HARDWARE's armature and friction torques, from the formula of issue 24 (smooth sign
    ``tanh(v/0.01)``, the default Coulomb velocity)."""
    return 0.25 * qdd, 0.1 * qd + 0.2 * np.tanh(qd / 0.01)


def same_record(a: Path, b: Path) -> None:
    first, second = read_run(a), read_run(b)
    for name in SERIES:
        assert np.array_equal(getattr(first, name), getattr(second, name)), name
    assert first.tables.keys() == second.tables.keys()
    for name, table in first.tables.items():
        assert np.array_equal(table, second.tables[name]), name
    for name in ("noise_parameters", "encoder", "torque_sensor", "actuator"):
        assert first.attributes[name] == second.attributes[name], name


def test_a_wrist_run_with_hardware_records_it_and_remakes_bit_for_bit(tmp_path: Path) -> None:
    (tmp_path / "hw.toml").write_text(HARDWARE)
    run_file, again = tmp_path / "wrist.h5", tmp_path / "again.h5"
    code, _, stderr = run_cli("wrist", "simulate", "30", "20", "-10",
                              "--speed", "90", "--acceleration", "600", "--hardware",
                              str(tmp_path / "hw.toml"), "-o", str(run_file))  # fmt: skip
    assert code == 0, stderr
    record = read_run(run_file)
    samples = record.time.size
    for name in JOINT_SERIES:
        assert record.tables[name].shape == (samples, 3), name
    for name in JOINT_RUN_TABLES:
        assert record.tables[name].shape == (1, 3), name
    t = record.tables
    armature, friction = expected_actuator(record.qd, record.qdd)
    np.testing.assert_allclose(t["tau_armature"], armature, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(t["tau_friction"], friction, rtol=1e-12, atol=1e-15)
    motor = record.tau + t["tau_armature"] + t["tau_friction"]
    np.testing.assert_array_equal(t["tau_motor"], motor)
    assert np.abs(t["tau_friction"]).max() > 0.1  # the joints moved
    assert record.attributes["encoder"]["counts_per_revolution"] == 4096.0
    assert record.attributes["actuator"]["gear_ratio"] == 50.0
    code, _, stderr = run_cli("simulate", "--from", str(run_file), "-o", str(again))
    assert code == 0, stderr
    same_record(run_file, again)


def test_a_wrist_run_without_hardware_has_no_joint_tables() -> None:
    record = wrist_record(simulate_wrist(np.radians([20.0, 10.0, 5.0]), duration=3.0))
    assert set(record.tables) == {"targets"}
    assert not {"encoder", "torque_sensor", "actuator"} & set(record.attributes)


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ("[encoder]\nnoize = 1.0\n", "hw.toml: unknown key encoder.noize; allowed:"),
        ("[actuator]\nviscous = -1.0\n", "hw.toml: actuator.viscous is -1; allowed: finite"),
    ],
)
def test_a_bad_hardware_file_is_one_line_exit_2_and_nothing_written(
    tmp_path: Path, table: str, message: str
) -> None:
    (tmp_path / "hw.toml").write_text(table)
    output = tmp_path / "wrist.h5"
    with pytest.MonkeyPatch.context() as patch:
        patch.chdir(tmp_path)
        code, _, stderr = run_cli("wrist", "simulate", "30", "20", "10", "--hardware", "hw.toml",
                                  "-o", str(output))  # fmt: skip
    assert code == 2, stderr
    assert stderr.count("\n") == 1 and message in stderr, stderr
    assert not output.exists()


def test_the_wrist_s_limits_are_its_model_s() -> None:
    lower, upper = wrist_robot().limits
    np.testing.assert_array_equal(lower, np.full(3, -2 * np.pi))
    np.testing.assert_array_equal(upper, np.full(3, 2 * np.pi))


def test_a_target_beyond_the_wrist_s_limit_is_refused_naming_joint_time_value_limit() -> None:
    simulate_wrist(np.array([2 * np.pi, 0.0, 0.0]), speed=np.radians(180.0), start=0.0)  # at it
    with pytest.raises(ParameterError) as caught:
        simulate_wrist(np.array([0.0, -7.0, 0.0]), speed=np.radians(180.0), start=0.0)
    message = str(caught.value)
    assert caught.value.parameter == "targets" and "\n" not in message
    # 180 deg/s with a 80 deg/s² trapezoid reaches -2π = -6.28319 a little after t = 6.3 s
    assert message.startswith("targets takes joint joint2 to -6.2") and " at t = " in message
    assert "allowed: within its limits [-6.28319, 6.28319]" in message


def test_the_cli_refuses_a_target_beyond_the_limit_and_writes_nothing(tmp_path: Path) -> None:
    output = tmp_path / "wrist.h5"
    code, _, stderr = run_cli("wrist", "simulate", "370", "0", "0", "-o", str(output))
    assert code == 2 and stderr.count("\n") == 1 and "joint joint1" in stderr, stderr
    assert "6.28319" in stderr and not output.exists()


def test_a_fourier_excitation_outside_the_limits_is_refused() -> None:
    a = np.zeros((3, 1))
    a[2, 0] = 2.0  # joint3: q = 7 + (2 / w) sin(w t), w = 2π·0.5: up to 7.64 rad, beyond 2π
    outside = FourierExcitation(a, np.zeros((3, 1)), np.array([0.0, 0.0, 7.0]), 0.5)
    settings = RunSettings(duration=1.0, rate=100.0, noise=False)
    with pytest.raises(ParameterError) as caught:
        simulate(wrist_robot(), FourierMotion(outside), settings)
    message = str(caught.value)
    assert caught.value.parameter == "motion"
    assert message == (
        "motion takes joint joint3 to 7 at t = 0 s; allowed: within its limits "
        "[-6.28319, 6.28319] (beyond its upper limit 6.28319)"
    )
    inside = FourierExcitation(a, np.zeros((3, 1)), np.array([0.0, 0.0, 5.0]), 0.5)
    record = simulate(wrist_robot(), FourierMotion(inside), settings)
    assert record.q[:, 2].max() == pytest.approx(5.0 + 2.0 / np.pi, rel=1e-3)
