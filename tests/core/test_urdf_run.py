"""Runs of example-robot-data robots: torques against Pinocchio's RNEA on an independently
loaded model, IMU signals against finite differences of frame placements, the run file."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from conftest import GRAVITY, paper_base_state, vee

from aaria_pin.apps.remake import simulate_urdf_from_run_file
from aaria_pin.core.catalogue import find_robot
from aaria_pin.core.record import RunRecord
from aaria_pin.core.trajectory import sample_times
from aaria_pin.core.urdf_robot import (
    UrdfRobot,
    default_urdf_joint_table,
    load_urdf_robot,
    read_urdf_file,
    urdf_joint_trajectory,
)
from aaria_pin.core.urdf_run import simulate_urdf_run, urdf_request
from aaria_pin.files.runfile import read_run, write_run

BASE_TABLE = np.array(
    [[0.1, 0.0, 1.3, 0.2], [0.2, 0.1, 0.9, 0.0], [0.05, 0.3, 1.7, 1.0],
     [0.2, 0.0, 1.1, 0.4], [0.15, 0.1, 0.8, 0.0], [0.3, -0.2, 1.4, 0.7]]
)  # fmt: skip
"""A base that moves and turns about every axis at once."""


def _robot_file(name: str) -> Path:
    return find_robot(name).urdf


def _free_flyer_state(base_table: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, ...]:
    """Base pose, body velocity and body acceleration from the paper's sines (conftest), as
    Pinocchio's free-flyer wants them: ``[p, quat]``, ``[Rᵀṗ, ω]``, ``[Rᵀp̈ - ω × Rᵀṗ, ω̇]``."""
    position, velocity, acceleration, rotation, omega, omega_dot = paper_base_state(base_table, t)
    q = np.hstack([position, [pin.Quaternion(R).coeffs() for R in rotation]])
    Rt = np.transpose(rotation, (0, 2, 1))
    v_lin = np.einsum("tij,tj->ti", Rt, velocity)
    a_lin = np.einsum("tij,tj->ti", Rt, acceleration) - np.cross(omega, v_lin)
    return q, np.hstack([v_lin, omega]), np.hstack([a_lin, omega_dot])


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_torques_equal_pinocchio_rnea_on_a_moving_base(name: str) -> None:
    file = _robot_file(name)
    record = simulate_urdf_run(
        read_urdf_file(file), base_table=BASE_TABLE, duration=2.0, rate=50.0, noise=False
    )
    model = pin.buildModelFromUrdf(str(file), pin.JointModelFreeFlyer())
    model.gravity.linear = GRAVITY.copy()
    data = model.createData()
    q_base, v_base, a_base = _free_flyer_state(BASE_TABLE, record.time)
    assert [model.names[j] for j in range(2, model.njoints)] == list(record.joint_names)
    for k in range(0, record.time.size, 7):
        tau = pin.rnea(
            model,
            data,
            np.concatenate([q_base[k], record.q[k]]),
            np.concatenate([v_base[k], record.qd[k]]),
            np.concatenate([a_base[k], record.qdd[k]]),
        )
        np.testing.assert_allclose(record.tau[k], tau[6:], atol=1e-9)
        R = record.base_pose[k, :3, :3]
        np.testing.assert_allclose(record.base_wrench[k, :3], R @ tau[:3], atol=1e-9)
        np.testing.assert_allclose(record.base_wrench[k, 3:], R @ tau[3:6], atol=1e-9)


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_base_force_is_the_rate_of_momentum_less_gravity(name: str) -> None:
    """Newton on the whole robot: f_base = m·(d²c/dt²) - m·g, c by finite differences."""
    file = _robot_file(name)
    h, t = 1e-4, np.array([0.3, 0.9, 1.4])
    text = read_urdf_file(file)
    loaded = load_urdf_robot(text)
    table = default_urdf_joint_table(loaded)
    model = pin.buildModelFromUrdf(str(file), pin.JointModelFreeFlyer())
    data = model.createData()
    record = simulate_urdf_run(text, table, BASE_TABLE, duration=1.5, rate=10.0, noise=False)
    for time in t:
        grid = time + np.array([-h, 0.0, h])
        q_base = _free_flyer_state(BASE_TABLE, grid)[0]
        q_joints = urdf_joint_trajectory(table, loaded, grid).q
        com = [
            pin.centerOfMass(model, data, np.concatenate([qb, qj]))
            for qb, qj in zip(q_base, q_joints, strict=True)
        ]
        accel = (com[2] - 2 * com[1] + com[0]) / h**2
        mass = sum(inertia.mass for inertia in model.inertias)
        k = round(time * 10)
        expected = mass * (accel - GRAVITY)
        np.testing.assert_allclose(record.base_wrench[k, :3], expected, rtol=1e-5, atol=1e-4)


