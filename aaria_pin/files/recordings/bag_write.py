"""Write a recorded run as a ROS 1 bag, an MCAP file or a ROS 2 sqlite3 file (``rosbags``).

One message per sample of each stream (:mod:`~aaria_pin.files.recordings.bag_format` for the
topics): an IMU as ``sensor_msgs/Imu`` (``angular_velocity`` [rad/s], ``linear_acceleration``
the specific force [m/s²], as REP 145 has it; no orientation: covariance ``[-1, 0, ...]``), the
joint states as one ``sensor_msgs/JointState`` (``position``, ``velocity``, ``effort`` by joint
name; a group the stream lacks left empty), a wrench as ``geometry_msgs/WrenchStamped``. Every
message's header stamp and log time are the stream's time,
``time_origin_ns + round(time·1e9)`` [ns], and the messages are written in time order (the
streams merged). A ``.mcap`` or ``.db3`` is the one storage file of a ROS 2 bag written in a
temporary folder beside the output and moved onto it when complete (the MCAP zstd-chunked: a
10 s, 14-IMU run is 6× smaller than as sqlite3): a failure leaves nothing at the output.
Measured on this machine by the research of issue 26: every float64 value read back bit for bit
in all three formats, and MCAP's own reference reader (``mcap-ros2-support``) decodes the files.
"""

from __future__ import annotations

import contextlib
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.recording import RecordedRun, SensorStream, joint_groups
from aaria_pin.errors import OutputFileError
from aaria_pin.files.recordings.bag_format import (
    IMU_TYPE,
    JOINTS_TOPIC,
    JOINTS_TYPE,
    WRENCH_TYPE,
    export_format,
    rosbags_typestore,
)

__all__ = ["write_bag"]

_TOPIC = {"imu": "/imu/{}", "wrench": "/wrench/{}", "joints": JOINTS_TOPIC}
_TYPE = {"imu": IMU_TYPE, "wrench": WRENCH_TYPE, "joints": JOINTS_TYPE}


def write_bag(path: str | Path, run: RecordedRun, form: str | None = None) -> Path:
    """Write ``run``'s streams to ``path``.

    Args:
        path: the output: a ``.bag``, ``.mcap`` or ``.db3`` file, or a ROS 2 bag folder
            (replaced when complete; a folder must not exist)
        run: the streams
        form: ``ros1``, ``mcap``, ``sqlite3``, ``ros2-sqlite3`` or ``ros2-mcap`` (a folder);
            None: by the suffix

    Returns:
        The path written.

    Raises:
        ParameterError: a format that is no bag's, or not the path's suffix.
        OutputFileError: a folder output that exists.
        InputFileError: ``rosbags`` missing.
    """
    from aaria_pin.files.paths import atomic_output, check_output

    out = Path(path)
    form = export_format(out, form)
    store = rosbags_typestore(form == "ros1")
    if form.startswith("ros2-"):
        if out.exists():
            raise OutputFileError(f"{out} exists; allowed: a new folder for a ROS 2 bag",
                                  parameter="path")  # fmt: skip
        check_output(out)  # "-", a name too long, a missing or unwritable folder
        with _scratch(out.parent) as folder:
            _write(folder / out.name, form.removeprefix("ros2-"), store, run)
            (folder / out.name).rename(out)
        return out
    with atomic_output(out) as temporary, _scratch(temporary.parent) as folder:
        target = folder / ("run.bag" if form == "ros1" else "bag")
        _write(target, form, store, run)
        written = target if form == "ros1" else next(target.glob(f"*{out.suffix}"))
        written.replace(temporary)
    return out


