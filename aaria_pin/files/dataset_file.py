"""The HDF5 file of a data set: run arrays with a leading run axis, written one run at a time.

Layout (``format = "aaria_pin dataset"``, ``format_version = 1``): the datasets of a run file
with a leading run axis, ``senSen`` (N × T × 91), ``senSenDH`` (N × 8 × 5), ``senSenJ``
(N × 8 × 5), ``senSenB`` (N × 6 × 4: a 2 × 4 table is stored expanded, one row per axis),
``q``, ``qd``, ``qdd``, ``tau``, ``base_wrench`` (N × T × 6), ``tool_pose`` (N × T × 4 × 4),
``imu_mount`` (N × 14 × 4 × 4); the time series in the data set's dtype, the inputs (tables
and mounts) in float64; ``complete`` (N, uint8: 1 once a run
is written and flushed) and ``failed`` (N, uint8). Each array is chunked one run per chunk and
compressed with gzip level 1 after the shuffle filter (the filter MATLAB's ``h5read`` reads; at
level 1 it costs little more than lzf on shuffled floats). The workers compress the chunks
(:func:`encode_run`) and the writer stores them as they are (HDF5's direct chunk write), so
compression runs in parallel. ``checksum`` (N × 11, uint32) holds the CRC-32 of each run's
arrays, so a run damaged by a crash is found on resume. File attributes: those of a run file (rate,
duration, noise, noise parameters, gravity, units, version) plus ``N``, ``seed``, ``vary``,
``config_json`` and ``dtype``; ``failures_json`` lists failed runs with their error.
"""

from __future__ import annotations

import json
import os
import zlib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.aaria.sensen import SENSEN_COLUMNS
from aaria_pin.core.se3 import Array
from aaria_pin.errors import InputFileError, OutputFileError
from aaria_pin.files.io import atomic_output

__all__ = [
    "AARIA_LAYOUT",
    "DATASET_FORMAT",
    "DATASET_FORMAT_VERSION",
    "INPUT_ARRAYS",
    "RUN_ARRAYS",
    "DatasetFile",
    "RunLayout",
    "decode_attributes",
    "encode_run",
    "file_layout",
    "is_dataset_file",
    "read_dataset_attributes",
    "run_shapes",
]

DATASET_FORMAT = "aaria_pin dataset"
DATASET_FORMAT_VERSION = 1


def run_shapes(samples: int) -> dict[str, tuple[int, ...]]:
    """Shape of each array of one run of ``samples`` samples, in file order."""
    return {
        "senSen": (samples, len(SENSEN_COLUMNS)),
        "senSenDH": (8, 5),
        "senSenJ": (8, 5),
        "senSenB": (6, 4),
        "q": (samples, 6),
        "qd": (samples, 6),
        "qdd": (samples, 6),
        "tau": (samples, 6),
        "base_wrench": (samples, 6),
        "tool_pose": (samples, 4, 4),
        "imu_mount": (14, 4, 4),
    }


RUN_ARRAYS = tuple(run_shapes(1))
"""Names of the per-run arrays, in file order."""

INPUT_ARRAYS = ("senSenDH", "senSenJ", "senSenB", "imu_mount")
"""The run inputs, always stored as float64 so a run can be re-made exactly."""


@dataclass(frozen=True)
class RunLayout:
    """The arrays of one run of a data set: names, shapes, which are inputs, column names.

    Attributes:
        shapes: shape of each array of one run, in file order; -1 stands for the T samples
        inputs: the arrays stored as float64 whatever the data set's dtype
        columns: column names of the first array (``senSen`` or ``signals``)
        strings: text datasets written once per file (e.g. ``urdf``)
    """

    shapes: dict[str, tuple[int, ...]]
    inputs: tuple[str, ...]
    columns: tuple[str, ...]
    strings: dict[str, str] = field(default_factory=dict)

    @property
    def names(self) -> tuple[str, ...]:
        """Array names, in file order."""
        return tuple(self.shapes)

    def run_shapes(self, samples: int) -> dict[str, tuple[int, ...]]:
        """Shapes of one run's arrays for T = ``samples``."""
        return {
            name: tuple(samples if dim == -1 else dim for dim in shape)
            for name, shape in self.shapes.items()
        }

    def to_json(self) -> str:
        """The layout as the file's ``layout_json`` attribute (strings and columns apart)."""
        return json.dumps(
            {"shapes": {k: list(v) for k, v in self.shapes.items()}, "inputs": list(self.inputs)}
        )