def _check_imus_by_finite_differences(
    model: pin.Model, record: RunRecord, table: np.ndarray, loaded: UrdfRobot
) -> None:
    """ω = vee(Rᵀ·dR/dt), f = Rᵀ·(d²p/dt² - g), from IMU placements at t ± h (free-flyer model)."""
    data, h = model.createData(), 1e-4
    for k, time in enumerate(record.time):
        grid = time + np.array([-h, 0.0, h])
        q_base = _free_flyer_state(BASE_TABLE, grid)[0]
        q_joints = urdf_joint_trajectory(table, loaded, grid).q
        poses = []
        for qb, qj in zip(q_base, q_joints, strict=True):
            fixed_part = _pinocchio_configuration(model, qj)
            pin.framesForwardKinematics(model, data, np.concatenate([qb, fixed_part]))
            poses.append(
                [
                    data.oMf[model.getFrameId(m.parent)].homogeneous @ m.T_parent_imu
                    for m in record.imu_mounts
                ]
            )
        for s in range(len(record.imu_mounts)):
            before, now, after = (poses[i][s] for i in range(3))
            R = now[:3, :3]
            omega = vee(R.T @ (after[:3, :3] - before[:3, :3]) / (2 * h))
            accel = (after[:3, 3] - 2 * now[:3, 3] + before[:3, 3]) / h**2
            specific_force = R.T @ (accel - GRAVITY)
            np.testing.assert_allclose(record.imu[k, s, :3], omega, atol=1e-6)
            np.testing.assert_allclose(record.imu[k, s, 3:], specific_force, atol=1e-5)


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_imu_signals_equal_finite_differences_on_a_moving_base(name: str) -> None:
    """ω = vee(Rᵀ·dR/dt), f = Rᵀ·(d²p/dt² - g), from frame placements at t ± h."""
    file = _robot_file(name)
    text = read_urdf_file(file)
    loaded = load_urdf_robot(text)
    table = default_urdf_joint_table(loaded)
    record = simulate_urdf_run(text, table, BASE_TABLE, duration=1.0, rate=4.0, noise=False)
    model = pin.buildModelFromUrdf(str(file), pin.JointModelFreeFlyer())
    _check_imus_by_finite_differences(model, record, table, loaded)


_TWISTED_URDF = """<robot name="twisted">
  <link name="root"><inertial><mass value="2.0"/>
    <inertia ixx="0.02" iyy="0.03" izz="0.04" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="a"><inertial><origin xyz="0.1 0.02 0.0"/><mass value="1.5"/>
    <inertia ixx="0.01" iyy="0.02" izz="0.015" ixy="0.001" ixz="0" iyz="0.002"/></inertial></link>
  <link name="b"><inertial><origin xyz="0.0 0.15 0.05"/><mass value="1.0"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.012" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="c"><inertial><origin xyz="0.05 0 0.1"/><mass value="0.7"/>
    <inertia ixx="0.004" iyy="0.005" izz="0.003" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="spin" type="continuous"><parent link="root"/><child link="a"/>
    <origin xyz="0 0 0.2" rpy="0.3 0 0"/><axis xyz="0 0 -1"/></joint>
  <joint name="tilt" type="continuous"><parent link="a"/><child link="b"/>
    <origin xyz="0.3 0 0" rpy="0 0.2 0.1"/><axis xyz="0.6 0.8 0"/></joint>
  <joint name="slide" type="prismatic"><parent link="b"/><child link="c"/>
    <origin xyz="0 0.3 0"/><axis xyz="0 0.6 -0.8"/>
    <limit lower="-0.2" upper="0.2" effort="50" velocity="1"/></joint>
</robot>"""
"""Continuous joints about -z and a skew axis (Pinocchio's unbounded unaligned joint), and a
prismatic joint along a skew axis: every joint type a URDF gives, with odd placements."""


