"""Read a recording (ROS 1 bag, ROS 2 bag folder, MCAP, ROS 2 sqlite3) into a recorded run.

Without a map (:class:`~aaria_pin.files.recordings.mapping.RecordingMap`), every
``sensor_msgs/Imu`` topic is an IMU named after its frame id (one IMU per frame id when several
share the topic; the topic's last part when the frame id is empty), every
``sensor_msgs/JointState`` topic a joint stream joined by joint name (one per set of joints
when several publishers share the topic: ``joints0``, ``joints1``, …), every
``geometry_msgs/WrenchStamped`` topic a wrench named after its topic's last part (the topics
:func:`~aaria_pin.files.recordings.bag_write.write_bag` writes read back to the same names).
A map names the sensors it wants and where they are. Each sensor keeps its own time: its
messages' header stamps (the map's ``time = "log"``: their log time; stamps all zero: log time,
with a warning), from the earliest of the recording (``time_origin_ns``).

The messages are decoded from their bytes with NumPy (:func:`read_topics`,
:mod:`~aaria_pin.files.recordings.bag_decode`: ROS 1 and little-endian CDR), 2 to 3.5 times
faster than deserialising each through ``rosbags`` (:func:`reference_read_topics`, kept as the
reference and for what the decoder leaves to it), to the same arrays bit for bit.

What is wrong in a recording is one line, an :class:`~aaria_pin.errors.InputFileError` naming
the file: no IMU topic; a mapped topic missing, of another type, or without the mapped frame id;
a file the reader cannot open or read through (a truncated or damaged bag: whatever the reader
raised, its first line; the readers raise more than their own error class, e.g. sqlite's and
zstd's); a time stamp that does not increase or a value that is not finite, naming the stream
and the sample (:class:`~aaria_pin.core.recording.SensorStream`'s own checks).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass
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
from aaria_pin.files.recordings.mapping import RecordingMap, SensorMap

__all__ = ["read_bag", "read_topics", "reference_read_topics"]


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


@dataclass
class _Topic:
    """A topic's messages as read: kind, stamps and log times [ns], frame ids, values."""

    topic: str
    kind: str
    stamps: Any
    logs: Any
    frames: Any
    values: Any
    columns: tuple[str, ...]


def read_bag(path: str | Path, mapping: RecordingMap | None = None) -> RecordedRun:
    """The recorded run of a ``.bag``, ``.mcap`` or ``.db3`` file or a ROS 2 bag folder.

    Args:
        path: the recording
        mapping: which topics are which sensors (None: every topic, module docstring)

    Raises:
        InputFileError: a file that is not a readable recording with an IMU topic, a mapped
            sensor not in it, or a stream whose time does not increase or whose values are
            not finite (one line, the file named; parameter ``file``).
    """
    file = Path(path)
    form = "ros2" if file.is_dir() else bag_format(file)
    if not file.exists():
        raise InputFileError(f"{file}: no such file", parameter="file")
    store = rosbags_typestore(form == "ros1")
    try:
        topics = read_topics(file, store, form == "ros1")
    except InputFileError:
        raise
    except Exception as exc:  # the readers raise their own, sqlite's, zstd's, OverflowError
        first = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
        raise InputFileError(
            f"{file} is damaged ({first}); allowed: a complete recording", parameter="file"
        ) from None
    if not any(t.kind == "imu" for t in topics.values()):
        listed = ", ".join(f"{t.topic} ({t.kind})" for t in topics.values()) or "none"
        raise InputFileError(f"{file} has no {IMU_TYPE} topic; allowed: a recording with IMUs"
                             f" (topics read: {listed})", parameter="file")  # fmt: skip
    mapping = mapping or RecordingMap()
    chosen = _chosen(file, topics, mapping)
    clock = [_clock(file, name, t, mask, mapping.time) for name, t, mask in chosen]
    origin = min(int(ns[0]) for ns in clock if ns.size)
    streams = []
    try:
        for (name, t, mask), ns in zip(chosen, clock, strict=True):
            streams.append(SensorStream(name, t.kind, (ns - origin) / 1e9, t.values[mask],
                                        t.columns, source=t.topic))  # fmt: skip
        return RecordedRun(streams, time_origin_ns=origin, source=str(file))
    except ParameterError as exc:
        raise InputFileError(f"{file}: {exc}", parameter="file") from None