AARIA_LAYOUT = RunLayout(
    {
        name: tuple(-1 if dim == 0 else dim for dim in shape)
        for name, shape in run_shapes(0).items()
    },
    INPUT_ARRAYS,
    SENSEN_COLUMNS,
)
"""The Aaria run layout (``senSen`` and the 8 × 5 tables); files without ``layout_json``."""


def file_layout(handle: Any) -> RunLayout:
    """The run layout of an open data set file (Aaria when it records none)."""
    text = handle.attrs.get("layout_json")
    if text is None:
        return AARIA_LAYOUT
    data = json.loads(text)
    shapes = {name: tuple(shape) for name, shape in data["shapes"].items()}
    first = handle[next(iter(shapes))]
    columns = tuple(str(c) for c in first.attrs.get("columns", ()))
    return RunLayout(shapes, tuple(data["inputs"]), columns)


def decode_attributes(attrs: Mapping[str, Any]) -> dict[str, Any]:
    """HDF5 attributes as plain values: JSON ones decoded (keys without ``_json``)."""
    out: dict[str, Any] = {}
    for key, value in attrs.items():
        if key.endswith("_json"):
            out[key[: -len("_json")]] = json.loads(value)
        else:
            out[key] = value.item() if isinstance(value, np.generic) else value
    return out


def _json_safe(value: Any) -> Any:
    if isinstance(value, (str, bool, int, float)):
        return value
    return json.dumps(value)


