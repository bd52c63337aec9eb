"""What the bag reader and writer share: the formats by suffix, the topics, the typestores.

A ``.bag`` is ROS 1 (``rosbags.rosbag1``, the ROS 1 Noetic typestore); a ``.mcap`` or a
``.db3`` is the one storage file of a ROS 2 bag (``rosbags.rosbag2``, MCAP or sqlite3, the
ROS 2 Humble typestore: Humble's sqlite3 bags carry no message definitions, and the three types
are the same in every stock typestore). An IMU is the topic ``/imu/<name>`` (frame id: its
name), the joint states ``/joint_states`` (joints by name), a wrench ``/wrench/<name>``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from aaria_pin.errors import InputFileError

__all__ = [
    "BAG_SUFFIXES",
    "EXPORT_FORMATS",
    "IMU_TYPE",
    "JOINTS_TOPIC",
    "JOINTS_TYPE",
    "WRENCH_TYPE",
    "bag_format",
    "rosbags_typestore",
]

BAG_SUFFIXES = {".bag": "ros1", ".mcap": "mcap", ".db3": "sqlite3"}
"""The recording formats by file suffix."""

EXPORT_FORMATS = {
    "mcap": ".mcap", "ros1": ".bag", "sqlite3": ".db3", "csv": ".csv", "ros2-sqlite3": "",
    "ros2-mcap": "",
}  # fmt: skip
"""The formats a run is exported to, and their suffix (empty: a ROS 2 bag folder)."""

IMU_TYPE = "sensor_msgs/msg/Imu"
JOINTS_TYPE = "sensor_msgs/msg/JointState"
WRENCH_TYPE = "geometry_msgs/msg/WrenchStamped"
JOINTS_TOPIC = "/joint_states"


def bag_format(path: Path) -> str:
    """``ros1``, ``mcap`` or ``sqlite3`` by the file's suffix.

    Raises:
        InputFileError: another suffix (parameter ``file``).
    """
    found = BAG_SUFFIXES.get(path.suffix.lower())
    if found is None:
        raise InputFileError(
            f"{path} is not a recording; allowed: {', '.join(BAG_SUFFIXES)} (ROS 1 bag, MCAP, "
            "ROS 2 sqlite3), a ROS 2 bag folder, .csv",
            parameter="file",
        )
    return found


def export_format(path: Path, form: str | None = None) -> str:
    """The format of an export to ``path``: ``form`` if given, else by the suffix.

    Raises:
        ParameterError: an unknown format, or one whose suffix is not the path's; no format
            for a path without a known suffix (parameter ``form``).
    """
    from aaria_pin.errors import ParameterError

    by_suffix = {suffix: name for name, suffix in EXPORT_FORMATS.items() if suffix}
    suffix = path.suffix.lower()
    chosen = by_suffix.get(suffix) if form is None else form
    allowed = ", ".join(EXPORT_FORMATS)
    if chosen is None or chosen not in EXPORT_FORMATS:
        what = f"{form}" if form is not None else f"not given and {path} has no known suffix"
        raise ParameterError(f"form is {what}; allowed: {allowed} (a ROS 2 bag folder:"
                             " ros2-sqlite3, ros2-mcap)", parameter="form")  # fmt: skip
    if EXPORT_FORMATS[chosen] != (suffix if suffix in by_suffix else ""):
        wanted = EXPORT_FORMATS[chosen] or "a folder name without a suffix"
        raise ParameterError(f"form {chosen} writes {wanted}; {path} is not one", parameter="form")
    return chosen


def rosbags_typestore(ros1: bool) -> Any:
    """The ``rosbags`` typestore (ROS 1 Noetic or ROS 2 Humble).

    Raises:
        InputFileError: ``rosbags`` is not installed (the way to install it).
    """
    try:
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        raise InputFileError(
            "recordings need the rosbags package; allowed: pip install 'aaria-pin[ros]'",
            parameter="file",
        ) from None
    return get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
