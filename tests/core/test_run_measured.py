"""The engine's joint channels: the actuator's friction, armature and motor torque against their
formulas, torque limits reported (not clipped), the torque drive through the actuator, a run in
pieces equal to the run whole, every robot kind, and the models recorded and read back."""

from __future__ import annotations

import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import aaria_pin as ap
from aaria_pin.apps.wrist.run import PointToPoint, wrist_robot
from aaria_pin.core.catalogue import find_robot
from aaria_pin.core.joint_sensors import (
    ActuatorModel,
    CurrentSensorModel,
    EncoderModel,
    TorqueSensorModel,
    joint_model_attributes,
    joint_models_from_attributes,
)
from aaria_pin.core.record import JOINT_RUN_TABLES, JOINT_SERIES, SERIES, RunRecord
from aaria_pin.core.run import (
    RunSettings,
    SampledTrajectory,
    TorqueDrive,
    join_chunks,
    simulate,
    simulate_pieces,
)
from aaria_pin.core.run.measured import (
    TorqueLimitWarning,
    joint_table_shapes,
)
from aaria_pin.core.run.robot import RunRobot
from aaria_pin.core.trajectory import JointTrajectory
from aaria_pin.core.urdf_robot import load_urdf_robot, read_urdf_file
from aaria_pin.core.urdf_run import loaded_robot_request
from aaria_pin.errors import InputFileError
from aaria_pin.files.runfile import read_run, write_run

ACTUATOR = ActuatorModel(
    rotor_inertia=[2e-5, 3e-5, 1e-5, 1e-5, 2e-5, 1e-5],
    gear_ratio=[100.0, 100.0, 80.0, 50.0, 100.0, 50.0],
    viscous=0.8,
    coulomb=[1.0, 2.0, 0.5, 0.5, 1.0, 0.3],
    coulomb_velocity=0.02,
    stribeck_torque=0.4,
    stribeck_velocity=0.05,
)
ENCODER = EncoderModel(counts_per_revolution=2**14, counts_per_metre=1e5, noise=1e-4, offset=1e-3)
TORQUE_SENSOR = TorqueSensorModel(noise=0.05, bias=0.2, resolution=0.01, scale_error=0.01)
CURRENT_SENSOR = CurrentSensorModel(
    torque_constant=0.05, noise=0.01, bias=0.02, resolution=0.001, scale_error=0.01
)
ALL = {
    "actuator": ACTUATOR,
    "encoder": ENCODER,
    "torque_sensor": TORQUE_SENSOR,
    "current_sensor": CURRENT_SENSOR,
}


def _ur5() -> RunRobot:
    loaded = load_urdf_robot(read_urdf_file(find_robot("ur5").urdf))
    return loaded_robot_request(loaded, source="ur5").robot


@pytest.fixture(scope="module")
def fig2() -> RunRecord:
    """aaria-fig2 (2 prismatic, 4 revolute) with every joint model on."""
    settings = RunSettings(0.5, 100.0, **ALL)
    return simulate(ap.preset_arm("aaria-fig2"), settings=settings, seeds=4)


def test_friction_against_its_formula(fig2: RunRecord) -> None:
    qd = fig2.qd
    coulomb = np.array([1.0, 2.0, 0.5, 0.5, 1.0, 0.3])
    dry = (coulomb + 0.4 * np.exp(-((qd / 0.05) ** 2))) * np.tanh(qd / 0.02)
    np.testing.assert_allclose(fig2.tables["tau_friction"], 0.8 * qd + dry, rtol=1e-14, atol=1e-14)


def test_armature_is_rotor_inertia_times_gear_ratio_squared_times_qdd(fig2: RunRecord) -> None:
    inertia = np.array([2e-5, 3e-5, 1e-5, 1e-5, 2e-5, 1e-5])
    ratio = np.array([100.0, 100.0, 80.0, 50.0, 100.0, 50.0])
    expected = inertia * ratio**2 * fig2.qdd
    np.testing.assert_allclose(fig2.tables["tau_armature"], expected, rtol=1e-14, atol=1e-14)


