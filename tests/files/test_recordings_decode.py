"""The fast path of bag reading (``files/recordings/bag_decode``): NumPy over the messages' bytes.

Against two independent expectations: the ``rosbags`` path (each message deserialised,
:func:`reference_read_topics`), which must give the same arrays bit for bit, on every bag the
tests write (our exports in each format, and bags written with ``rosbags`` directly in ROS 1
and ROS 2 serialisation, with what makes a layout vary: frame ids of several lengths on one
topic, two publishers of joint states, empty arrays); and the numbers written into them.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("rosbags")

from aaria_pin.apps.recordings import export_run
from aaria_pin.core.record import RunRecord
from aaria_pin.files.recordings.bag_decode import decode_fixed, decode_joint_states
from aaria_pin.files.recordings.bag_format import IMU_TYPE, JOINTS_TYPE, WRENCH_TYPE
from aaria_pin.files.recordings.bag_read import read_bag, read_topics, reference_read_topics

FRAMES = ("a", "wrist", "wrist_camera_imu", "ab")
"""IMU frame ids on one topic: CDR pads "a" and "ab" (2 and 3 bytes with the NUL) to one
message length, so a length alone does not fix the layout."""


@pytest.fixture(scope="module")
def run() -> RunRecord:
    from aaria_pin.core.catalogue import find_robot
    from aaria_pin.core.urdf_robot import read_urdf_file
    from aaria_pin.core.urdf_run import urdf_request

    text = read_urdf_file(find_robot("ur5").urdf)
    return urdf_request(text, source="ur5", duration=0.2, rate=100.0).record()


def assert_bit_identical(path: Path) -> dict[str, Any]:
    """Both readers' topics of ``path``: the same names, kinds, columns and arrays, bit for bit."""
    from aaria_pin.files.recordings.bag_format import rosbags_typestore

    ros1 = path.suffix == ".bag"
    store = rosbags_typestore(ros1)
    fast, reference = read_topics(path, store, ros1), reference_read_topics(path, store)
    assert list(fast) == list(reference)
    for name, topic in fast.items():
        other = reference[name]
        assert (topic.topic, topic.kind, topic.columns) == (other.topic, other.kind, other.columns)
        for field in ("stamps", "logs", "values"):
            mine, theirs = getattr(topic, field), getattr(other, field)
            assert mine.dtype == theirs.dtype and mine.shape == theirs.shape, (name, field)
            assert mine.tobytes() == theirs.tobytes(), (name, field)
        assert topic.frames.tolist() == other.frames.tolist()
    return fast


@pytest.mark.parametrize("name", ["run.bag", "run.mcap", "run.db3", "folder_sqlite", "folder_mcap"])
def test_an_exported_run_decodes_as_rosbags_deserialises_it(
    run: RunRecord, tmp_path: Path, name: str
) -> None:
    form = {"folder_sqlite": "ros2-sqlite3", "folder_mcap": "ros2-mcap"}.get(name)
    path = export_run(run, tmp_path / name, form)
    topics = assert_bit_identical(path)
    slot = next(i for i, m in enumerate(run.imu_mounts) if m.parent)
    imu = topics[f"/imu/{run.imu_mounts[slot].name}"]
    np.testing.assert_array_equal(imu.values, run.imu[:, slot])  # the numbers exported
    np.testing.assert_array_equal(imu.stamps, np.round(run.time * 1e9).astype(np.int64))


