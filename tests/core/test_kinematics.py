"""IMU signals: fast path vs Pinocchio per sample, and vs finite differences of paper matrices."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import paper_frames
from pinocchio_oracles import reference_frame_poses, reference_imu_signals

from aaria_pin.aaria.dh_robot import build_dh_robot
from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.aaria.sine_tables import (
    base_motion,
    default_base_table,
    default_joint_table,
    joint_trajectory,
)
from aaria_pin.core.kinematics import imu_signals
from aaria_pin.core.trajectory import sample_times

G = np.array([0.0, 0.0, -9.81])
BASE_6X4 = np.array(
    [
        [0.04, 0.1, 1.1, 0.2],
        [0.03, -0.2, 0.9, 0.0],
        [0.05, 0.0, 1.3, 1.0],
        [0.2, 0.1, 0.8, 0.4],
        [0.15, -0.1, 1.2, 0.0],
        [0.25, 0.3, 0.6, 2.0],
    ]
)


@pytest.mark.parametrize("name", ["aaria-fig2", "aaria-fig3"])
@pytest.mark.parametrize("base_table", [default_base_table(), BASE_6X4])
def test_fast_path_equals_pinocchio_per_sample(name: str, base_table: np.ndarray) -> None:
    robot = build_dh_robot(get_preset(name).table)
    model = robot.model(moving_base=True)
    time = sample_times(3.0, 40)
    trajectory = joint_trajectory(default_joint_table(robot.chain), robot.chain, time)
    base = base_motion(base_table, time)
    frames = [*model.sensor_frames, "tool_tip", "link3"]
    fast = imu_signals(model, base, trajectory, frames)
    reference = reference_imu_signals(model, base, trajectory, frames)
    np.testing.assert_allclose(fast, reference, rtol=0, atol=1e-9)


def test_fixed_base_model_equals_pinocchio() -> None:
    robot = build_dh_robot(get_preset("spherical-wrist").table, "standard")
    model = robot.model(moving_base=False)
    time = sample_times(2.0, 30)
    q = np.column_stack([np.sin(time), np.cos(2 * time), 0.5 * time])
    qd = np.column_stack([np.cos(time), -2 * np.sin(2 * time), 0.5 + 0 * time])
    qdd = np.column_stack([-np.sin(time), -4 * np.cos(2 * time), 0 * time])
    from aaria_pin.core.trajectory import BaseMotion, JointTrajectory

    trajectory = JointTrajectory(time, q, qd, qdd)
    base = BaseMotion.resting(time.size)
    np.testing.assert_allclose(
        imu_signals(model, base, trajectory, model.sensor_frames),
        reference_imu_signals(model, base, trajectory, model.sensor_frames),
        atol=1e-9,
    )


# --- an independent computation: poses from the paper's matrices, derivatives by differences ---


def _world_poses(table, senJ, senB, mounts, t: float) -> list[np.ndarray | None]:
    """World poses of the 14 IMU slots at time t (None for empty modules)."""
    T_base, modules, T_tool = paper_frames(table, senJ, senB, t)
    poses: list[np.ndarray | None] = [T_base @ mounts[0], T_tool @ mounts[1]]
    for i, T in enumerate(modules):
        poses += [None, None] if T is None else [T @ mounts[2 + 2 * i], T @ mounts[3 + 2 * i]]
    return poses


@pytest.mark.parametrize("name", ["aaria-fig2", "aaria-fig3"])
def test_imu_signals_against_finite_differences_of_paper_matrices(name: str) -> None:
    table = get_preset(name).table
    record = simulate_run(table, base_table=BASE_6X4, duration=2.0, rate=5.0, noise=False)
    h = 1e-4
    for k in (1, 4, 9):
        t = record.time[k]
        before, now, after = (
            _world_poses(
                table, record.tables["senSenJ"], record.tables["senSenB"], record.imu_mount, t + s
            )
            for s in (-h, 0.0, h)
        )
        for slot in range(14):
            columns = record.view("senSen")[k, 7 + 6 * slot : 13 + 6 * slot]
            if now[slot] is None:
                assert not columns.any()
                continue
            R, Rm, Rp = now[slot][:3, :3], before[slot][:3, :3], after[slot][:3, :3]
            skew = R.T @ (Rp - Rm) / (2 * h)
            omega = (
                np.array(
                    [skew[2, 1] - skew[1, 2], skew[0, 2] - skew[2, 0], skew[1, 0] - skew[0, 1]]
                )
                / 2
            )
            accel = (after[slot][:3, 3] - 2 * now[slot][:3, 3] + before[slot][:3, 3]) / h**2
            np.testing.assert_allclose(columns[:3], omega, atol=1e-6)
            np.testing.assert_allclose(columns[3:], R.T @ (accel - G), atol=2e-4)
        np.testing.assert_allclose(
            record.tool_pose[k], now[1] @ np.linalg.inv(record.imu_mount[1]), atol=1e-12
        )


def test_resting_imus_read_gravity_in_their_axes() -> None:
    table = get_preset("aaria-fig2").table
    senJ = np.zeros((8, 5))
    senJ[:6, 2] = [0.03, 0.4, -0.7, 1.2, -0.02, 2.0]
    senB = np.array([[0.0, 0.5, 0.0, 0.0], [0.0, 0.3, 0.0, 0.0]])
    record = simulate_run(table, senJ, senB, duration=0.5, rate=10, noise=False)
    poses = _world_poses(table, senJ, senB, record.imu_mount, 0.0)
    for slot, pose in enumerate(poses):
        columns = record.view("senSen")[:, 7 + 6 * slot : 13 + 6 * slot]
        np.testing.assert_allclose(columns[:, :3], 0.0, atol=1e-12)
        np.testing.assert_allclose(
            columns[:, 3:], np.tile(pose[:3, :3].T @ [0, 0, 9.81], (6, 1)), atol=1e-12
        )


_ODD_AXES_URDF = """<?xml version="1.0"?>
<robot name="odd">
  <link name="base"><inertial><mass value="1"/><origin xyz="0 0 0.1"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="a"><inertial><mass value="2"/><origin xyz="0.2 0 0"/>
    <inertia ixx="0.02" iyy="0.03" izz="0.04" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="b"><inertial><mass value="1"/><origin xyz="0 0.1 0"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="c"><inertial><mass value="1"/><origin xyz="0 0 0.1"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="imu_c"/><link name="tool_tip"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="a"/>
    <origin xyz="0.1 0.2 0.3" rpy="0.3 -0.2 0.5"/><axis xyz="0.6 0 0.8"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="j2" type="prismatic"><parent link="a"/><child link="b"/>
    <origin xyz="0.4 0 0" rpy="0 0.4 0"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="j3" type="revolute"><parent link="b"/><child link="c"/>
    <origin xyz="0 0.3 0" rpy="1.2 0 0"/><axis xyz="1 0 0"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="imu_c_joint" type="fixed"><parent link="c"/><child link="imu_c"/>
    <origin xyz="0.05 0.02 0.2" rpy="0.1 0.2 0.3"/></joint>
  <joint name="tool_joint" type="fixed"><parent link="c"/><child link="tool_tip"/>
    <origin xyz="0 0 0.3" rpy="0 0 0"/></joint>
