"""The pick-and-place run with joint hardware, its re-make, and the arm's joint limits."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import run_cli
from test_wrist_run import HARDWARE, expected_actuator, same_record

from aaria_pin.apps.arm.dims import get_arm_preset
from aaria_pin.apps.arm.preset import ARM_JOINTS, arm_joints, build_arm_model
from aaria_pin.apps.arm.run import PickPlaceRobot, pick_place_record, simulate_pick_place
from aaria_pin.apps.arm.task import Cylinder
from aaria_pin.core.imu_noise import noise_attributes
from aaria_pin.core.imu_presets import imu_preset
from aaria_pin.core.record import JOINT_RUN_TABLES, JOINT_SERIES
from aaria_pin.core.run import Payload
from aaria_pin.files.runfile import read_run

TASK = ["arm", "pick-place", "--cylinder", "0.35", "0.1", "--place", "0.2", "-0.3", "--rate", "50"]
PRISMATIC = "\ncounts_per_metre = 1.0e5\n"
"""The lift and the finger slide: their encoders count per metre."""


def test_a_pick_place_run_with_hardware_records_it_and_remakes_bit_for_bit(
    tmp_path: Path,
) -> None:
    hardware = tmp_path / "hw.toml"
    hardware.write_text(HARDWARE.replace("\noffset", PRISMATIC + "offset"))
    run_file, again = tmp_path / "pp.h5", tmp_path / "again.h5"
    code, _, stderr = run_cli(*TASK, "--hardware", str(hardware), "--imu-model", "bmi088",
                              "-o", str(run_file))  # fmt: skip
    assert code == 0, stderr
    record = read_run(run_file)
    samples = record.time.size
    for name in JOINT_SERIES:
        assert record.tables[name].shape == (samples, len(ARM_JOINTS)), name
    for name in JOINT_RUN_TABLES:
        assert record.tables[name].shape == (1, len(ARM_JOINTS)), name
    t = record.tables
    armature, friction = expected_actuator(record.qd, record.qdd)
    np.testing.assert_allclose(t["tau_armature"], armature, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(t["tau_friction"], friction, rtol=1e-12, atol=1e-15)
    motor = record.tau + t["tau_armature"] + t["tau_friction"]
    np.testing.assert_array_equal(t["tau_motor"], motor)
    assert record.attributes["encoder"]["counts_per_metre"] == 1.0e5
    assert record.attributes["noise_parameters"] == noise_attributes(imu_preset("bmi088"))
    code, _, stderr = run_cli("simulate", "--from", str(run_file), "-o", str(again))
    assert code == 0, stderr
    same_record(run_file, again)


def test_a_pick_place_run_without_hardware_has_no_joint_tables() -> None:
    record = pick_place_record(simulate_pick_place(Cylinder(0.35, 0.1), (0.2, -0.3), rate=20.0))
    assert record.tables == {}
    assert not {"noise_parameters", "encoder", "torque_sensor", "actuator"} & set(record.attributes)


def test_a_bad_hardware_file_is_one_line_exit_2_and_nothing_written(tmp_path: Path) -> None:
    (tmp_path / "hw.toml").write_text("[torque_sensor]\nbias = true\n")
    output = tmp_path / "pp.h5"
    with pytest.MonkeyPatch.context() as patch:
        patch.chdir(tmp_path)
        code, _, stderr = run_cli(*TASK, "--hardware", "hw.toml", "-o", str(output))
    assert code == 2, stderr
    assert stderr.count("\n") == 1 and "hw.toml: torque_sensor.bias is True; allowed:" in stderr
    assert not output.exists()


def test_the_arm_s_limits_are_its_urdf_s() -> None:
    dims = get_arm_preset("pick-place-arm")
    robot = build_arm_model(dims, (0.03, 0.12), free_flyer=True)
    lower, upper = PickPlaceRobot(robot, Payload(robot, np.zeros(2, dtype=bool))).limits
    joints = {j.name: j for j in arm_joints(dims)}
    np.testing.assert_array_equal(lower, [joints[name].lower for name in ARM_JOINTS])
    np.testing.assert_array_equal(upper, [joints[name].upper for name in ARM_JOINTS])
    assert lower[0] == 0.27 and upper[-1] == 0.12  # the lift's floor, the finger's opening
