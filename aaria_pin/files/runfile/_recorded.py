"""The recorded kind of run file: what a robot measured, each sensor at its own time stamps.

An HDF5 run file (``format = "aaria_pin run"``, ``format_version`` 2) of ``kind = "recorded"``
holds a :class:`~aaria_pin.core.recording.RecordedRun` (``aaria import`` writes it). Root
attributes: ``time_origin_ns`` (int64: the stamp every stream's time counts from [ns]),
``source`` (the recording), ``source_format`` (``ros1``, ``mcap``, ``sqlite3``, ``ros2``,
``csv``), ``mapping_toml`` (the map used, as TOML text), ``streams_json`` (the streams in
order: name, kind, source, columns) and ``checksums`` (each array's CRC-32, as for every run
file). One pair of flat datasets per stream, named by kind and index (valid MATLAB names):
``imu0_time`` (N, float64, seconds from ``time_origin_ns``) and ``imu0`` (N × 6: ``wx wy wz``
[rad/s], ``fx fy fz`` [m/s²]); ``joints0_time``, ``joints0`` (N × C: ``q:<joint>`` [rad or m],
``qd:<joint>`` [rad/s or m/s], ``tau:<joint>`` [N·m or N], the groups recorded);
``wrench0_time``, ``wrench0`` (N × 6: ``fx fy fz`` [N], ``mx my mz`` [N·m]). Always float64:
float32 time stamps broke fits (issue 26). There is no truth (no true joint values, no RNEA
torques): a command that needs it refuses such a file in one line
(:func:`refuse_recorded`).
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.recording import RecordedRun, SensorStream
from aaria_pin.errors import InputFileError, ParameterError

__all__ = [
    "RECORDED_KIND",
    "is_recorded_file",
    "is_recorded_run",
    "read_recorded_run",
    "recorded_summary",
    "refuse_recorded",
    "stream_line",
    "stream_summary",
    "write_recorded_run",
]

RECORDED_KIND = "recorded"
"""The ``kind`` attribute of a recorded run file."""


def _names(run: RecordedRun) -> list[str]:
    """Each stream's dataset name (kind and index within the kind)."""
    counts: dict[str, int] = {}
    names = []
    for stream in run.streams:
        names.append(f"{stream.kind}{counts.get(stream.kind, 0)}")
        counts[stream.kind] = counts.get(stream.kind, 0) + 1
    return names


def write_recorded_run(
    path: str | os.PathLike[str], run: RecordedRun, source_format: str = "", mapping_toml: str = ""
) -> Path:
    """Write a recorded run file (module docstring), atomically.

    Args:
        path: the output (``.h5`` or ``.hdf5``)
        run: the streams
        source_format: the recording's format
        mapping_toml: the map used, as TOML text

    Raises:
        OutputFileError: an output that is not ``.h5``/``.hdf5`` (parameter ``path``), or
            cannot be written.
    """
    import h5py

    from aaria_pin.errors import OutputFileError
    from aaria_pin.files._stored import crc32_function
    from aaria_pin.files.paths import atomic_output
    from aaria_pin.files.runfile._attributes import RUN_FORMAT, RUN_FORMAT_VERSION
    from aaria_pin.files.runfile._checksums import CHECKSUMS_ATTRIBUTE, _text, crc_of_values

    out = Path(path)
    if out.suffix.lower() not in (".h5", ".hdf5"):
        raise OutputFileError(f"path {out} is not .h5 or .hdf5; allowed: a recorded run is an"
                              " HDF5 run file", parameter="path")  # fmt: skip
    crc32 = crc32_function()
    checksums: dict[str, str] = {}
    streams = [{"name": s.name, "kind": s.kind, "source": s.source, "columns": list(s.columns)}
               for s in run.streams]  # fmt: skip
    with atomic_output(out) as temporary, h5py.File(temporary, "w") as handle:
        attrs = handle.attrs
        attrs["format"], attrs["format_version"] = RUN_FORMAT, RUN_FORMAT_VERSION
        attrs["kind"], attrs["time_origin_ns"] = RECORDED_KIND, np.int64(run.time_origin_ns)
        attrs["source"], attrs["source_format"] = run.source, source_format
        attrs["mapping_toml"], attrs["streams_json"] = mapping_toml, json.dumps(streams)
        for name, stream in zip(_names(run), run.streams, strict=True):
            for key, data in ((f"{name}_time", stream.time), (name, stream.values)):
                handle.create_dataset(key, data=np.asarray(data, np.float64))
                checksums[key] = _text(crc_of_values(crc32, data))
            handle[f"{name}_time"].attrs["units"] = "s"
            handle[name].attrs["columns"] = ",".join(stream.columns)
        attrs[CHECKSUMS_ATTRIBUTE] = json.dumps(checksums)
    return out


