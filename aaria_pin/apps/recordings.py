"""Recordings in and out: a run exported as a robot would have recorded it, a recording imported.

:func:`recorded_from_run` keeps what a simulated run's sensors measured: each IMU's signals
(the slots that exist), the joint states (``q_measured`` and ``tau_measured`` where the run has
encoders and torque sensors; without torque sensors, motor currents times each joint's
``k_t·N`` as a drive reports effort from them; else the true ``q`` and ``tau``; ``qd`` as
computed), and the
base wrench (``base``). :func:`export_run` writes them (or a recorded run's streams) as a ROS 1
bag, an MCAP file, a ROS 2 sqlite3 file or bag folder
(:func:`~aaria_pin.files.recordings.bag_write.write_bag`) or a CSV table
(:func:`~aaria_pin.files.recordings.csv_io.write_csv`), so Foxglove and PlotJuggler open a
simulated run; :func:`import_recordings` reads recordings back
(:func:`~aaria_pin.files.recordings.bag_read.read_bag`,
:func:`~aaria_pin.files.recordings.csv_io.read_csv`) to the same arrays. :func:`export_file`
and :func:`import_file` are ``aaria export`` and ``aaria import``: file in, file out, the
lines they print.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np

from aaria_pin.core.arguments import checked
from aaria_pin.core.current_sensor import recorded_per_ampere
from aaria_pin.core.record import RunRecord
from aaria_pin.core.recording import STREAM_COLUMNS, RecordedRun, SensorStream
from aaria_pin.errors import InputFileError, ParameterError
from aaria_pin.files.recordings.mapping import RecordingMap

__all__ = [
    "export_file",
    "export_run",
    "import_file",
    "import_recordings",
    "open_recorded",
    "recorded_from_run",
    "recorded_input",
    "recording_format",
]


def recorded_from_run(record: RunRecord) -> RecordedRun:
    """The streams a robot would have recorded of a simulated run (module docstring)."""
    time = np.asarray(record.time, dtype=np.float64)
    streams = [
        SensorStream(mount.name, "imu", time, record.imu[:, slot], STREAM_COLUMNS["imu"])
        for slot, mount in enumerate(record.imu_mounts)
        if mount.parent
    ]
    q = record.tables.get("q_measured", record.q)
    tau = record.tables.get("tau_measured")
    if tau is None and "current_measured" in record.tables:  # a joint's torque from its current
        per_ampere = recorded_per_ampere(record.attributes, record.q.shape[1])
        if per_ampere is not None:
            tau = record.tables["current_measured"] * per_ampere
    tau = record.tau if tau is None else tau
    joints = record.joint_names
    columns = tuple(f"{group}:{j}" for group in ("q", "qd", "tau") for j in joints)
    values = np.concatenate([q, record.qd, tau], axis=1)
    streams.append(SensorStream("joints", "joints", time, values, columns))
    streams.append(
        SensorStream("base", "wrench", time, record.base_wrench, STREAM_COLUMNS["wrench"])
    )
    return RecordedRun(streams, source=str(record.attributes.get("robot", "")))


def recorded_input(path: str | os.PathLike[str], run: int | None = None) -> RecordedRun | None:
    """The recorded run of a recording or a recorded run file; None for a run or a data set.

    A ROS 1/ROS 2 bag (file or folder), an MCAP file or a CSV is read as ``aaria import`` reads
    it without a map (:func:`import_recordings`); a recorded run file as ``aaria import`` wrote
    it. With ``run`` given the file is a data set: None.

    Raises:
        InputFileError, ParameterError: as :func:`import_recordings` and
            :func:`~aaria_pin.files.runfile.read_recorded_run`.
    """
    from aaria_pin.files.runfile import is_recorded_file, read_recorded_run

    if run is None and is_recording(Path(path)):
        return import_recordings([path])
    if run is None and is_recorded_file(path):
        return read_recorded_run(path)
    return None


@checked
def open_recorded(path: str | os.PathLike[str], run: int | None = None) -> RecordedRun:
    """The recorded streams of a recording, a recorded run, a run or run ``run`` of a data set.

    A recording or a recorded run file as :func:`recorded_input` reads it; a simulated run's
    streams as :func:`recorded_from_run` makes them.

    Raises:
        InputFileError, ParameterError: as :func:`~aaria_pin.files.source.open_record` and
            :func:`import_recordings`.
    """
    from aaria_pin.files.source import open_record

    recorded = recorded_input(path, run)
    return recorded if recorded is not None else recorded_from_run(open_record(path, run))


@checked
def export_run(record: RunRecord | RecordedRun, path: str | Path, form: str | None = None) -> Path:
    """Write a run's recorded streams to ``path`` (module docstring).

    Args:
        record: a simulated run (its measured streams are written) or a recorded run
        path: the output: ``.mcap``, ``.bag``, ``.db3``, ``.csv`` or a ROS 2 bag folder
        form: the format (:data:`~aaria_pin.files.recordings.bag_format.EXPORT_FORMATS`);
            None: by the suffix

    Raises:
        ParameterError: an unknown format, or not the path's (parameter ``form``).
        InputFileError: ``rosbags`` missing.
    """
    from aaria_pin.files.recordings.bag_format import export_format
    from aaria_pin.files.recordings.bag_write import write_bag
    from aaria_pin.files.recordings.csv_io import write_csv

    run = record if isinstance(record, RecordedRun) else recorded_from_run(record)
    if export_format(Path(path), form) == "csv":
        return write_csv(path, run)
    return write_bag(path, run, form)


def export_file(
    path: str | os.PathLike[str], run: int | None, output: str | Path, form: str | None = None
) -> str:
    """``aaria export``: a run file (or run ``run`` of a data set) to a recording; its line."""
    recorded = open_recorded(path, run)
    written = export_run(recorded, output, form)
    samples = sum(s.time.size for s in recorded.streams)
    return f"wrote {written}: {len(recorded.streams)} streams, {samples} messages"


def is_recording(path: Path) -> bool:
    """Whether ``path`` is a recording :func:`recording_format` names (a folder, a bag, CSV)."""
    from aaria_pin.files.recordings.bag_format import BAG_SUFFIXES

    return path.is_dir() or path.suffix.lower() in {*BAG_SUFFIXES, ".csv"}


def recording_format(path: Path) -> str:
    """``ros2`` (a bag folder), ``csv``, or a bag file's format (by its suffix)."""
    from aaria_pin.files.recordings.bag_format import bag_format

    if path.is_dir():
        return "ros2"
    return "csv" if path.suffix.lower() == ".csv" else bag_format(path)