class DatasetFile:
    """An open data set file, for writing runs into it or resuming it.

    Use :meth:`create` or :meth:`open_for_resume`; close with :meth:`close` (or a ``with``
    block).
    """

    def __init__(self, handle: Any, path: Path) -> None:
        self._handle = handle
        self.path = path
        self.layout = file_layout(handle)
        self._datasets = {name: handle[name] for name in self.layout.names}
        self._pending: dict[int, list[int]] = {}  # run -> checksums, written at the next flush

    @classmethod
    def create(
        cls,
        path: str | os.PathLike[str],
        n_runs: int,
        samples: int,
        dtype: str,
        attributes: Mapping[str, Any],
        layout: RunLayout = AARIA_LAYOUT,
    ) -> DatasetFile:
        """Create a new data set file (an existing file at ``path`` is replaced).

        The file is made under a temporary name and renamed when its layout is complete, so a
        crash during creation leaves no half-made file at ``path``.

        Args:
            path: the ``.h5`` file
            n_runs: number of runs N
            samples: samples per run T
            dtype: ``"float32"`` or ``"float64"``
            attributes: file attributes (numbers and strings as they are, others as JSON)
            layout: the arrays of a run (default the Aaria layout)

        Raises:
            OutputFileError: the file cannot be created.
        """
        file = Path(path)
        with atomic_output(file) as temporary:
            handle = _new_file(temporary, n_runs, samples, dtype, attributes, layout)
            handle.close()
        return cls._open(file)

    @classmethod
    def _open(cls, file: Path) -> DatasetFile:
        import h5py

        try:
            handle = h5py.File(file, "r+")
        except OSError as exc:
            raise InputFileError(f"{file}: cannot be opened ({exc})") from None
        return cls(handle, file)

    @classmethod
    def open_for_resume(cls, path: str | os.PathLike[str]) -> DatasetFile:
        """Reopen a data set to continue it: a fresh copy of its intact runs replaces it.

        Every run flagged complete whose stored chunks match their CRC-32 is copied, chunk bytes
        as they are, into a new file that then replaces the old one; damaged, unflagged and
        half-written runs are left out, to be redone. A crash can leave HDF5's chunk index
        pointing past the end of the file; the copy starts from clean metadata.

        Raises:
            InputFileError: missing, unreadable, or not a complete data set layout.
        """
        file = Path(path)
        old = _open_dataset_read_only(file)
        try:
            attrs = dict(old.attrs)
            n_runs, samples = int(attrs.pop("N")), int(attrs.pop("samples"))
            dtype = str(attrs.pop("dtype"))
            for key in ("format", "format_version"):
                attrs.pop(key, None)
            layout = file_layout(old)
            strings = {
                name: old[name].asstr()[()]
                for name in old
                if name not in (*layout.names, "checksum", "complete", "failed")
            }
            layout = RunLayout(layout.shapes, layout.inputs, layout.columns, strings)
            attrs.pop("layout_json", None)
            with atomic_output(file) as temporary:
                new = _new_file(temporary, n_runs, samples, dtype, {}, layout, raw_attributes=attrs)
                _copy_intact_runs(old, new)
                new.close()
        finally:
            old.close()
        return cls._open(file)

    @property
    def attributes(self) -> dict[str, Any]:
        """File attributes, JSON ones decoded (keys without the ``_json`` suffix)."""
        return decode_attributes(self._handle.attrs)

    @property
    def n_runs(self) -> int:
        """Number of runs N."""
        return int(self._handle.attrs["N"])

    def complete_runs(self) -> np.ndarray:
        """Boolean mask of the runs that are complete."""
        return np.asarray(self._handle["complete"][()], dtype=bool)

    def write_run(self, run: int, encoded: Mapping[str, tuple[bytes, int]]) -> None:
        """Store run ``run``'s encoded chunks (see :func:`encode_run`) and mark it complete.

        The file is flushed by :meth:`flush`; a crash before then loses the run, and a crash
        during it leaves a run whose checksum fails, which a resumed job redoes.
        """
        checksums = []
        for name in self.layout.names:
            data, checksum = encoded[name]
            dataset = self._datasets[name]
            dataset.id.write_direct_chunk((run,) + (0,) * (dataset.ndim - 1), data)
            checksums.append(checksum)
        self._pending[run] = checksums

    def flush(self) -> None:
        """Mark the runs written since the last flush complete, and push it all to disk.

        The chunks are flushed before the flags, so a flag never points at data still in memory.
        """
        if self._pending:
            self._handle.flush()
            runs = sorted(self._pending)
            self._handle["checksum"][runs] = np.array([self._pending[k] for k in runs])
            self._handle["complete"][runs] = 1
            self._handle["failed"][runs] = 0
            self._pending.clear()
        self._handle.flush()

    def mark_failed(self, run: int, message: str) -> None:
        """Record that run ``run`` failed, with its error message."""
        failures = json.loads(self._handle.attrs["failures_json"])
        failures[str(run)] = message
        self._handle.attrs["failures_json"] = json.dumps(failures)
        self._handle["failed"][run] = 1
        self._handle.flush()

    def clear_failures(self) -> None:
        """Forget earlier failures (before a resumed job retries them)."""
        self._handle.attrs["failures_json"] = "{}"
        self._handle["failed"][...] = 0

    def failures(self) -> dict[int, str]:
        """Failed runs and their error messages."""
        return {int(k): v for k, v in json.loads(self._handle.attrs["failures_json"]).items()}

    def close(self) -> None:
        """Flush and close the file."""
        self.flush()
        self._handle.close()

    def __enter__(self) -> DatasetFile:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def encode_run(
    arrays: Mapping[str, Array], dtype: str, inputs: tuple[str, ...] = INPUT_ARRAYS
) -> dict[str, tuple[bytes, int]]:
    """Each array of a run as the bytes of its HDF5 chunk, and the CRC-32 of those bytes.

    The chunk is what HDF5's filters make of it: the shuffle filter (byte ``j`` of every
    element together), then deflate, so h5py, MATLAB and any HDF5 reader decode it. Deflate runs
    through ISA-L (``isal``: a standard zlib stream, about 8 times faster than zlib at the same
    size), or zlib where ``isal`` is missing. Inputs (tables, mounts) stay float64, time series
    take ``dtype``. The arrays are encoded in the order given (the layout's file order).
    """
    try:
        from isal.isal_zlib import compress
    except ImportError:  # pragma: no cover - isal is a dependency; zlib makes the same format
        from zlib import compress
    encoded = {}
    for name, value in arrays.items():
        array = np.ascontiguousarray(value, dtype="float64" if name in inputs else dtype)
        shuffled = array.view(np.uint8).reshape(-1, array.itemsize).T.tobytes()
        chunk = compress(shuffled, 1)
        encoded[name] = (chunk, zlib.crc32(chunk))
    return encoded