def test_the_motor_torque_is_the_sum_exactly(fig2: RunRecord) -> None:
    t = fig2.tables
    np.testing.assert_array_equal(t["tau_motor"], fig2.tau + t["tau_armature"] + t["tau_friction"])
    assert not np.array_equal(t["tau_motor"], fig2.tau)


def test_the_models_add_tables_and_attributes_and_leave_the_rest_bit_for_bit(
    fig2: RunRecord,
) -> None:
    plain = simulate(ap.preset_arm("aaria-fig2"), settings=RunSettings(0.5, 100.0), seeds=4)
    for name in SERIES:  # the IMU noise, q and tau are the run's without the models
        np.testing.assert_array_equal(getattr(fig2, name), getattr(plain, name))
    added = set(fig2.tables) - set(plain.tables)
    assert added == {*JOINT_SERIES, *JOINT_RUN_TABLES}
    expected = joint_table_shapes(RunSettings(0.5, 100.0, **ALL), fig2.n_samples, 6)
    assert list(fig2.tables)[-len(added) :] == list(expected)  # after the robot's, in order
    assert {n: fig2.tables[n].shape for n in added} == expected
    new = set(fig2.attributes) - set(plain.attributes)
    assert new == {"encoder", "torque_sensor", "actuator", "current_sensor", "actuator_limits"}
    assert "sensors" not in fig2.attributes  # built-in channels are not user sensors


@pytest.mark.parametrize("suffix", [".h5", ".mat"])
def test_models_are_recorded_and_read_back_from_a_run_file(
    fig2: RunRecord, tmp_path: Path, suffix: str
) -> None:
    stored = read_run(write_run(tmp_path / f"run{suffix}", fig2))
    assert joint_models_from_attributes(stored.attributes) == {**ALL, "controller": None}
    assert joint_models_from_attributes({}) == dict.fromkeys([*ALL, "controller"])
    assert joint_model_attributes(RunSettings()) == {}
    for name in (*JOINT_SERIES, *JOINT_RUN_TABLES):
        np.testing.assert_array_equal(stored.tables[name], fig2.tables[name])


def test_a_damaged_stored_model_is_one_line_naming_the_file_parameter() -> None:
    with pytest.raises(InputFileError) as caught:
        joint_models_from_attributes({"encoder": {"noise": -1.0}})
    assert caught.value.parameter == "file" and "noise is -1" in str(caught.value)
    with pytest.raises(InputFileError):
        joint_models_from_attributes({"actuator": "fast"})


def test_a_run_in_pieces_equals_the_run_whole(fig2: RunRecord) -> None:
    settings = RunSettings(0.5, 100.0, chunk=7, **ALL)
    pieces = join_chunks(simulate_pieces(ap.preset_arm("aaria-fig2"), None, settings, 4))
    for name in fig2.tables:
        np.testing.assert_array_equal(pieces.tables[name], fig2.tables[name])
    assert pieces.attributes["actuator_limits"] == fig2.attributes["actuator_limits"]


def test_float32_runs_round_the_time_axis_tables_as_a_data_set_stores_them() -> None:
    settings = RunSettings(0.2, 100.0, dtype="float32", **ALL)
    record = simulate(ap.preset_arm("aaria-fig2"), settings=settings, seeds=4)
    for name in JOINT_SERIES:
        table = record.tables[name]
        np.testing.assert_array_equal(table, table.astype(np.float32).astype(np.float64))
    offset = record.tables["encoder_offset"]  # drawn values stay float64
    assert not np.array_equal(offset, offset.astype(np.float32).astype(np.float64))