def _chosen(
    file: Path, topics: dict[str, _Topic], mapping: RecordingMap
) -> list[tuple[str, _Topic, Any]]:
    """The streams to make: name, topic and the mask of its messages."""
    chosen = []
    for kind, sensors in (("imu", mapping.imus), ("wrench", mapping.wrenches)):
        if not sensors:
            groups = [_default_sensors(t) for t in topics.values() if t.kind == kind]
            sensors = tuple(s for group in groups for s in group)
        for sensor in sensors:
            chosen.append(_mapped(file, topics, kind, sensor))
    joints = [t for t in topics.values() if t.kind == "joints"]
    if mapping.joints is not None:
        _mapped(file, topics, "joints", SensorMap("joints", mapping.joints))  # there, of its type
        joints = [t for t in joints if t.topic == mapping.joints]
    for k, topic in enumerate(joints):
        name = "joints" if len(joints) == 1 else f"joints{k}"
        chosen.append((name, topic, np.ones(topic.stamps.size, bool)))
    return chosen


def _default_sensors(topic: _Topic) -> list[SensorMap]:
    """A topic's sensors without a map: one per frame id (IMUs), else named by the topic."""
    last = topic.topic.rstrip("/").split("/")[-1]
    frames = sorted(set(topic.frames.tolist()))
    if topic.kind == "imu" and frames and all(frames):
        if len(frames) == 1:
            return [SensorMap(frames[0], topic.topic)]
        return [SensorMap(frame, topic.topic, frame) for frame in frames]
    return [SensorMap(last, topic.topic)]


def _mapped(
    file: Path, topics: dict[str, _Topic], kind: str, sensor: SensorMap
) -> tuple[str, _Topic, Any]:
    """A mapped sensor's topic and messages (one line if the recording lacks them)."""
    found = topics.get(sensor.topic)
    of_kind = ", ".join(t.topic for t in topics.values() if t.kind == kind) or "none"
    if found is None or found.kind != kind:
        what = "is not in the recording" if found is None else f"holds {found.kind} messages"
        raise InputFileError(f"{file}: topic {sensor.topic} ({kind} {sensor.name}) {what};"
                             f" allowed: {of_kind}", parameter="file")  # fmt: skip
    mask = np.ones(found.stamps.size, bool)
    if sensor.frame:
        mask = found.frames == sensor.frame
        if not mask.any():
            seen = ", ".join(sorted(set(found.frames.tolist()))) or "none"
            raise InputFileError(f"{file}: frame id {sensor.frame} ({kind} {sensor.name}) is in no"
                                 f" message on {sensor.topic}; allowed: {seen}",
                                 parameter="file")  # fmt: skip
    return sensor.name, found, mask


def _clock(file: Path, name: str, topic: _Topic, mask: Any, time: str) -> Any:
    """A stream's time stamps [ns]: header stamps, or log time (asked, or stamps all zero)."""
    stamps = topic.stamps[mask]
    if time == "header" and stamps.size and not stamps.any():
        warnings.warn(f"{file}: {name} ({topic.topic}) has no header stamps (all zero); its log"
                      " time is used", stacklevel=3)  # fmt: skip
        time = "log"
    return topic.logs[mask] if time == "log" else stamps


def read_topics(file: Path, store: Any, ros1: bool) -> dict[str, _Topic]:
    """Every IMU, joint-state and wrench topic (messages in the reader's order), decoded fast.

    One pass over the recording gathers each topic's serialised messages, which
    :mod:`~aaria_pin.files.recordings.bag_decode` reads with NumPy; a topic it does not decode
    (big-endian CDR) is deserialised as :func:`reference_read_topics` does. The arrays equal
    :func:`reference_read_topics`'s bit for bit (``tests/files/test_recordings_decode.py``).

    Measured: ``aaria import`` of a 30 s, 200 Hz, 14-IMU aaria-fig2 run exported as ``.mcap``
    (``aaria export run.h5 -o run.mcap``: 96 016 messages; ``/usr/bin/time aaria import
    run.mcap -o rec.h5``, a shared 2-core machine under load) took 5.5-6.3 s (1.9 s of CPU)
    through :func:`reference_read_topics` and takes 1.6-1.9 s (0.55 s of CPU) with this, the
    files written equal; ``.db3`` 3.1 s → 1.3 s, ROS 1 ``.bag`` 3.4 s → 2.3 s. For MCAP the
    one pass gains most (``rosbags`` decompresses the chunks again for each topic asked for:
    reading the raw messages topic by topic took 3.2 s, in one pass 0.4 s), for the others the
    decoding (deserialising took about 1.3 s).
    """
    from rosbags.highlevel import AnyReader

    found: dict[str, _Topic] = {}
    with AnyReader([file], default_typestore=store) as reader:
        topics = {t: i for t, i in reader.topics.items() if i.msgtype in (*_ROWS, JOINTS_TYPE)}
        gathered: dict[str, list[tuple[Any, int, bytes]]] = {topic: [] for topic in topics}
        connections = [c for info in topics.values() for c in info.connections]
        for connection, log, raw in reader.messages(connections=connections):
            gathered[connection.topic].append((connection, log, raw))
        for topic, info in topics.items():
            messages = gathered[topic]
            msgtype = str(info.msgtype)
            parts = _decoded(topic, msgtype, messages, ros1)
            if parts is None:
                parts = _deserialised(reader, topic, msgtype, messages)
            for k, part in enumerate(parts):
                found[topic if k == 0 else f"{topic} ({k})"] = part
    return found