def _new_file(
    path: Path,
    n_runs: int,
    samples: int,
    dtype: str,
    attributes: Mapping[str, Any],
    layout: RunLayout,
    raw_attributes: Mapping[str, Any] | None = None,
) -> Any:
    """Write the empty layout of a data set into ``path`` and return the open h5py file."""
    import h5py

    try:
        handle = h5py.File(path, "w", track_order=True)
    except OSError as exc:
        raise OutputFileError(f"{path}: cannot be created ({exc})") from None
    handle.attrs["format"] = DATASET_FORMAT
    handle.attrs["format_version"] = DATASET_FORMAT_VERSION
    handle.attrs["N"] = n_runs
    handle.attrs["samples"] = samples
    handle.attrs["dtype"] = dtype
    for key, value in attributes.items():
        safe = _json_safe(value)
        handle.attrs[key if safe is value else f"{key}_json"] = safe
    for key, value in (raw_attributes or {}).items():
        handle.attrs[key] = value
    handle.attrs.setdefault("failures_json", "{}")
    if layout is not AARIA_LAYOUT:
        handle.attrs["layout_json"] = layout.to_json()
    strings = h5py.string_dtype("utf-8")
    for index, (name, shape) in enumerate(layout.run_shapes(samples).items()):
        dataset = handle.create_dataset(
            name,
            shape=(n_runs, *shape),
            dtype="float64" if name in layout.inputs else dtype,
            chunks=(1, *shape),
            compression="gzip",
            compression_opts=1,
            shuffle=True,
        )
        if index == 0:
            dataset.attrs.create("columns", list(layout.columns), dtype=strings)
    for name, text in layout.strings.items():
        handle.create_dataset(name, data=text, dtype=strings)
    handle.create_dataset("checksum", shape=(n_runs, len(layout.shapes)), dtype="u4")
    handle.create_dataset("complete", shape=(n_runs,), dtype="u1", fillvalue=0)
    handle.create_dataset("failed", shape=(n_runs,), dtype="u1", fillvalue=0)
    handle.flush()
    return handle


def _open_dataset_read_only(file: Path) -> Any:
    """Open a data set for reading, refusing anything that is not a complete layout."""
    import h5py

    if not file.is_file():
        raise InputFileError(f"{file}: no such file to resume")
    try:
        handle = h5py.File(file, "r")
    except OSError as exc:
        raise InputFileError(
            f"{file}: cannot be opened ({exc}); allowed: --overwrite to start again"
        ) from None
    if handle.attrs.get("format") != DATASET_FORMAT:
        handle.close()
        raise InputFileError(f"{file}: not a complete aaria_pin data set; cannot resume it")
    names = file_layout(handle).names
    missing = [name for name in (*names, "checksum", "complete") if name not in handle]
    if missing:
        handle.close()
        raise InputFileError(f"{file}: not a complete aaria_pin data set; cannot resume it")
    return handle


def is_dataset_file(path: str | os.PathLike[str]) -> bool:
    """Whether a file is an aaria_pin data set (an HDF5 file with its ``format``).

    Raises:
        InputFileError: an ``.h5`` file that HDF5 cannot read.
    """
    import h5py

    file = Path(path)
    if file.suffix.lower() not in (".h5", ".hdf5") or not file.is_file():
        return False
    try:
        with h5py.File(file, "r") as handle:
            return bool(handle.attrs.get("format") == DATASET_FORMAT)
    except OSError as exc:
        raise InputFileError(f"{file}: cannot be read as HDF5 ({exc})") from None


def read_dataset_attributes(path: str | os.PathLike[str]) -> dict[str, Any]:
    """A data set's attributes (decoded), opening it read-only."""
    handle = _open_dataset_read_only(Path(path))
    try:
        return decode_attributes(handle.attrs)
    finally:
        handle.close()


def _copy_intact_runs(old: Any, new: Any) -> None:
    """Copy the chunk bytes of every complete run whose CRC-32 matches into ``new``."""
    complete = np.asarray(old["complete"][()], dtype=bool)
    names = file_layout(old).names
    checksums = old["checksum"][()]
    intact = []
    for run in np.flatnonzero(complete):
        chunks = []
        try:
            for index, name in enumerate(names):
                origin = (int(run),) + (0,) * (old[name].ndim - 1)
                _, data = old[name].id.read_direct_chunk(origin)
                if zlib.crc32(data) != checksums[run, index]:
                    raise ValueError("checksum")
                chunks.append((name, origin, data))
        except (OSError, ValueError, KeyError):
            continue
        for name, origin, data in chunks:
            new[name].id.write_direct_chunk(origin, data)
        intact.append(int(run))
    if intact:
        new["checksum"][intact] = checksums[intact]
        new["complete"][intact] = 1
    new.flush()


def check_dataset_path(path: Path, resume: bool, overwrite: bool) -> None:
    """Refuse an output that exists without ``resume``/``overwrite``, or a missing folder.

    Raises:
        OutputFileError: as above, naming the flag to use.
    """
    if resume and overwrite:
        raise OutputFileError("--resume and --overwrite exclude each other; allowed: one of them")
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise OutputFileError(f"{path}: folder {folder} does not exist")
    if path.suffix.lower() not in (".h5", ".hdf5"):
        raise OutputFileError(f"{path}: unknown data set type {path.suffix!r}; allowed: .h5, .hdf5")
    if path.exists() and not (resume or overwrite):
        raise OutputFileError(f"{path}: exists; allowed: --resume to continue it, --overwrite")
    if resume and not path.is_file():
        raise InputFileError(f"{path}: no such file to resume")