def _messages(store: Any, ros1: bool) -> list[tuple[str, str, int, Any]]:
    """Topic, type, log time [ns] and message of a lab-like recording (module docstring)."""
    t = store.types
    vector, quaternion = t["geometry_msgs/msg/Vector3"], t["geometry_msgs/msg/Quaternion"]

    def header(k: int, ns: int, frame: str) -> Any:
        stamp = t["builtin_interfaces/msg/Time"](sec=ns // 10**9, nanosec=ns % 10**9)
        extra = {"seq": k} if ros1 else {}
        return t["std_msgs/msg/Header"](**extra, stamp=stamp, frame_id=frame)

    rng = np.random.default_rng(5)
    found = []
    for k in range(12):
        ns = 1_700_000_000 * 10**9 + k * 2_500_001
        w = rng.normal(size=6)
        imu = t[IMU_TYPE](
            header=header(k, ns, FRAMES[k % len(FRAMES)]), orientation=quaternion(
            x=0.0, y=0.0, z=0.0, w=1.0), orientation_covariance=rng.normal(size=9),
            angular_velocity=vector(x=w[0], y=w[1], z=w[2]),
            angular_velocity_covariance=np.zeros(9),
            linear_acceleration=vector(x=w[3], y=w[4], z=w[5]),
            linear_acceleration_covariance=np.zeros(9),
        )  # fmt: skip
        found.append(("/imus", IMU_TYPE, ns + 7, imu))
        f = rng.normal(size=6)
        wrench = t[WRENCH_TYPE](header=header(k, ns, "ft" if k % 3 else ""), wrench=t[
            "geometry_msgs/msg/Wrench"](force=vector(x=f[0], y=f[1], z=f[2]),
            torque=vector(x=f[3], y=f[4], z=f[5])))  # fmt: skip
        found.append(("/ft", WRENCH_TYPE, ns + 8, wrench))
        arm = t[JOINTS_TYPE](header=header(k, ns, "arm"), name=["j1", "j2"],
                             position=rng.normal(size=2), velocity=rng.normal(size=2),
                             effort=np.zeros(0) if k % 2 else rng.normal(size=2))  # fmt: skip
        found.append(("/joint_states", JOINTS_TYPE, ns + 9, arm))
        other = t[JOINTS_TYPE](header=header(k, ns, "arm"), name=["k1", "k2"],  # same length
                               position=rng.normal(size=2), velocity=rng.normal(size=2),
                               effort=rng.normal(size=2))  # fmt: skip
        found.append(("/joint_states", JOINTS_TYPE, ns + 10, other))
    return found


def _lab_bag(path: Path, ros1: bool, little_endian: bool = True) -> Path:
    """The recording of :func:`_messages`, written with ``rosbags`` directly."""
    from aaria_pin.files.recordings.bag_format import rosbags_typestore

    store = rosbags_typestore(ros1)
    if ros1:
        from rosbags.rosbag1 import Writer as Writer1

        writer: Any = Writer1(path)
    else:
        from rosbags.rosbag2 import StoragePlugin, Writer

        writer = Writer(path, version=9, storage_plugin=StoragePlugin.SQLITE3)
    connections: dict[str, Any] = {}
    with writer:
        for topic, msgtype, log, message in _messages(store, ros1):
            if topic not in connections:
                connections[topic] = writer.add_connection(topic, msgtype, typestore=store)
            raw = (
                store.serialize_ros1(message, msgtype)
                if ros1
                else store.serialize_cdr(message, msgtype, little_endian=little_endian)
            )
            writer.write(connections[topic], log, raw)
    return path


@pytest.mark.parametrize("ros1", [True, False], ids=["ros1", "ros2"])
def test_a_lab_bag_decodes_as_rosbags_deserialises_it(tmp_path: Path, ros1: bool) -> None:
    from aaria_pin.files.recordings.bag_format import rosbags_typestore

    path = _lab_bag(tmp_path / ("lab.bag" if ros1 else "lab_bag"), ros1)
    topics = assert_bit_identical(path)
    store = rosbags_typestore(ros1)
    sent = _messages(store, ros1)
    imus = [m for topic, _, _, m in sent if topic == "/imus"]
    assert topics["/imus"].frames.tolist() == [m.header.frame_id for m in imus]
    rows = [[m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z,
             m.linear_acceleration.x, m.linear_acceleration.y, m.linear_acceleration.z]
            for m in imus]  # fmt: skip
    np.testing.assert_array_equal(topics["/imus"].values, rows)
    arm = [m for topic, _, _, m in sent if topic == "/joint_states" and m.name[0] == "j1"]
    parts = {(t.columns[0], len(t.columns)): t for t in topics.values() if t.kind == "joints"}
    full = parts[("q:j1", 6)]  # the arm with efforts (every other message), then without
    np.testing.assert_array_equal(full.values[:, 4:], [m.effort for m in arm[::2]])
    np.testing.assert_array_equal(parts[("q:j1", 4)].values[:, :2], [m.position for m in arm[1::2]])
    assert len(parts) == 3 and parts[("q:k1", 6)].values.shape == (12, 6)
    assert read_bag(path).stream("wrist_camera_imu").values.shape == (3, 6)
    serialise = store.serialize_ros1 if ros1 else store.serialize_cdr
    raws = {t: [bytes(serialise(m, t)) for _, kind, _, m in sent if kind == t]
            for t in (IMU_TYPE, WRENCH_TYPE, JOINTS_TYPE)}  # fmt: skip
    assert decode_fixed(raws[IMU_TYPE], IMU_TYPE, ros1) is not None  # not left to rosbags
    assert decode_fixed(raws[WRENCH_TYPE], WRENCH_TYPE, ros1) is not None
    assert len(decode_joint_states(raws[JOINTS_TYPE], ros1) or ()) == 3


def test_big_endian_cdr_is_left_to_rosbags(tmp_path: Path) -> None:
    """Not decoded here (None): the reader deserialises it, to the same arrays."""
    path = _lab_bag(tmp_path / "big_bag", ros1=False, little_endian=False)
    assert_bit_identical(path)
    from aaria_pin.files.recordings.bag_format import rosbags_typestore

    store = rosbags_typestore(False)
    raws = [bytes(store.serialize_cdr(m, t, little_endian=False))
            for _, t, _, m in _messages(store, False)]  # fmt: skip
    assert decode_fixed(raws[:1], IMU_TYPE, False) is None
    assert decode_joint_states(raws[2:3], False) is None


def test_a_message_of_another_length_than_its_layout_is_not_decoded() -> None:
    from aaria_pin.files.recordings.bag_format import rosbags_typestore

    store = rosbags_typestore(False)
    sent = _messages(store, False)
    imu = bytes(store.serialize_cdr(sent[0][3], IMU_TYPE))
    joints = bytes(store.serialize_cdr(sent[2][3], JOINTS_TYPE))
    assert decode_fixed([imu], IMU_TYPE, False) is not None
    assert decode_fixed([imu + bytes(8)], IMU_TYPE, False) is None
    assert decode_fixed([imu[:10]], IMU_TYPE, False) is None
    assert decode_joint_states([joints], False) is not None
    assert decode_joint_states([joints[:-8]], False) is None