def _pinocchio_configuration(model: pin.Model, joint_values: np.ndarray) -> np.ndarray:
    """Joint values to Pinocchio's configuration of the actuated joints, written out here:
    cos/sin for an unbounded joint (a free-flyer root skipped)."""
    out = []
    actuated = [j for j in model.joints[1:] if j.shortname() != "JointModelFreeFlyer"]
    for joint, value in zip(actuated, joint_values, strict=True):
        out += [np.cos(value), np.sin(value)] if joint.nq == 2 else [value]
    return np.array(out)


def test_continuous_and_skew_joints_on_a_moving_base() -> None:
    table = np.array([[0.9, 0, 0.3, 1.1, 0.0], [0.7, 0, -0.2, 1.7, 1.0], [0, 0.1, 0.05, 2.3, 0.5]])
    record = simulate_urdf_run(
        _TWISTED_URDF, table, BASE_TABLE, duration=1.0, rate=4.0, noise=False
    )
    fixed_model = pin.buildModelFromXML(_TWISTED_URDF)
    assert [j.shortname() for j in fixed_model.joints[1:]] == [
        "JointModelRevoluteUnboundedUnaligned",
        "JointModelRevoluteUnboundedUnaligned",
        "JointModelPrismaticUnaligned",
    ]
    model = pin.buildModelFromXML(_TWISTED_URDF, pin.JointModelFreeFlyer())
    model.gravity.linear = GRAVITY.copy()
    data = model.createData()
    loaded = load_urdf_robot(_TWISTED_URDF)
    q_base, v_base, a_base = _free_flyer_state(BASE_TABLE, record.time)
    for k in range(record.time.size):
        q = np.concatenate([q_base[k], _pinocchio_configuration(fixed_model, record.q[k])])
        tau = pin.rnea(
            model, data, q, np.r_[v_base[k], record.qd[k]], np.r_[a_base[k], record.qdd[k]]
        )
        np.testing.assert_allclose(record.tau[k], tau[6:], atol=1e-9)
    _check_imus_by_finite_differences(model, record, table, loaded)


def test_continuous_joints_and_mimic_joints_simulate() -> None:
    """kinova has continuous joints (cos/sin configuration), panda a mimic finger."""
    record = simulate_urdf_run(read_urdf_file(_robot_file("kinova")), duration=1.0, noise=False)
    assert np.all(np.isfinite(record.tau))
    panda = simulate_urdf_run(read_urdf_file(_robot_file("panda")), duration=1.0, noise=False)
    names = list(panda.joint_names)
    leader, follower = names.index("panda_finger_joint1"), names.index("panda_finger_joint2")
    np.testing.assert_array_equal(panda.q[:, follower], panda.q[:, leader])


def test_run_file_round_trip_and_remake(tmp_path: Path) -> None:
    record = simulate_urdf_run(
        read_urdf_file(_robot_file("ur5")), duration=1.0, rate=20.0, seed=7, source="ur5"
    )
    path = write_run(tmp_path / "ur5.h5", record)
    stored = read_run(path)
    np.testing.assert_array_equal(stored.signals(), record.signals())
    for name in ("q", "qd", "qdd", "tau", "base_pose", "base_wrench", "tool_pose"):
        np.testing.assert_array_equal(getattr(stored, name), getattr(record, name))
    assert stored.columns == record.columns
    assert stored.columns[:2] == ("time", "q:shoulder_pan_joint")
    assert stored.urdf == record.urdf
    assert [m.name for m in stored.imu_mounts] == [m.name for m in record.imu_mounts]
    remade = simulate_urdf_from_run_file(path)
    np.testing.assert_array_equal(remade.signals(), record.signals())
    np.testing.assert_array_equal(remade.tau, record.tau)


