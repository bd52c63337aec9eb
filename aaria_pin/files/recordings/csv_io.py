"""A recorded run as CSV, and back: one table, one time column, a column per signal.

:func:`write_csv` writes a run whose streams share one time axis (a simulated run's) as a
header row ``time``, ``imu:<name>:wx`` … ``imu:<name>:fz``, ``q:<joint>``, ``qd:<joint>``,
``tau:<joint>``, ``wrench:<name>:fx`` … ``:mz``, after a comment line holding the run's
``time_origin_ns``; floats are written as Python's ``repr`` writes them (the shortest text that
reads back to the same float64: the round trip is bit for bit). :func:`read_csv` reads such a
file, or a CSV of a lab's logger through a map (each IMU's six columns, the time column).
"""

from __future__ import annotations

import csv
import io
import re
from pathlib import Path

import numpy as np

from aaria_pin.core.recording import STREAM_COLUMNS, RecordedRun, SensorStream
from aaria_pin.errors import InputFileError, ParameterError
from aaria_pin.files.recordings.mapping import RecordingMap

__all__ = ["read_csv", "write_csv"]

_ORIGIN = re.compile(r"time_origin_ns\s*=\s*(-?\d+)")
"""The comment line that holds the run's time origin."""

_JOINT_GROUPS = ("q", "qd", "tau")


def _column_names(stream: SensorStream) -> list[str]:
    """A stream's columns in the CSV header."""
    if stream.kind == "joints":
        return list(stream.columns)
    return [f"{stream.kind}:{stream.name}:{c}" for c in stream.columns]


def write_csv(path: str | Path, run: RecordedRun) -> Path:
    """Write a run's streams as one CSV table (module docstring).

    Raises:
        ParameterError: streams on different time axes (parameter ``form``: another format
            keeps each sensor's own time).
    """
    from aaria_pin.files.paths import atomic_output

    out = Path(path)
    time = run.streams[0].time if run.streams else np.zeros(0)
    for stream in run.streams:
        if not np.array_equal(stream.time, time):
            raise ParameterError(
                f"form csv needs one time axis; stream {stream.name} has its own; allowed: mcap,"
                " ros1, sqlite3, ros2-sqlite3, ros2-mcap (each sensor at its own time)",
                parameter="form",
            )
    header = ["time", *(c for s in run.streams for c in _column_names(s))]
    table = np.column_stack([time, *(s.values for s in run.streams)])
    buffer = io.StringIO()
    buffer.write(f"# aaria_pin recording: time [s] from time_origin_ns = {run.time_origin_ns}\n")
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(header)
    writer.writerows(table.tolist())  # Python floats: repr, exact
    with atomic_output(out) as temporary:
        temporary.write_text(buffer.getvalue(), encoding="utf-8")
    return out


def read_csv(path: str | Path, mapping: RecordingMap | None = None) -> RecordedRun:
    """The recorded run of a CSV table (module docstring).

    Without a map the columns are named as :func:`write_csv` names them; a map's IMUs (and
    wrenches) with ``columns`` take those six columns, its ``time_column`` is the time [s].

    Raises:
        InputFileError: no header, no time column, a mapped column missing, a cell that is not
            a number, time not increasing or a value not finite (one line; parameter ``file``).
    """
    from aaria_pin.files.io import read_csv_table

    file = Path(path)
    if not file.is_file():
        raise InputFileError(f"{file}: no such file", parameter="file")
    mapping = mapping or RecordingMap()
    table, header = read_csv_table(file)
    first = file.read_text(encoding="utf-8-sig").split("\n", 1)[0]
    found = _ORIGIN.search(first) if first.startswith("#") else None
    if header is None or mapping.time_column not in header:
        raise InputFileError(f"{file} has no column {mapping.time_column}; allowed: a header row"
                             " with a time column [s]", parameter="file")  # fmt: skip
    index = {name: k for k, name in enumerate(header)}
    time = table[:, index[mapping.time_column]]

    def take(names: list[str] | tuple[str, ...], what: str) -> np.ndarray:
        missing = [n for n in names if n not in index]
        if missing:
            raise InputFileError(f"{file}: column {missing[0]} ({what}) is not in the header;"
                                 f" allowed: {', '.join(header or ())}",
                                 parameter="file")  # fmt: skip
        return table[:, [index[n] for n in names]]

    parts: list[tuple[str, str, np.ndarray, tuple[str, ...]]] = []
    for kind, sensors in (("imu", mapping.imus), ("wrench", mapping.wrenches)):
        for sensor in sensors:
            columns = sensor.columns or tuple(
                f"{kind}:{sensor.name}:{c}" for c in STREAM_COLUMNS[kind]
            )
            parts.append(
                (sensor.name, kind, take(columns, f"{kind} {sensor.name}"), STREAM_COLUMNS[kind])
            )
        if not sensors:
            names = dict.fromkeys(
                h.split(":")[1] for h in header if h.startswith(f"{kind}:") and h.count(":") == 2
            )
            for name in names:
                columns = tuple(f"{kind}:{name}:{c}" for c in STREAM_COLUMNS[kind])
                parts.append((name, kind, take(columns, f"{kind} {name}"), STREAM_COLUMNS[kind]))
    joints = tuple(h for h in header if h.split(":")[0] in _JOINT_GROUPS and h.count(":") == 1)
    if joints:
        parts.append(("joints", "joints", take(joints, "joints"), joints))
    if not any(kind == "imu" for _, kind, _, _ in parts):
        raise InputFileError(f"{file} has no IMU columns; allowed: imu:<name>:wx … fz, or a map's"
                             " [[imu]] columns", parameter="file")  # fmt: skip
    try:
        streams = [SensorStream(n, k, time, v, c, source=str(file)) for n, k, v, c in parts]
        origin = int(found.group(1)) if found else 0
        return RecordedRun(streams, time_origin_ns=origin, source=str(file))
    except ParameterError as exc:
        raise InputFileError(f"{file}: {exc}", parameter="file") from None
