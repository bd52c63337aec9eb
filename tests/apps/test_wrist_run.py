from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pinocchio as pin
import pytest
from click.testing import CliRunner
from conftest import Rx, Rz, Tz, run_cli

from aaria_pin.aaria.presets import APPENDIX_B_PARTS
from aaria_pin.apps.wrist.run import report_wrist, simulate_wrist, wrist_record, wrist_robot
from aaria_pin.apps.wrist.wrist_kinematics import wrist_fk
from aaria_pin.cli import main
from aaria_pin.core.excitation import FourierExcitation
from aaria_pin.core.record import JOINT_RUN_TABLES, JOINT_SERIES, SERIES
from aaria_pin.core.run import FourierMotion, RunSettings, simulate
from aaria_pin.errors import ParameterError
from aaria_pin.files.runfile import read_run


def test_model_carries_the_appendix_b_parts() -> None:
    model = report_wrist().model().model
    masses = [inertia.mass for inertia in model.inertias[1:]]
    np.testing.assert_allclose(masses, [APPENDIX_B_PARTS[f"link{i}"][2] for i in (1, 2, 3)])
    np.testing.assert_allclose(model.inertias[2].lever, [0.08277, 0.02, 0.0])


def test_motion_reaches_the_targets_and_the_tool_pose_is_equation_9() -> None:
    targets = np.radians([60.0, 45.0, -30.0])
    run = simulate_wrist(targets)
    np.testing.assert_allclose(run.q[-1], targets, atol=1e-12)
    assert np.all(run.q[run.time <= 2.0] == 0.0)
    for k in range(0, run.time.size, 50):
        np.testing.assert_allclose(run.tool_pose[k], wrist_fk(run.q[k]), atol=1e-12)


def test_torques_balance_the_energy() -> None:
    run = simulate_wrist(np.radians([80.0, 60.0, -45.0]), rate=1000.0)
    model = report_wrist().model().model
    data = model.createData()
    energy = np.array(
        [
            pin.computeKineticEnergy(model, data, q, v) + pin.computePotentialEnergy(model, data, q)
            for q, v in zip(run.q, run.qd, strict=True)
        ]
    )
    dt = run.time[1] - run.time[0]
    power = np.einsum("ti,ti->t", run.tau, run.qd)
    work = np.concatenate([[0.0], np.cumsum((power[1:] + power[:-1]) / 2) * dt])
    assert np.ptp(energy) > 0.1  # the check is not trivial
    np.testing.assert_allclose(energy - energy[0], work, atol=1e-5)


def test_static_torque_by_hand() -> None:
    run = simulate_wrist([0.0, np.pi / 2, 0.0], speed=10.0, acceleration=100.0, duration=3.0)
    still = run.time > 2.5
    np.testing.assert_allclose(run.tau[still, 0], 0.0, atol=1e-12)  # a vertical axis: no load
    assert np.all(np.abs(run.tau[still, 1]) > 0.05)
    # By hand: the report's Table 1 (standard DH, alpha = -90°, 90°, 0°, d3 = 132 mm) and its
    # Appendix B parts 3 and 4 (mass [kg], centre of mass [mm] in the link's post-joint frame,
    # Rz(theta_i)·Tz(d_i)); tau_j = -z_j · sum over the links j moves of (c_i - o_j) × m_i·g.
    q, alpha, d = [0.0, np.pi / 2, 0.0], [-np.pi / 2, np.pi / 2, 0.0], [0.0, 0.0, 0.132]
    parts = {2: (0.29058, [82.77, 20.0, 0.0]), 3: (0.16480, [-0.00039, 28.38, -0.00035])}
    joint_frames, post_joint, T = [], {}, np.eye(4)
    for i in range(3):
        joint_frames.append(T.copy())  # joint i+1 turns about this frame's z axis
        T = T @ Rz(q[i]) @ Tz(d[i])
        post_joint[i + 1] = T.copy()
        T = T @ Rx(alpha[i])
    expected = []
    for j in (1, 2, 3):
        origin, axis = joint_frames[j - 1][:3, 3], joint_frames[j - 1][:3, 2]
        moment = np.zeros(3)
        for i, (mass, com_mm) in parts.items():
            if i >= j:
                com = (post_joint[i] @ np.r_[np.array(com_mm) * 1e-3, 1.0])[:3]
                moment += np.cross(com - origin, mass * np.array([0.0, 0.0, -9.81]))
        expected.append(-axis @ moment)
    np.testing.assert_allclose(run.tau[still], np.tile(expected, (still.sum(), 1)), atol=1e-12)