def test_a_motor_torque_beyond_its_limit_is_kept_reported_and_warned_once() -> None:
    limits = [5.0, 1e6, 1e6, 1e6, 1e6, 1e6]
    settings = RunSettings(0.5, 100.0, chunk=10, actuator=replace(ACTUATOR, torque_limit=limits))
    robot = ap.preset_arm("aaria-fig2")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        record = join_chunks(simulate_pieces(robot, None, settings, 0))
    motor = record.tables["tau_motor"]
    first = int(np.flatnonzero(np.abs(motor[:, 0]) > 5.0)[0])
    ours = [w for w in caught if issubclass(w.category, TorqueLimitWarning)]
    assert len(ours) == 1 and issubclass(TorqueLimitWarning, UserWarning)
    message = str(ours[0].message)
    assert "joint1" in message and f"t = {record.time[first]:.6g} s" in message
    assert f"{motor[first, 0]:.6g}" in message and "\n" not in message
    limit = record.attributes["actuator_limits"]
    assert limit["exceeded"] == [True, False, False, False, False, False]
    np.testing.assert_allclose(limit["tau_motor_peak"], np.abs(motor).max(axis=0), rtol=0)
    assert limit["torque_limit"] == limits
    plain = simulate(robot, settings=RunSettings(0.5, 100.0), seeds=0)
    np.testing.assert_array_equal(record.q, plain.q)  # not clipped: the motion is kept


def test_no_torque_limit_falls_back_to_the_models_effort_limit() -> None:
    robot = _ur5()
    effort = np.asarray(robot.model.model.effortLimit)[robot.model.base_nv :]
    settings = RunSettings(
        0.2, 100.0, noise=False, actuator=ActuatorModel(torque_limit=[0, 0, 0, 1, 0, 0])
    )
    record = simulate(robot, settings=settings)
    expected = effort.copy()
    expected[3] = 1.0
    assert record.attributes["actuator_limits"]["torque_limit"] == list(expected)


def test_torque_replay_through_the_actuator_follows_the_prescribed_motion() -> None:
    robot = _ur5()
    motors = ActuatorModel(rotor_inertia=1e-4, gear_ratio=50.0, viscous=2.0)
    settings = RunSettings(0.5, 500.0, noise=False, actuator=motors)
    prescribed = simulate(robot, settings=settings)
    motor = prescribed.tables["tau_motor"]
    driven = simulate(robot, TorqueDrive(motor), settings)
    assert driven.attributes["drive"] == "torque"
    np.testing.assert_array_equal(driven.tables["torque_table"], motor)
    assert np.abs(driven.q - prescribed.q).max() < 1e-4
    assert np.abs(driven.qd - prescribed.qd).max() < 1e-3
    # the motion it made needs the torques it was given
    np.testing.assert_allclose(driven.tables["tau_motor"], motor, atol=2e-2 * np.abs(motor).max())
    # motor torques on the bare joints: wrist_3 passes its velocityLimit at once (kept: ignore)
    rigid = simulate(robot, TorqueDrive(motor, limits="ignore"), replace(settings, actuator=None))
    assert np.abs(rigid.q - prescribed.q).max() > 100 * np.abs(driven.q - prescribed.q).max()


def _pick_place(settings: RunSettings) -> RunRecord:
    """The pick-and-place arm's run through the engine, its settings given (the app's own
    ``simulate_pick_place`` makes its settings)."""
    from aaria_pin.apps.arm.payload import payload_inertia, with_payload
    from aaria_pin.apps.arm.run import PickPlaceRobot, simulate_pick_place
    from aaria_pin.apps.arm.task import Cylinder
    from aaria_pin.core.run.series import Payload

    run = simulate_pick_place(Cylinder(0.5, 0.2), (-0.3, 0.4), rate=5.0)
    model = with_payload(run.robot.model, payload_inertia(run.dims, run.cylinder))
    arm = PickPlaceRobot(run.robot, Payload(replace(run.robot, model=model), run.path.held))
    path = run.path
    motion = SampledTrajectory(JointTrajectory(path.time, path.q, path.qd, path.qdd))
    record = simulate(arm, motion, replace(settings, duration=float(path.time[-1]), rate=5.0))
    np.testing.assert_array_equal(record.tau, run.tau)  # the app's run, the payload carried
    return record


