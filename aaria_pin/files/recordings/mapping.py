"""Which topics (or CSV columns) are which sensors: the recording map, from TOML and flags.

A :class:`RecordingMap` names the IMUs (a ``sensor_msgs/Imu`` topic, optionally only the
messages of one frame id; in a CSV, six columns), the joint states' topic and the wrenches
(a ``geometry_msgs/WrenchStamped`` topic), and which time a sensor keeps: its messages' header
stamps (``header``, the instant the driver measured) or their log time (``log``, when the
recorder received them). :func:`read_map` reads it from a TOML file (``aaria template
recording``), :func:`with_flags` puts ``--imu NAME=TOPIC[@FRAME]``, ``--joints TOPIC``,
``--wrench NAME=TOPIC`` and ``--time`` over it. An empty map takes every topic of the three
types, as :func:`~aaria_pin.files.recordings.bag_read.read_bag` names them.
"""

from __future__ import annotations

import os
import tomllib
from collections.abc import Sequence
from dataclasses import dataclass, replace
from json import dumps
from pathlib import Path
from typing import Any

from aaria_pin.core.recording import first_repeated
from aaria_pin.errors import InputFileError, ParameterError

__all__ = ["TIME_SOURCES", "RecordingMap", "SensorMap", "map_toml", "read_map", "with_flags"]

TIME_SOURCES = ("header", "log")
"""A sensor's time: its messages' header stamps, or their log (receive) time."""


@dataclass(frozen=True)
class SensorMap:
    """One IMU or wrench of a recording.

    Attributes:
        name: the sensor's name in the run (an IMU's name in the model or IMU layout)
        topic: its topic (a CSV: empty)
        frame: an IMU's frame id, when several IMUs share one topic (empty: every message)
        columns: in a CSV, its six columns (``wx wy wz fx fy fz`` or ``fx fy fz mx my mz``)
    """

    name: str
    topic: str = ""
    frame: str = ""
    columns: tuple[str, ...] = ()


@dataclass(frozen=True)
class RecordingMap:
    """The sensors of a recording (module docstring); empty parts: every topic of the type.

    Attributes:
        imus: the IMUs
        joints: the ``sensor_msgs/JointState`` topic (None: every one)
        wrenches: the wrenches
        time: ``header`` or ``log``
        time_column: a CSV's time column [s]
    """

    imus: tuple[SensorMap, ...] = ()
    joints: str | None = None
    wrenches: tuple[SensorMap, ...] = ()
    time: str = "header"
    time_column: str = "time"

    def __post_init__(self) -> None:
        if self.time not in TIME_SOURCES:
            raise ParameterError(parameter="time", value=self.time, allowed=", ".join(TIME_SOURCES))
        twice = first_repeated([s.name for s in (*self.imus, *self.wrenches)])
        if twice is not None:
            message = f"sensor {twice} is mapped twice; allowed: one entry per sensor"
            raise ParameterError(message, parameter="map", value=twice)


def _sensors(table: Any, key: str, file: Path) -> tuple[SensorMap, ...]:
    """The ``[[imu]]`` or ``[[wrench]]`` tables of a map file."""
    entries = table.get(key, [])
    if not isinstance(entries, list):
        entries = [entries]
    found = []
    for k, entry in enumerate(entries):
        unknown = sorted(set(entry) - {"name", "topic", "frame_id", "columns"})
        if "name" not in entry or unknown or not isinstance(entry.get("columns", []), list):
            what = f"key {unknown[0]}" if unknown else "no name" if "name" not in entry else ""
            raise InputFileError(f"{file}: [[{key}]] {k + 1} has {what or 'bad columns'}; allowed:"
                                 " name, topic, frame_id, columns", parameter="map")  # fmt: skip
        columns = tuple(str(c) for c in entry.get("columns", ()))
        if columns and len(columns) != 6:
            raise InputFileError(f"{file}: [[{key}]] {entry['name']} has {len(columns)} columns;"
                                 " allowed: 6", parameter="map")  # fmt: skip
        found.append(SensorMap(str(entry["name"]), str(entry.get("topic", "")),
                               str(entry.get("frame_id", "")), columns))  # fmt: skip
    return tuple(found)


