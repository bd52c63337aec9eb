"""Recordings out and back in (``files/recordings``): a simulated run exported as a ROS 1 bag,
an MCAP file and a ROS 2 sqlite3 file reads back to the same arrays; the MCAP file is decoded by
MCAP's own reference reader (``mcap-ros2-support``, not ours) to the same numbers; a bag written
directly with ``rosbags`` (not by our writer) reads in; bad recordings are one line each."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("rosbags")

from aaria_pin.apps.recordings import export_run, recorded_from_run
from aaria_pin.core.catalogue import find_robot
from aaria_pin.core.joint_sensors import EncoderModel
from aaria_pin.core.record import RunRecord
from aaria_pin.core.urdf_robot import read_urdf_file
from aaria_pin.core.urdf_run import urdf_request
from aaria_pin.errors import InputFileError
from aaria_pin.files.recordings.bag_read import read_bag


@pytest.fixture(scope="module")
def run() -> RunRecord:
    """ur5, 0.3 s at 200 Hz, IMU noise and encoders on (the measured q is exported)."""
    text = read_urdf_file(find_robot("ur5").urdf)
    encoder = EncoderModel(counts_per_revolution=2**18, noise=1e-5)
    return urdf_request(text, source="ur5", duration=0.3, rate=200.0, encoder=encoder).record()


@pytest.mark.parametrize("suffix", [".bag", ".mcap", ".db3"])
def test_a_run_exported_reads_back_to_the_same_arrays(
    run: RunRecord, tmp_path: Path, suffix: str
) -> None:
    path = export_run(run, tmp_path / f"run{suffix}")
    back = read_bag(path)
    sent = recorded_from_run(run)
    assert {s.name for s in back.streams} == {s.name for s in sent.streams}
    for stream in sent.streams:
        got = back.stream(stream.name)
        assert got.kind == stream.kind and got.columns == stream.columns
        np.testing.assert_array_equal(got.values, stream.values)
        np.testing.assert_array_equal(got.time, stream.time)  # 200 Hz: whole nanoseconds
    joints = back.stream("joints")
    np.testing.assert_array_equal(joints.values[:, :6], run.tables["q_measured"])


def test_the_mcap_file_decodes_with_the_reference_reader(run: RunRecord, tmp_path: Path) -> None:
    reader_module = pytest.importorskip("mcap_ros2.reader")
    path = export_run(run, tmp_path / "run.mcap")
    slot = next(i for i, m in enumerate(run.imu_mounts) if m.parent)
    name = run.imu_mounts[slot].name
    rows, stamps = [], []
    with path.open("rb") as f:
        for item in reader_module.read_ros2_messages(f, topics=[f"/imu/{name}"]):
            m = item.ros_msg
            rows.append([m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z,
                         m.linear_acceleration.x, m.linear_acceleration.y,
                         m.linear_acceleration.z])  # fmt: skip
            stamps.append(m.header.stamp.sec * 10**9 + m.header.stamp.nanosec)
    np.testing.assert_array_equal(np.array(rows), run.imu[:, slot])
    np.testing.assert_array_equal(np.array(stamps), np.round(run.time * 1e9).astype(np.int64))


def _bag(path: Path, stamps_ns: list[int], values: list[float]) -> Path:
    """A ROS 1 bag written with rosbags directly: one IMU topic (frame ``wrist``)."""
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC)
    t = store.types
    vector = t["geometry_msgs/msg/Vector3"]
    with Writer(path) as writer:
        connection = writer.add_connection("/wrist/imu", "sensor_msgs/msg/Imu", typestore=store)
        for k, (ns, value) in enumerate(zip(stamps_ns, values, strict=True)):
            header = t["std_msgs/msg/Header"](
                seq=k, stamp=t["builtin_interfaces/msg/Time"](sec=ns // 10**9, nanosec=ns % 10**9),
                frame_id="wrist",
            )  # fmt: skip
            quaternion = t["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0)
            message = t["sensor_msgs/msg/Imu"](
                header=header, orientation=quaternion, orientation_covariance=np.zeros(9),
                angular_velocity=vector(x=value, y=0.0, z=0.0),
                angular_velocity_covariance=np.zeros(9),
                linear_acceleration=vector(x=0.0, y=0.0, z=9.81),
                linear_acceleration_covariance=np.zeros(9),
            )  # fmt: skip
            writer.write(
                connection, 10**9 + k, store.serialize_ros1(message, "sensor_msgs/msg/Imu")
            )
    return path


def test_a_bag_written_by_rosbags_reads_in(tmp_path: Path) -> None:
    start = 1_700_000_000 * 10**9
    stamps = [start + k * 5_000_000 for k in range(4)]
    back = read_bag(_bag(tmp_path / "lab.bag", stamps, [0.1, 0.2, 0.3, 0.4]))
    imu = back.stream("wrist")
    assert back.time_origin_ns == start
    np.testing.assert_array_equal(imu.time, [0.0, 0.005, 0.01, 0.015])
    np.testing.assert_array_equal(imu.values[:, 0], [0.1, 0.2, 0.3, 0.4])
    assert imu.rate == pytest.approx(200.0)


def test_time_going_backwards_is_one_line(tmp_path: Path) -> None:
    stamps = [10**9, 10**9 + 5_000_000, 10**9 + 2_000_000]
    with pytest.raises(
        InputFileError, match=r"stream wrist time at sample 2 .* strictly increasing"
    ):
        read_bag(_bag(tmp_path / "back.bag", stamps, [0.1, 0.2, 0.3]))


def test_nan_is_one_line(tmp_path: Path) -> None:
    with pytest.raises(InputFileError, match=r"sample 1 wx is nan; allowed: a finite number"):
        read_bag(_bag(tmp_path / "nan.bag", [10**9, 2 * 10**9], [0.1, float("nan")]))


@pytest.mark.parametrize("suffix", [".bag", ".mcap", ".db3"])
def test_a_truncated_recording_is_one_line(run: RunRecord, tmp_path: Path, suffix: str) -> None:
    path = export_run(run, tmp_path / f"run{suffix}")
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    with pytest.raises(InputFileError) as caught:
        read_bag(path)
    message = str(caught.value)
    assert "\n" not in message and ("is damaged" in message or "has no" in message), message


def test_a_recording_without_imus_and_a_foreign_suffix_are_refused(tmp_path: Path) -> None:
    from aaria_pin.core.recording import RecordedRun, SensorStream
    from aaria_pin.files.recordings.bag_write import write_bag

    wrench = SensorStream("ft", "wrench", np.array([0.0, 0.01]), np.zeros((2, 6)),
                          ("fx", "fy", "fz", "mx", "my", "mz"))  # fmt: skip
    path = write_bag(tmp_path / "ft.mcap", RecordedRun([wrench]))
    with pytest.raises(InputFileError, match="has no sensor_msgs/msg/Imu topic"):
        read_bag(path)
    with pytest.raises(InputFileError, match=r"is not a recording; allowed: \.bag"):
        read_bag(tmp_path / "run.txt")


def _ros2_joint_bag(folder: Path, gripper: bool = False) -> Path:
    """A ROS 2 sqlite3 bag written with rosbags directly: an IMU (no frame id) and joint states
    whose messages carry no effort (an empty array), stamps 3 ms before their log times; with
    ``gripper``, a second publisher of one joint on the same topic, at 50 Hz."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    t = store.types
    vector = t["geometry_msgs/msg/Vector3"]

    def header(ns: int) -> object:
        stamp = t["builtin_interfaces/msg/Time"](sec=ns // 10**9, nanosec=ns % 10**9)
        return t["std_msgs/msg/Header"](stamp=stamp, frame_id="")

    with Writer(folder, version=9, storage_plugin=StoragePlugin.SQLITE3) as writer:
        imu = writer.add_connection("/arm/imu", "sensor_msgs/msg/Imu", typestore=store)
        js = writer.add_connection("/joint_states", "sensor_msgs/msg/JointState", typestore=store)
        for k in range(3):
            ns = 5 * 10**9 + k * 10**7
            message = t["sensor_msgs/msg/Imu"](
                header=header(ns), orientation=t["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0,
                z=0.0, w=1.0), orientation_covariance=np.zeros(9),
                angular_velocity=vector(x=float(k), y=0.0, z=0.0),
                angular_velocity_covariance=np.zeros(9),
                linear_acceleration=vector(x=0.0, y=0.0, z=9.81),
                linear_acceleration_covariance=np.zeros(9),
            )  # fmt: skip
            writer.write(imu, ns + 3_000_000, store.serialize_cdr(message, "sensor_msgs/msg/Imu"))
            state = t["sensor_msgs/msg/JointState"](
                header=header(ns), name=["elbow", "wrist"], position=np.array([k, -k], float),
                velocity=np.array([1.0, 2.0]), effort=np.zeros(0),
            )  # fmt: skip
            raw = store.serialize_cdr(state, "sensor_msgs/msg/JointState")
            writer.write(js, ns + 3_000_000, raw)
            if gripper and k % 2 == 0:
                finger = t["sensor_msgs/msg/JointState"](
                    header=header(ns + 1000), name=["finger"], position=np.array([0.01 * k]),
                    velocity=np.zeros(0), effort=np.array([2.0]),
                )  # fmt: skip
                raw = store.serialize_cdr(finger, "sensor_msgs/msg/JointState")
                writer.write(js, ns + 3_000_001, raw)
    return folder


def test_a_ros2_bag_folder_written_by_rosbags_reads_in(tmp_path: Path) -> None:
    from aaria_pin.files.recordings.mapping import RecordingMap

    back = read_bag(_ros2_joint_bag(tmp_path / "lab_bag"))
    assert back.time_origin_ns == 5 * 10**9 and back.imu_names == ("imu",)  # the topic's name
    states = back.joint_states()
    assert states.names == ("elbow", "wrist") and states.tau is None
    np.testing.assert_array_equal(states.q, [[0, 0], [1, -1], [2, -2]])
    np.testing.assert_array_equal(states.time, [0.0, 0.01, 0.02])
    logged = read_bag(tmp_path / "lab_bag", RecordingMap(time="log"))
    assert logged.time_origin_ns == 5 * 10**9 + 3_000_000


def test_a_bag_without_message_definitions_reads_as_humble_ones_do(tmp_path: Path) -> None:
    import sqlite3

    from rosbags.highlevel import AnyReader

    folder = _ros2_joint_bag(tmp_path / "humble_bag")
    with sqlite3.connect(next(folder.glob("*.db3"))) as db:  # as a pre-Iron recorder wrote it
        db.execute("DELETE FROM message_definitions")
    with pytest.raises(Exception, match="no type definitions"), AnyReader([folder]):
        pass  # rosbags alone refuses it
    assert read_bag(folder).imu_names == ("imu",)


def test_two_publishers_on_one_joint_states_topic_are_two_streams(tmp_path: Path) -> None:
    back = read_bag(_ros2_joint_bag(tmp_path / "two_bag", gripper=True))
    arm, finger = back.joint_states("joints0"), back.joint_states("joints1")
    assert arm.names == ("elbow", "wrist") and finger.names == ("finger",)
    np.testing.assert_array_equal(finger.q, [[0.0], [0.02]])
    np.testing.assert_array_equal(finger.tau, [[2.0], [2.0]])
    np.testing.assert_array_equal(finger.time, [1e-6, 0.020001])
    assert finger.qd is None and arm.tau is None


def test_a_sensor_without_header_stamps_keeps_its_log_time_with_a_warning(tmp_path: Path) -> None:
    with pytest.warns(UserWarning, match=r"wrist \(/wrist/imu\) has no header stamps"):
        back = read_bag(_bag(tmp_path / "nostamp.bag", [0, 0, 0], [0.1, 0.2, 0.3]))
    assert back.time_origin_ns == 10**9  # the helper logs message k at 1 s + k ns
    np.testing.assert_array_equal(back.stream("wrist").time, [0.0, 1e-9, 2e-9])


def test_a_run_with_motor_currents_exports_their_torques_as_effort(tmp_path: Path) -> None:
    from aaria_pin.core.joint_sensors import ActuatorModel, CurrentSensorModel

    text = read_urdf_file(find_robot("ur5").urdf)
    current = urdf_request(
        text,
        source="ur5",
        duration=0.2,
        rate=100.0,
        actuator=ActuatorModel(gear_ratio=100.0, viscous=0.5),
        current_sensor=CurrentSensorModel(torque_constant=0.1, noise=0.003),
    ).record()
    effort = read_bag(export_run(current, tmp_path / "run.mcap")).stream("joints").values[:, 12:]
    expected = current.tables["current_measured"] * (0.1 * 100.0)  # A x k_t x N = N·m
    np.testing.assert_allclose(effort, expected, rtol=1e-12)
    assert np.abs(effort - current.tau).max() > 0.1  # not the rigid-body torques (friction in)