def test_fixed_base_run_has_identity_base_and_gravity_only_base_imu() -> None:
    record = simulate_urdf_run(
        read_urdf_file(_robot_file("ur5")), moving_base=False, duration=1.0, noise=False
    )
    assert "base_table" not in record.tables
    np.testing.assert_array_equal(record.base_pose, np.broadcast_to(np.eye(4), (101, 4, 4)))
    np.testing.assert_allclose(record.imu_signals("imu_base"), [[0, 0, 0, 0, 0, 9.81]] * 101)


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_fixed_mount_carries_the_static_weight(name: str) -> None:
    """A still robot on a fixed base: the mount pushes up by m·g, with moment c × (m·g)."""
    file = _robot_file(name)
    text = read_urdf_file(file)
    loaded = load_urdf_robot(text)
    table = default_urdf_joint_table(loaded)
    table[:, :2] = 0.0  # no swing: every joint rests at its bias
    record = simulate_urdf_run(text, table, moving_base=False, duration=0.5, noise=False)
    model = pin.buildModelFromUrdf(str(file))
    data = model.createData()
    mass = sum(inertia.mass for inertia in model.inertias)
    floating = pin.buildModelFromUrdf(str(file), pin.JointModelFreeFlyer())  # root link counted
    q_at_rest = np.r_[0, 0, 0, 0, 0, 0, 1, _pinocchio_configuration(model, record.q[0])]
    com = pin.centerOfMass(floating, floating.createData(), q_at_rest)
    force = np.array([0.0, 0.0, mass * 9.81])
    np.testing.assert_allclose(record.base_wrench[:, :3], np.tile(force, (51, 1)), atol=1e-9)
    np.testing.assert_allclose(
        record.base_wrench[:, 3:], np.tile(np.cross(com, force), (51, 1)), atol=1e-9
    )
    gravity_torques = pin.computeGeneralizedGravity(
        model, data, _pinocchio_configuration(model, record.q[0])
    )
    np.testing.assert_allclose(record.tau[0], gravity_torques, atol=1e-9)


def test_sample_grid_matches_the_aaria_run() -> None:
    record = simulate_urdf_run(
        read_urdf_file(_robot_file("ur5")), duration=0.5, rate=100.0, noise=False
    )
    np.testing.assert_array_equal(record.time, sample_times(0.5, 100.0))


def test_the_deprecated_urdf_producers_warn_and_equal_the_request(tmp_path: Path) -> None:
    import warnings

    from aaria_pin.core.run import join_chunks
    from aaria_pin.core.urdf_run import (
        loaded_robot_request,
        simulate_loaded_robot,
        simulate_urdf_from_record,
        simulate_urdf_from_record_chunks,
        simulate_urdf_run_chunks,
        urdf_request,
    )

    text = _robot_file("ur5").read_text()
    options = {"duration": 0.4, "rate": 50.0, "seed": 2}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        expected = urdf_request(text, **options).record()
        loaded = loaded_robot_request(load_urdf_robot(text), **options).record()
    with pytest.warns(DeprecationWarning, match=r"^simulate_urdf_run is deprecated; use "):
        record = simulate_urdf_run(text, **options)
    with pytest.warns(DeprecationWarning, match="simulate_urdf_run_chunks is deprecated"):
        pieces = join_chunks(simulate_urdf_run_chunks(text, chunk=6, **options))
    with pytest.warns(DeprecationWarning, match="simulate_loaded_robot is deprecated"):
        from_loaded = simulate_loaded_robot(load_urdf_robot(text), **options)
    with pytest.warns(DeprecationWarning, match="simulate_urdf_from_record is deprecated"):
        remade = simulate_urdf_from_record(expected)
    with pytest.warns(DeprecationWarning, match="simulate_urdf_from_record_chunks is deprecated"):
        remade_pieces = join_chunks(simulate_urdf_from_record_chunks(expected, chunk=4))
    path = tmp_path / "ur5.h5"
    write_run(path, expected)
    with pytest.warns(DeprecationWarning, match="simulate_urdf_from_run_file is deprecated"):
        from_file = simulate_urdf_from_run_file(path)
    for other in (record, pieces, remade, remade_pieces, from_file):
        np.testing.assert_array_equal(other.imu, expected.imu)
        np.testing.assert_array_equal(other.tau, expected.tau)
    np.testing.assert_array_equal(from_loaded.tau, loaded.tau)
    assert expected.n_samples == 21 and np.abs(expected.tau).max() > 0


def test_a_base_table_with_a_held_base_is_refused_naming_both() -> None:
    from aaria_pin.core.conflicts import OptionConflictError
    from aaria_pin.core.oscillation import default_base_table

    entry = find_robot("ur5")
    with pytest.raises(OptionConflictError) as error:
        urdf_request(
            entry.urdf.read_text(),
            urdf_dir=entry.urdf.parent,
            moving_base=False,
            base_table=default_base_table(),
        )
    assert error.value.parameter == "base_table" and "moving_base" in str(error.value)