@pytest.mark.parametrize("kind", ["dh", "urdf", "wrist", "pick-place"])
def test_every_robot_kind_records_the_joint_tables(kind: str) -> None:
    models = {**ALL, "actuator": ActuatorModel(rotor_inertia=1e-5, gear_ratio=100.0, viscous=0.1)}
    settings = RunSettings(0.2, 100.0, noise=False, **models)
    if kind == "wrist":
        motion = PointToPoint(np.array([0.5, 0.4, -0.3]), 2.0, 10.0, "trapezoid", 0.0)
        record = simulate(wrist_robot(), motion, settings)
    elif kind == "pick-place":
        record = _pick_place(settings)
    else:
        robot = ap.preset_arm("aaria-fig2") if kind == "dh" else _ur5()
        record = simulate(robot, settings=settings)
    n = len(record.joint_names)
    assert record.attributes["kind"] == kind
    for name in JOINT_SERIES:
        assert record.tables[name].shape == (record.n_samples, n)
    tables = record.tables
    motor = record.tau + tables["tau_armature"] + tables["tau_friction"]
    np.testing.assert_array_equal(tables["tau_motor"], motor)
    step = 2 * np.pi / 2**14
    if kind in ("urdf", "wrist"):  # every joint revolute
        counts = (record.tables["q_measured"] - record.tables["encoder_offset"]) / step
        np.testing.assert_allclose(counts, np.round(counts), rtol=0, atol=1e-6)


@pytest.mark.parametrize("kind", ["dh", "urdf"])
def test_a_prescribed_motion_outside_the_joint_limits_is_refused(kind: str) -> None:
    robot = ap.preset_arm("aaria-fig2") if kind == "dh" else _ur5()
    _, upper = robot.limits
    q = np.zeros((21, len(robot.joint_names)))
    q[10:, 0] = upper[0] + 0.5
    zeros = np.zeros_like(q)
    motion = SampledTrajectory(JointTrajectory(np.arange(21) / 100.0, q, zeros, zeros))
    with pytest.raises(ap.ParameterError, match="allowed: within its range"):
        simulate(robot, motion, RunSettings(0.2, 100.0, noise=False, **ALL))


def test_a_per_joint_value_of_another_length_is_refused_before_any_piece() -> None:
    settings = RunSettings(0.2, 100.0, chunk=5, actuator=ActuatorModel(viscous=[0.1, 0.2]))
    pieces = simulate_pieces(ap.preset_arm("aaria-fig2"), None, settings, 0)
    with pytest.raises(ap.ParameterError, match="viscous has 2 values; allowed: one number or 6"):
        next(pieces)


@pytest.mark.parametrize("suffix", [".h5", ".mat"])
def test_a_run_file_written_in_pieces_holds_the_whole_runs_joint_tables(
    fig2: RunRecord, tmp_path: Path, suffix: str
) -> None:
    from aaria_pin.files.runfile import write_run_pieces

    settings = RunSettings(0.5, 100.0, chunk=8, **ALL)
    pieces = simulate_pieces(ap.preset_arm("aaria-fig2"), None, settings, 4)
    path = tmp_path / f"run{suffix}"
    write_run_pieces(path, pieces, None, mat_version="7.3")
    stored = read_run(path)
    for name in (*JOINT_SERIES, *JOINT_RUN_TABLES):
        np.testing.assert_array_equal(stored.tables[name], fig2.tables[name])
    assert stored.attributes["actuator_limits"] == fig2.attributes["actuator_limits"]


def test_an_empty_modules_column_reads_zero_in_every_joint_table() -> None:
    robot = ap.preset_arm("aaria-fig3")  # module 2 empty: a record column without a joint
    assert robot.columns is not None
    empty = sorted(set(range(6)) - set(robot.columns))
    assert empty == [1] and (robot.tables["senSenDH"][1, 4] == 0)
    motors = ActuatorModel(rotor_inertia=1e-5, gear_ratio=10.0, viscous=1.0)
    settings = RunSettings(0.2, 100.0, noise=False, **{**ALL, "actuator": motors})
    record = simulate(robot, settings=settings, seeds=2)
    for name in (*JOINT_SERIES, *JOINT_RUN_TABLES):
        table = record.tables[name]
        assert (table[:, empty] == 0).all(), name
        assert (table[:, robot.columns] != 0).any(), name
