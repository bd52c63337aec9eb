"""Read a recording (ROS 1 bag, MCAP, ROS 2 sqlite3) into a recorded run (``rosbags``).

Every ``sensor_msgs/Imu`` topic is an IMU named after its frame id (the topic's last part when
the frame id is empty), every ``sensor_msgs/JointState`` topic is joined by joint name into
one joint stream, every ``geometry_msgs/WrenchStamped`` topic is a wrench named after its
topic's last part (the topics :func:`~aaria_pin.files.recordings.bag_write.write_bag` writes
read back to the same names). Each sensor keeps its own header stamps as its time, from the
earliest stamp of the recording (``time_origin_ns``). What is wrong in a recording is one line,
an :class:`~aaria_pin.errors.InputFileError` naming the file: no IMU topic; a file the reader
cannot open or read through (a truncated or damaged bag: whatever the reader raised, its first
line; the readers raise more than their own error class, e.g. sqlite's and zstd's); a time
stamp that does not increase, or a value that is not finite, naming the stream and the sample
(:class:`~aaria_pin.core.recording.SensorStream`'s own checks).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.recording import STREAM_COLUMNS, RecordedRun, SensorStream
from aaria_pin.errors import InputFileError, ParameterError
from aaria_pin.files.recordings.bag_format import (
    IMU_TYPE,
    JOINTS_TYPE,
    WRENCH_TYPE,
    bag_format,
    rosbags_typestore,
)

__all__ = ["read_bag"]


def _imu_row(message: Any) -> tuple[float, ...]:
    w, f = message.angular_velocity, message.linear_acceleration
    return (w.x, w.y, w.z, f.x, f.y, f.z)


def _wrench_row(message: Any) -> tuple[float, ...]:
    f, m = message.wrench.force, message.wrench.torque
    return (f.x, f.y, f.z, m.x, m.y, m.z)


_ROWS: dict[str, tuple[str, Callable[[Any], tuple[float, ...]]]] = {
    IMU_TYPE: ("imu", _imu_row),
    WRENCH_TYPE: ("wrench", _wrench_row),
}
"""The fixed-column message types: the stream kind and the row of a message."""


def read_bag(path: str | Path) -> RecordedRun:
    """The recorded run of a ``.bag``, ``.mcap`` or ``.db3`` file.

    Raises:
        InputFileError: a file that is not a readable recording with an IMU topic, or a stream
            whose time does not increase or whose values are not finite (one line, the file
            named; parameter ``file``).
    """
    file = Path(path)
    form = bag_format(file)
    if not file.is_file():
        raise InputFileError(f"{file}: no such file", parameter="file")
    store = rosbags_typestore(form == "ros1")
    try:
        topics = _topics(file, store)
    except InputFileError:
        raise
    except Exception as exc:  # the readers raise their own, sqlite's, zstd's, OverflowError
        first = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
        raise InputFileError(
            f"{file} is damaged ({first}); allowed: a complete recording", parameter="file"
        ) from None
    if not any(kind == "imu" for kind, *_ in topics.values()):
        raise InputFileError(
            f"{file} has no {IMU_TYPE} topic; allowed: a recording with IMUs", parameter="file"
        )
    origin = min(int(stamps[0]) for _, _, stamps, _, _ in topics.values() if stamps.size)
    streams = []
    try:
        for kind, name, stamps, values, columns in topics.values():
            time = (stamps - origin) / 1e9
            streams.append(SensorStream(name, kind, time, values, columns, source=str(file)))
        return RecordedRun(streams, time_origin_ns=origin, source=str(file))
    except ParameterError as exc:
        raise InputFileError(f"{file}: {exc}", parameter="file") from None


def _topics(file: Path, store: Any) -> dict[str, tuple[str, str, Any, Any, tuple[str, ...]]]:
    """Per topic: kind, name, stamps [ns], values, columns (messages in the reader's order)."""
    from rosbags.highlevel import AnyReader

    found: dict[str, tuple[str, str, Any, Any, tuple[str, ...]]] = {}
    with AnyReader([file], default_typestore=store) as reader:
        for topic, info in reader.topics.items():
            if info.msgtype in _ROWS:
                kind, row = _ROWS[info.msgtype]
                stamps: list[int] = []
                rows: list[tuple[float, ...]] = []
                frames: set[str] = set()
                for connection, _, raw in reader.messages(connections=info.connections):
                    message: Any = reader.deserialize(raw, connection.msgtype)
                    stamps.append(_stamp(message))
                    rows.append(row(message))
                    frames.add(message.header.frame_id)
                frame = next(iter(frames)) if len(frames) == 1 else ""
                name = frame if kind == "imu" and frame else topic.rstrip("/").split("/")[-1]
                values = np.array(rows, dtype=np.float64).reshape(-1, 6)
                found[topic] = (
                    kind,
                    name,
                    np.array(stamps, np.int64),
                    values,
                    STREAM_COLUMNS[kind],
                )
            elif info.msgtype == JOINTS_TYPE:
                found[topic] = _joint_topic(reader, info)
    return found


def _stamp(message: Any) -> int:
    """A message's header stamp [ns]."""
    return int(message.header.stamp.sec) * 1_000_000_000 + int(message.header.stamp.nanosec)


def _joint_topic(reader: Any, info: Any) -> tuple[str, str, Any, Any, tuple[str, ...]]:
    """A JointState topic as one stream: the groups every message has, by joint name.

    Raises:
        InputFileError: messages naming other joints than the first one does.
    """
    stamps: list[int] = []
    rows: list[Any] = []
    joints: list[str] | None = None
    groups: tuple[str, ...] | None = None
    for connection, _, raw in reader.messages(connections=info.connections):
        message = reader.deserialize(raw, connection.msgtype)
        names = list(message.name)
        arrays = {"q": message.position, "qd": message.velocity, "tau": message.effort}
        present = tuple(g for g, a in arrays.items() if len(a) == len(names))
        if joints is None:
            joints, groups = names, present
        if names != joints or present != groups:
            raise InputFileError(
                f"topic {info.connections[0].topic} message {len(stamps)} has joints {names} "
                f"({', '.join(present)}); allowed: the first message's {joints} "
                f"({', '.join(groups or ())})",
                parameter="file",
            )
        stamps.append(_stamp(message))
        rows.append(np.concatenate([np.asarray(arrays[g], np.float64) for g in present]))
    columns = tuple(f"{g}:{j}" for g in (groups or ()) for j in (joints or ()))
    values = np.array(rows, dtype=np.float64).reshape(-1, len(columns))
    return "joints", "joints", np.array(stamps, np.int64), values, columns