@checked
def import_recordings(
    paths: str | os.PathLike[str] | Sequence[str | os.PathLike[str]],
    mapping: RecordingMap | None = None,
) -> RecordedRun:
    """One recorded run of one or more recordings (their streams together, one time origin).

    Args:
        paths: a recording, or several (a split bag)
        mapping: topics or frame ids to sensor names (None: as ``aaria import`` without a map)

    Raises:
        InputFileError: a recording that is not one, damaged, or without what the map names;
            two recordings with a sensor of one name (parameter ``file``).
    """
    from aaria_pin.files.recordings.bag_read import read_bag
    from aaria_pin.files.recordings.csv_io import read_csv

    runs = []
    for path in map(Path, [paths] if isinstance(paths, str | os.PathLike) else paths):
        reader = read_csv if recording_format(path) == "csv" else read_bag
        runs.append(reader(path, mapping))
    if len(runs) == 1:
        return runs[0]
    origin = min(r.time_origin_ns for r in runs)
    parts: dict[str, list[SensorStream]] = {}
    for r in runs:  # a sensor in several recordings (a split bag): its parts in time order
        for s in r.streams:
            shifted = replace(s, time=s.time + (r.time_origin_ns - origin) / 1e9)
            parts.setdefault(s.name, []).append(shifted)
    try:
        streams = [_joined(pieces) for pieces in parts.values()]
        return RecordedRun(streams, origin, ", ".join(r.source for r in runs))
    except ParameterError as exc:
        raise InputFileError(f"{exc} (in {len(runs)} recordings)", parameter="file") from None


def _joined(pieces: list[SensorStream]) -> SensorStream:
    """One sensor's parts from several recordings, in time order, as one stream.

    Raises:
        ParameterError: parts of other kinds or columns, or overlapping in time.
    """
    first = pieces[0]
    if len(pieces) == 1:
        return first
    for piece in pieces[1:]:
        if (piece.kind, piece.columns) != (first.kind, first.columns):
            raise ParameterError(f"stream {first.name} is {piece.kind} {piece.columns} in one"
                                 f" recording and {first.kind} {first.columns} in another;"
                                 " allowed: one sensor per name", parameter="file")  # fmt: skip
    pieces = sorted(pieces, key=lambda s: float(s.time[0]) if s.time.size else 0.0)
    time = np.concatenate([s.time for s in pieces])
    values = np.concatenate([s.values for s in pieces])
    return SensorStream(first.name, first.kind, time, values, first.columns, first.source)


def import_file(
    paths: Sequence[str | os.PathLike[str]], output: str | Path, mapping: RecordingMap | None = None
) -> str:
    """``aaria import``: recordings to a recorded run file; the lines it prints.

    Per stream: kind, name, messages, rate [Hz], span [s], source.
    """
    from aaria_pin.files.recordings.mapping import map_toml
    from aaria_pin.files.runfile import stream_line, stream_summary, write_recorded_run

    run = import_recordings(paths, mapping)
    form = ",".join(sorted({recording_format(Path(p)) for p in paths}))
    write_recorded_run(output, run, form, map_toml(mapping or RecordingMap()))
    rows = [stream_summary(s) for s in run.streams]
    head = f"wrote {output}: recorded run of {len(run.streams)} streams"
    return "\n".join([head, *map(stream_line, rows)])