@contextlib.contextmanager
def _scratch(parent: Path) -> Iterator[Path]:
    """A hidden scratch folder in ``parent``, removed afterwards whatever happens.

    The rosbags writers refuse an existing output: they write in here.
    """
    folder = Path(tempfile.mkdtemp(prefix=".aaria-", dir=parent if str(parent) else "."))
    try:
        yield folder
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def _write(target: Path, form: str, store: Any, run: RecordedRun) -> None:
    """The bag at ``target`` (a ROS 1 file, or a ROS 2 bag folder)."""
    ros1 = form == "ros1"
    if ros1:
        from rosbags.rosbag1 import Writer as Writer1

        writer: Any = Writer1(target)
    else:
        from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin
        from rosbags.rosbag2 import Writer as Writer2

        plugin = StoragePlugin.MCAP if form == "mcap" else StoragePlugin.SQLITE3
        writer = Writer2(target, version=9, storage_plugin=plugin)
        if form == "mcap":
            writer.set_compression(CompressionMode.STORAGE, CompressionFormat.ZSTD)
    serialize = store.serialize_ros1 if ros1 else store.serialize_cdr
    streams = run.streams
    stamps = [run.time_origin_ns + np.round(s.time * 1e9).astype(np.int64) for s in streams]
    which = np.concatenate([np.full(t.size, i) for i, t in enumerate(stamps)])
    rows = np.concatenate([np.arange(t.size) for t in stamps])
    order = np.argsort(np.concatenate(stamps), kind="stable")
    with writer:
        connections = [
            writer.add_connection(_TOPIC[s.kind].format(s.name), _TYPE[s.kind], typestore=store)
            for s in streams
        ]
        build = [_BUILDERS[s.kind](s, store, ros1) for s in streams]
        for i, k in zip(which[order], rows[order], strict=True):
            ns = int(stamps[i][k])
            writer.write(connections[i], ns, serialize(build[i](k, ns), _TYPE[streams[i].kind]))


def _header(store: Any, ros1: bool, k: int, ns: int, frame: str) -> Any:
    """A message header stamped ``ns`` [ns] (ROS 1's with its sequence number)."""
    stamp = store.types["builtin_interfaces/msg/Time"](
        sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000
    )
    extra = {"seq": k} if ros1 else {}
    return store.types["std_msgs/msg/Header"](**extra, stamp=stamp, frame_id=frame)


def _imu(stream: SensorStream, store: Any, ros1: bool) -> Any:
    """``message(row, ns)``: a ``sensor_msgs/Imu`` (no orientation, REP 145)."""
    types = store.types
    imu, quaternion = types[IMU_TYPE], types["geometry_msgs/msg/Quaternion"]
    vector = types["geometry_msgs/msg/Vector3"]
    none, unknown = np.zeros(9), np.r_[-1.0, np.zeros(8)]

    def message(k: int, ns: int) -> Any:
        w = stream.values[k]
        return imu(
            header=_header(store, ros1, k, ns, stream.name),
            orientation=quaternion(x=0.0, y=0.0, z=0.0, w=1.0),
            orientation_covariance=unknown,
            angular_velocity=vector(x=w[0], y=w[1], z=w[2]),
            angular_velocity_covariance=none,
            linear_acceleration=vector(x=w[3], y=w[4], z=w[5]),
            linear_acceleration_covariance=none,
        )

    return message


def _wrench(stream: SensorStream, store: Any, ros1: bool) -> Any:
    """``message(row, ns)``: a ``geometry_msgs/WrenchStamped``."""
    types = store.types
    stamped, wrench = types[WRENCH_TYPE], types["geometry_msgs/msg/Wrench"]
    vector = types["geometry_msgs/msg/Vector3"]

    def message(k: int, ns: int) -> Any:
        w = stream.values[k]
        force, moment = vector(x=w[0], y=w[1], z=w[2]), vector(x=w[3], y=w[4], z=w[5])
        header = _header(store, ros1, k, ns, stream.name)
        return stamped(header=header, wrench=wrench(force=force, torque=moment))

    return message


def _joints(stream: SensorStream, store: Any, ros1: bool) -> Any:
    """``message(row, ns)``: a ``sensor_msgs/JointState`` (a group the stream lacks empty)."""
    joints, groups = joint_groups(stream)
    state = store.types[JOINTS_TYPE]

    def message(k: int, ns: int) -> Any:
        row = stream.values[k]
        return state(
            header=_header(store, ros1, k, ns, ""),
            name=joints,
            position=row[groups["q"]],
            velocity=row[groups["qd"]],
            effort=row[groups["tau"]],
        )

    return message


_BUILDERS = {"imu": _imu, "wrench": _wrench, "joints": _joints}
"""Each stream kind's message builder."""