</robot>
"""


@pytest.mark.parametrize("moving_base", [False, True])
def test_any_axis_urdf_equals_pinocchio(moving_base: bool) -> None:
    from aaria_pin.core.kinematics import frame_poses
    from aaria_pin.core.model import build_model
    from aaria_pin.core.trajectory import BaseMotion, JointTrajectory

    model = build_model(_ODD_AXES_URDF, moving_base=moving_base)
    assert model.model.joints[2 if moving_base else 1].shortname() == "JointModelRevoluteUnaligned"
    time = sample_times(2.0, 25)
    phases = np.array([0.0, 1.0, 2.0])
    q = np.sin(np.outer(time, [1.0, 1.5, 0.7]) + phases)
    qd = np.cos(np.outer(time, [1.0, 1.5, 0.7]) + phases) * [1.0, 1.5, 0.7]
    qdd = -q * np.array([1.0, 1.5, 0.7]) ** 2
    trajectory = JointTrajectory(time, q, qd, qdd)
    base = base_motion(BASE_6X4, time) if moving_base else BaseMotion.resting(time.size)
    frames = ["imu_c", "tool_tip", "a", "b"]
    np.testing.assert_allclose(
        imu_signals(model, base, trajectory, frames),
        reference_imu_signals(model, base, trajectory, frames),
        atol=1e-9,
    )
    np.testing.assert_allclose(
        frame_poses(model, base, trajectory, frames),
        reference_frame_poses(model, base, trajectory, frames),
        atol=1e-12,
    )


def test_quaternions_of_any_rotation_match_scipy() -> None:
    from scipy.spatial.transform import Rotation

    from aaria_pin.core._kinematics_kernel import free_flyer_state

    rotations = Rotation.random(2000, random_state=4)
    half_turns = Rotation.from_rotvec(np.pi * np.eye(3))  # w = 0: the x, y, z branches
    matrices = np.concatenate([rotations.as_matrix(), half_turns.as_matrix(), np.eye(3)[None]])
    n = matrices.shape[0]
    q, v, a = np.empty((n, 7)), np.empty((n, 6)), np.empty((n, 6))
    zeros = np.zeros((n, 3))
    free_flyer_state(matrices, zeros, zeros, zeros, zeros, zeros, q, v, a)
    ours = q[:, 3:]
    theirs = Rotation.from_matrix(matrices).as_quat(canonical=True)
    # q and -q are the same rotation; compare up to that sign
    signs = np.sign(np.sum(ours * theirs, axis=1))
    np.testing.assert_allclose(ours, theirs * signs[:, None], atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(ours, axis=1), 1.0, atol=1e-14)


def test_wrong_trajectory_shapes_are_refused_before_the_kernel() -> None:
    from aaria_pin.core.trajectory import JointTrajectory
    from aaria_pin.errors import ModelError

    robot = build_dh_robot(get_preset("aaria-fig3").table)
    model = robot.model(moving_base=True)
    time = sample_times(1.0, 10)
    base = base_motion(default_base_table(), time)
    short = np.zeros((time.size, 3))
    with pytest.raises(ModelError, match=r"trajectory q has shape \(11, 3\); allowed: \(11, 5\)"):
        imu_signals(model, base, JointTrajectory(time, short, short, short), model.sensor_frames)
    good = joint_trajectory(default_joint_table(robot.chain), robot.chain, time)
    half_base = base_motion(default_base_table(), time[:5])
    with pytest.raises(ModelError, match="base rotation has shape"):
        imu_signals(model, half_base, good, model.sensor_frames)
