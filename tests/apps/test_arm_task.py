"""The pick-and-place task: path, grasp positions, payload torques, run file, CLI."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from click.testing import CliRunner

from aaria_pin.apps.arm.payload import payload_inertia, with_payload
from aaria_pin.apps.arm.preset import ArmDimensions, build_arm_model, grasp_offset
from aaria_pin.apps.arm.run import simulate_pick_place, write_pick_place_run
from aaria_pin.apps.arm.task import PHASES, Cylinder
from aaria_pin.cli import main
from aaria_pin.errors import ParameterError
from tests.apps.test_arm_checks import rnea_at_rest

DIMS = ArmDimensions()


@pytest.fixture(scope="module")
def run():
    return simulate_pick_place(Cylinder(0.5, 0.2, mass=1.2), (-0.3, 0.4))


def test_static_payload_share_is_the_hand_computation() -> None:
    from aaria_pin.core.trajectory import JointTrajectory

    robot = build_arm_model(DIMS)
    model = robot.model
    cylinder = Cylinder(0.0, 0.0, radius=0.04, height=0.14, mass=0.8)
    payload = payload_inertia(DIMS, cylinder)
    q = np.array([0.5, 0.7, -1.1, 0.4, 0.9, -0.3, 0.08])  # hand tilted: the moment matters
    zero = np.zeros(7)
    still = JointTrajectory(np.zeros(1), q[None], zero[None], zero[None])
    tau, _ = rnea_at_rest(robot, still, payload)
    tau_free, _ = rnea_at_rest(robot, still)
    # by hand: the weight m·g at the payload's centre, as a wrench about the hand frame's origin
    data = model.createData()
    hand = model.getFrameId("hand", pin.FrameType.BODY)
    J = pin.computeFrameJacobian(model, data, q, hand, pin.LOCAL_WORLD_ALIGNED)
    pin.framesForwardKinematics(model, data, q)
    oMh = data.oMf[hand]
    offset = grasp_offset(DIMS, cylinder.radius, cylinder.height)
    com = oMh.rotation @ offset[:3, 3]  # from the hand origin
    weight = np.array([0.0, 0.0, -9.81 * cylinder.mass])
    wrench = np.concatenate([-weight, np.cross(com, -weight)])  # what the hand must supply
    np.testing.assert_allclose(tau[0] - tau_free[0], J.T @ wrench, atol=1e-10)
    assert abs(tau[0, 0] - tau_free[0, 0]) == pytest.approx(9.81 * 0.8)  # the lift carries it


def test_run_torques_carry_the_cylinder_only_where_held(run) -> None:
    from aaria_pin.core.trajectory import JointTrajectory

    path = run.path
    trajectory = JointTrajectory(path.time, path.q, path.qd, path.qdd)
    payload = payload_inertia(run.dims, run.cylinder)
    tau_loaded, wrench_loaded = rnea_at_rest(run.robot, trajectory, payload)
    tau_bare, wrench_bare = rnea_at_rest(run.robot, trajectory)
    held = path.held
    assert 0 < held.sum() < held.size
    np.testing.assert_array_equal(run.tau[held], tau_loaded[held])
    np.testing.assert_array_equal(run.tau[~held], tau_bare[~held])
    np.testing.assert_array_equal(run.base_wrench[held], wrench_loaded[held])
    np.testing.assert_array_equal(run.base_wrench[~held], wrench_bare[~held])
    np.testing.assert_array_equal(run.tau_free, tau_bare)
    # the lift carries the cylinder's weight while held (at rest in z: the grasp phase's end)
    assert np.abs(run.tau[held, 0] - tau_bare[held, 0]).max() >= 9.81 * run.cylinder.mass


def test_path_phases_and_grasp_positions(run) -> None:
    path = run.path
    assert path.boundaries.shape == (len(PHASES), 2)
    # C¹ path: finite differences of q match qd
    dt = path.time[1] - path.time[0]
    np.testing.assert_allclose(np.gradient(path.q, dt, axis=0)[1:-1], path.qd[1:-1], atol=2e-3)
    grasp = np.searchsorted(path.time, path.boundaries[2, 0])
    np.testing.assert_allclose(run.tool_pose[grasp, :3, 3], [0.5, 0.2, 0.06], atol=1e-9)
    release = np.searchsorted(path.time, path.boundaries[6, 0])
    np.testing.assert_allclose(run.tool_pose[release, :3, 3], [-0.3, 0.4, 0.06], atol=1e-9)
    np.testing.assert_allclose(
        run.tool_pose[:, :3, 2], np.tile([0, 0, -1], (path.time.size, 1)), atol=1e-9
    )
    assert np.all(np.abs(path.q[:, 2]) <= np.pi)  # the elbow never passes the pillar side
    low, high = DIMS.lift_range
    assert np.all((path.q[:, 0] >= low - 1e-12) & (path.q[:, 0] <= high + 1e-12))


def test_payload_changes_torques_only_while_held(run) -> None:
    difference = np.abs(run.tau - run.tau_free).max(axis=1)
    assert np.all(difference[~run.path.held] == 0.0)
    assert np.all(difference[run.path.held] > 1.0)  # at least the lift carries m·g


def test_with_payload_adds_mass_to_the_hand() -> None:
    model = build_arm_model(DIMS).model
    payload = payload_inertia(DIMS, Cylinder(0.0, 0.0, mass=2.0))
    loaded = with_payload(model, payload)
    j = model.getJointId("hand_roll")
    assert loaded.inertias[j].mass == pytest.approx(model.inertias[j].mass + 2.0)
    with pytest.raises(ParameterError):
        with_payload(model, payload, "wrist")


def test_run_file_round_trip(run, tmp_path) -> None:
    from aaria_pin.files.runfile import read_run

    path = write_pick_place_run(tmp_path / "run.h5", run)
    record = read_run(path)
    np.testing.assert_array_equal(record.tau, run.tau)
    np.testing.assert_array_equal(record.tool_pose, run.tool_pose)
    assert record.attributes["phases"] == list(PHASES)
    assert "meshes/hand.stl" in record.urdf


def test_cli_refuses_unreachable_targets_and_writes_nothing(tmp_path) -> None:
    out = tmp_path / "run.h5"
    result = CliRunner().invoke(
        main,
        ["arm", "pick-place", "--cylinder", "0.9", "0.2", "--place", "0.3", "0.3", "-o", str(out)],
    )
    assert result.exit_code == 2
    assert "reachable annulus" in result.output
    assert not out.exists()
    result = CliRunner().invoke(
        main,
        [
            "arm",
            "pick-place",
            "--cylinder",
            "0.4",
            "0.2",
            "--place",
            "0.3",
            "0.3",
            "--height",
            "0.05",
            "-o",
            str(out),
        ],
    )
    assert result.exit_code == 2 and "fingertips" in result.output and not out.exists()


@pytest.mark.slow
def test_cli_pick_place_writes_run_and_pictures(tmp_path) -> None:
    out, sheet, gif = tmp_path / "run.h5", tmp_path / "poses.png", tmp_path / "task.gif"
    result = CliRunner().invoke(
        main,
        [
            "arm",
            "pick-place",
            "--cylinder",
            "0.3",
            "-0.4",
            "--place",
            "-0.5",
            "0.1",
            "--mass",
            "0.7",
            "-o",
            str(out),
            "--sheet",
            str(sheet),
            "--animation",
            str(gif),
            "--fps",
            "2",
        ],
    )
    assert result.exit_code == 0, result.output
    assert out.stat().st_size > 0
    assert sheet.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert gif.read_bytes()[:6] == b"GIF89a"
    result = CliRunner().invoke(main, ["arm", "urdf", "-o", str(tmp_path / "arm")])
    assert result.exit_code == 0
    assert (tmp_path / "arm" / "meshes" / "upper_arm.stl").is_file()


def test_the_run_record_in_both_formats_and_its_remake(run, tmp_path) -> None:
    from aaria_pin.apps.arm.run import pick_place_record
    from aaria_pin.apps.remake import remake_run
    from aaria_pin.files.runfile import read_run

    record = pick_place_record(run)
    assert record.attributes["kind"] == "pick-place"
    assert record.attributes["robot"] == "pick-place-arm"
    samples = run.path.time.size
    assert record.imu.shape == (samples, 0, 6) and record.imu_mounts == ()
    np.testing.assert_array_equal(record.base_pose, np.broadcast_to(np.eye(4), (samples, 4, 4)))
    assert record.attributes["rate"] == 100.0
    for suffix in (".h5", ".mat"):
        path = write_pick_place_run(tmp_path / f"run{suffix}", run)
        stored = read_run(path)
        np.testing.assert_array_equal(stored.tau, run.tau)
        assert stored.joint_names == record.joint_names
        remade = remake_run(path)
        for name in ("q", "tau", "base_wrench", "tool_pose"):
            np.testing.assert_array_equal(getattr(remade, name), getattr(record, name))