def test_cli_writes_the_run(tmp_path) -> None:
    out = tmp_path / "wrist.h5"
    result = CliRunner().invoke(main, ["wrist", "simulate", "60", "-45", "10", "-o", str(out)])
    assert result.exit_code == 0, result.output
    with h5py.File(out) as handle:
        assert handle["tau"].shape[1] == 3 and handle["tool_pose"].shape[1:] == (4, 4)
        np.testing.assert_allclose(handle["q"][-1], np.radians([60, -45, 10]), atol=1e-12)
    bad = CliRunner().invoke(
        main, ["wrist", "simulate", "1", "2", "3", "--speed", "-3", "-o", str(tmp_path / "x.h5")]
    )
    assert bad.exit_code == 2 and "speed" in bad.stderr
    assert not (tmp_path / "x.h5").exists()


def test_bad_targets() -> None:
    with pytest.raises(ParameterError, match="targets"):
        simulate_wrist([1.0, np.nan, 0.0])


def test_the_preset_urdf_carries_the_parts_too(tmp_path) -> None:
    import xml.etree.ElementTree as ET

    out = tmp_path / "wrist.urdf"
    result = CliRunner().invoke(main, ["urdf", "--preset", "spherical-wrist", "-o", str(out)])
    assert result.exit_code == 0, result.output
    masses = {
        link.get("name"): float(link.find("inertial/mass").get("value"))
        for link in ET.parse(out).getroot().iter("link")
        if link.find("inertial") is not None
    }
    assert masses["link2"] == pytest.approx(0.29058)
    assert masses["base"] == pytest.approx(0.05987)


def test_the_run_record_fixed_mount_imus_and_remake(tmp_path) -> None:
    import xml.etree.ElementTree as ET

    from aaria_pin.apps.remake import remake_run
    from aaria_pin.apps.wrist.run import wrist_record, write_wrist_run
    from aaria_pin.files.runfile import read_run

    run = simulate_wrist(np.radians([60.0, 45.0, -30.0]), duration=4.0, rate=50.0)
    record = wrist_record(run)
    assert record.attributes["kind"] == "wrist" and record.attributes["robot"] == "spherical-wrist"
    assert record.joint_names == ("joint1", "joint2", "joint3")
    np.testing.assert_array_equal(record.base_pose, np.broadcast_to(np.eye(4), (201, 4, 4)))
    np.testing.assert_array_equal(record.tables["targets"], np.radians([60.0, 45.0, -30.0]))
    # At rest before the start, the mount carries the weight of every link of the URDF.
    mass = sum(
        float(link.find("inertial/mass").get("value"))
        for link in ET.fromstring(record.urdf).iter("link")
        if link.find("inertial") is not None
    )
    still = record.time < 2.0
    np.testing.assert_allclose(
        record.base_wrench[still, :3], np.tile([0, 0, mass * 9.81], (still.sum(), 1)), atol=1e-9
    )
    np.testing.assert_allclose(record.base_wrench[still, 5], 0.0, atol=1e-12)
    assert record.imu_names[:2] == ("imu_base", "imu_tool") and len(record.imu_names) == 8
    np.testing.assert_allclose(  # a still base: no rotation, gravity's reaction straight up
        record.imu_signals("imu_base"), np.tile([0, 0, 0, 0, 0, 9.81], (201, 1)), atol=1e-12
    )
    for suffix in (".h5", ".mat"):
        path = write_wrist_run(tmp_path / f"wrist{suffix}", run)
        stored = read_run(path)
        np.testing.assert_array_equal(stored.tau, run.tau)
        remade = remake_run(path)
        for name in ("q", "tau", "base_wrench", "tool_pose", "imu"):
            np.testing.assert_array_equal(getattr(remade, name), getattr(record, name))


# --- issue 24: joint hardware and the model's joint limits ---

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
[current_sensor]
torque_constant = 0.05
noise = 0.01
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
    for name in ("noise_parameters", "encoder", "torque_sensor", "actuator", "current_sensor"):
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