def is_recorded_run(handle: Any) -> bool:
    """Whether an open HDF5 file is a recorded run file."""
    kind = handle.attrs.get("kind")
    return (kind.decode() if isinstance(kind, bytes) else kind) == RECORDED_KIND


def is_recorded_file(path: str | os.PathLike[str]) -> bool:
    """Whether ``path`` is an HDF5 file of a recorded run (False for any other or none)."""
    import h5py

    try:
        with h5py.File(path, "r") as handle:
            return is_recorded_run(handle)
    except (OSError, ValueError):
        return False


def refuse_recorded(file: str | os.PathLike[str]) -> InputFileError:
    """The one line a command that needs a simulated run (its truth, its model) says."""
    return InputFileError(f"{file} is a recorded run (measured signals only); allowed: a"
                          " simulated run (a recorded run: aaria info, aaria export, aaria"
                          " identify FILE for an Aaria arm's DH table, aaria identify"
                          " --rigid/--joint)",
                          parameter="file")  # fmt: skip


def read_recorded_run(path: str | os.PathLike[str]) -> RecordedRun:
    """The recorded run of a recorded run file, its arrays verified.

    Raises:
        InputFileError: not a recorded run file, a damaged array, a stream whose time does not
            increase or whose values are not finite (parameter ``file``).
    """
    import h5py

    from aaria_pin.files._stored import damaged_errors
    from aaria_pin.files.runfile._checksums import stored_checksums, verify_checksums

    file = Path(path)
    if not file.is_file():
        raise InputFileError(f"{file}: no such file", parameter="file")
    with damaged_errors(file), h5py.File(file, "r") as handle:
        if not is_recorded_run(handle):
            raise InputFileError(f"{file} is not a recorded run; allowed: a file written by aaria"
                                 " import", parameter="file")  # fmt: skip
        attrs = handle.attrs
        entries = json.loads(attrs["streams_json"])
        arrays = {key: handle[key][()] for key in handle}
        verify_checksums(file, stored_checksums(file, attrs.get("checksums")), arrays)
        origin, source = int(attrs["time_origin_ns"]), str(attrs.get("source", ""))
    counts: dict[str, int] = {}
    streams = []
    try:
        for entry in entries:
            kind = entry["kind"]
            name = f"{kind}{counts.get(kind, 0)}"
            counts[kind] = counts.get(kind, 0) + 1
            streams.append(SensorStream(entry["name"], kind, arrays[f"{name}_time"], arrays[name],
                                        tuple(entry["columns"]), entry["source"]))  # fmt: skip
        return RecordedRun(streams, origin, source)
    except (ParameterError, KeyError) as exc:
        raise InputFileError(f"{file}: {exc}; allowed: a recorded run as aaria import writes it",
                             parameter="file") from None  # fmt: skip


def recorded_summary(path: str | os.PathLike[str]) -> tuple[dict[str, Any], str]:
    """A recorded run file's summary (for ``aaria info``): as numbers and as text."""
    run = read_recorded_run(path)
    rows = [stream_summary(s) for s in run.streams]
    summary = {"path": str(path), "kind": RECORDED_KIND, "source": run.source,
               "time_origin_ns": run.time_origin_ns, "streams": rows}  # fmt: skip
    lines = [f"{path}: recorded run (measured signals only) of {run.source or 'unknown'},"
             f" {len(rows)} streams, time from {run.time_origin_ns} ns"]  # fmt: skip
    lines += [stream_line(row) for row in rows]
    return summary, "\n".join(lines) + "\n"


def stream_summary(stream: SensorStream) -> dict[str, Any]:
    """A stream's name, kind, source, samples, rate [Hz], span [s] and columns."""
    span = float(stream.time[-1] - stream.time[0]) if stream.time.size else 0.0
    return {"name": stream.name, "kind": stream.kind, "source": stream.source,
            "samples": stream.time.size, "rate": stream.rate, "span": span,
            "columns": list(stream.columns)}  # fmt: skip


def stream_line(row: dict[str, Any]) -> str:
    """One stream's line: name, kind, source, samples, rate [Hz], span [s]."""
    return (f"  {row['kind']:6s} {row['name']:16s} {row['samples']:7d} samples"
            f" {row['rate']:9.3f} Hz {row['span']:9.3f} s  {row['source']}")  # fmt: skip