def read_map(path: str | os.PathLike[str]) -> RecordingMap:
    """The map of a TOML file (``aaria template recording``).

    Raises:
        InputFileError: a missing file, bad TOML, an unknown key (parameter ``map``).
    """
    file = Path(path)
    try:
        table = tomllib.loads(file.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        first = (str(exc).splitlines() or [type(exc).__name__])[0]
        raise InputFileError(
            f"{file}: {first}; allowed: a TOML recording map", parameter="map"
        ) from None
    unknown = sorted(set(table) - {"time", "time_column", "imu", "joints", "wrench"})
    if unknown:
        raise InputFileError(f"{file}: key {unknown[0]} is unknown; allowed: time, time_column,"
                             " imu, joints, wrench", parameter="map")  # fmt: skip
    joints = table.get("joints", {})
    topic = joints.get("topic") if isinstance(joints, dict) else None
    return RecordingMap(_sensors(table, "imu", file), None if topic is None else str(topic),
                        _sensors(table, "wrench", file), str(table.get("time", "header")),
                        str(table.get("time_column", "time")))  # fmt: skip


def _pair(text: str, parameter: str, form: str) -> tuple[str, str]:
    """``NAME=VALUE`` of a flag, else a one-line ParameterError."""
    name, sep, value = text.partition("=")
    if not (sep and name.strip() and value.strip()):
        raise ParameterError(parameter=parameter, value=text, allowed=form)
    return name.strip(), value.strip()


def with_flags(
    base: RecordingMap | None,
    imus: Sequence[str] = (),
    joints: str | None = None,
    wrenches: Sequence[str] = (),
    time: str | None = None,
) -> RecordingMap:
    """``base`` with the flags over it (a flag's sensor replaces the map's of the same name).

    Args:
        base: the map file's map (None: empty)
        imus: ``NAME=TOPIC`` or ``NAME=TOPIC@FRAME_ID`` each
        joints: the joint states' topic
        wrenches: ``NAME=TOPIC`` each
        time: ``header`` or ``log``

    Raises:
        ParameterError: a flag not of that form (parameter ``imu`` or ``wrench``).
    """
    found = base or RecordingMap()
    given = []
    for text in imus:
        name, where = _pair(text, "imu", "NAME=TOPIC or NAME=TOPIC@FRAME_ID")
        topic, _, frame = where.partition("@")
        given.append(SensorMap(name, topic, frame))
    forces = [SensorMap(*_pair(text, "wrench", "NAME=TOPIC")) for text in wrenches]

    def merged(old: tuple[SensorMap, ...], new: list[SensorMap]) -> tuple[SensorMap, ...]:
        names = {s.name for s in new}
        return (*(s for s in old if s.name not in names), *new)

    return replace(found, imus=merged(found.imus, given), wrenches=merged(found.wrenches, forces),
                   joints=found.joints if joints is None else joints,
                   time=found.time if time is None else time)  # fmt: skip


def map_toml(mapping: RecordingMap) -> str:
    """The map as TOML text (a recorded run file stores it; :func:`read_map` reads it back)."""

    def sensor(key: str, s: SensorMap) -> str:
        extra = f"frame_id = {dumps(s.frame)}\n" if s.frame else ""
        extra += f"columns = {dumps(list(s.columns))}\n" if s.columns else ""
        return f"\n[[{key}]]\nname = {dumps(s.name)}\ntopic = {dumps(s.topic)}\n{extra}"

    text = f"time = {dumps(mapping.time)}\ntime_column = {dumps(mapping.time_column)}\n"
    text += "" if mapping.joints is None else f"\n[joints]\ntopic = {dumps(mapping.joints)}\n"
    text += "".join(sensor("imu", s) for s in mapping.imus)
    return text + "".join(sensor("wrench", s) for s in mapping.wrenches)