def reference_read_topics(file: Path, store: Any) -> dict[str, _Topic]:
    """:func:`read_topics` through ``rosbags``: each topic read, each message deserialised."""
    from rosbags.highlevel import AnyReader

    found: dict[str, _Topic] = {}
    with AnyReader([file], default_typestore=store) as reader:
        for topic, info in reader.topics.items():
            if info.msgtype in (*_ROWS, JOINTS_TYPE):
                messages = reader.messages(connections=info.connections)
                for k, part in enumerate(_deserialised(reader, topic, info.msgtype, messages)):
                    found[topic if k == 0 else f"{topic} ({k})"] = part
    return found


def _decoded(
    topic: str, msgtype: str, messages: list[tuple[Any, int, bytes]], ros1: bool
) -> list[_Topic] | None:
    """A topic's streams decoded from its messages' bytes (None: not decoded, module docs)."""
    from aaria_pin.files.recordings.bag_decode import decode_fixed, decode_joint_states

    raws = [raw for _, _, raw in messages]
    logs = np.array([log for _, log, _ in messages], dtype=np.int64)
    if msgtype in _ROWS:
        decoded = decode_fixed(raws, msgtype, ros1)
        if decoded is None:
            return None
        kind = _ROWS[msgtype][0]
        stamps, frames, values = decoded
        return [_Topic(topic, kind, stamps, logs, frames, values, STREAM_COLUMNS[kind])]
    parts = decode_joint_states(raws, ros1)
    if parts is None:
        return None
    return [
        _Topic(topic, "joints", p.stamps, logs[p.index], np.full(p.index.size, "", dtype=object),
               p.values, tuple(f"{g}:{j}" for g in p.present for j in p.names))
        for p in parts
    ]  # fmt: skip


def _deserialised(reader: Any, topic: str, msgtype: str, messages: Any) -> list[_Topic]:
    """A topic's streams, its messages deserialised one at a time (``rosbags``)."""
    if msgtype == JOINTS_TYPE:  # a stream per set of joints (publishers)
        return _joint_topic(reader, topic, messages)
    kind, row = _ROWS[msgtype]
    stamps, logs, rows, frames = [], [], [], []
    for connection, log, raw in messages:
        message: Any = reader.deserialize(raw, connection.msgtype)
        stamps.append(_stamp(message))
        logs.append(log)
        rows.append(row(message))
        frames.append(message.header.frame_id)
    values = np.array(rows, dtype=np.float64).reshape(-1, 6)
    return [_Topic(topic, kind, np.array(stamps, np.int64), np.array(logs, np.int64),
                   np.array(frames, dtype=object), values, STREAM_COLUMNS[kind])]  # fmt: skip


def _stamp(message: Any) -> int:
    """A message's header stamp [ns]."""
    return int(message.header.stamp.sec) * 1_000_000_000 + int(message.header.stamp.nanosec)


def _joint_topic(reader: Any, topic: str, messages: Any) -> list[_Topic]:
    """A JointState topic as streams: one per set of joints its messages name.

    Several publishers share a topic (an arm's and a gripper's); each set of joints (and of
    the groups ``q``, ``qd``, ``tau`` its messages fill) is a stream, its columns by joint name.
    """
    parts: dict[tuple[tuple[str, ...], tuple[str, ...]], tuple[list[int], list[int], list[Any]]]
    parts = {}
    for connection, log, raw in messages:
        message = reader.deserialize(raw, connection.msgtype)
        names = tuple(message.name)
        arrays = {"q": message.position, "qd": message.velocity, "tau": message.effort}
        present = tuple(g for g, a in arrays.items() if len(a) == len(names))
        stamps, logs, rows = parts.setdefault((names, present), ([], [], []))
        stamps.append(_stamp(message))
        logs.append(log)
        rows.append(np.concatenate([np.asarray(arrays[g], np.float64) for g in present]))
    found = []
    for (names, present), (stamps, logs, rows) in parts.items():
        columns = tuple(f"{g}:{j}" for g in present for j in names)
        values = np.array(rows, dtype=np.float64).reshape(-1, len(columns))
        frames = np.full(len(stamps), "", dtype=object)
        found.append(_Topic(topic, "joints", np.array(stamps, np.int64),
                            np.array(logs, np.int64), frames, values, columns))  # fmt: skip
    return found
