"""Sharded data sets: workers write shard files, the client writes a manifest over them.

On a cluster every run's bytes would otherwise travel to the one process that writes the file.
Instead each worker task writes its runs into a **shard** (:class:`ShardWriter`): an HDF5 file
with the data set's per-run arrays stacked ``rows × …`` (the same dtypes, chunks and filters as
a one-file data set, chunk bytes as :func:`~.layout.encode_run` made them), ``run`` (rows,
int64: the run of each row), ``complete`` (rows, uint8) and ``checksum`` (rows × arrays,
uint32: the CRC-32 of each array's chunks). A shard is written under a temporary name and
renamed, so a shard present under its name is whole; its name (:func:`shard_name`) is a pure
function of the job's prefix and its runs, so a task run again (its worker died) replaces it
with the same content.

The client receives only each shard's acknowledgement (runs, rows, checksums) and writes the
output as a **manifest** (:func:`write_manifest`): an ordinary version 2 data set file whose
per-run arrays are HDF5 virtual datasets mapping each run to its row in a shard, by a path
relative to the manifest's folder (the folder with its shards can be moved), and whose views
(``senSen``, ``signals``) are virtual datasets over those as in any data set file. h5py,
MATLAB's ``h5read``, ``aaria info`` and :class:`~.reader.DatasetReader` read it as one file.
The manifest records its shards' folder and name prefix (attributes ``shard_dir``,
``shard_prefix``); ``--resume`` lists the shards by that prefix and keeps every row whose chunks
still match its checksum (:func:`verify_shard`).
"""

from __future__ import annotations

import json
import os
import zlib
from collections.abc import Iterator, Mapping, Sequence
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.errors import OutputFileError
from aaria_pin.files._stored import first_line
from aaria_pin.files.dataset.layout import (
    DatasetLayout,
    EncodedRun,
    chunk_origins,
    read_run_chunks,
)
from aaria_pin.files.dataset.store import _new_file
from aaria_pin.files.paths import atomic_output

__all__ = [
    "SHARD_FORMAT",
    "ManifestContents",
    "ManifestShards",
    "RunLocation",
    "ShardContents",
    "ShardWriter",
    "list_shards",
    "missing_shards",
    "read_manifest_shards",
    "remove_unused_shards",
    "shard_files",
    "shard_name",
    "verify_shard",
    "write_manifest",
]

SHARD_FORMAT = "aaria_pin dataset shard"
SHARD_FORMAT_VERSION = 1


@dataclass(frozen=True)
class RunLocation:
    """Where a run of a sharded data set is stored.

    Attributes:
        shard: the shard's file name (in the shard folder)
        row: the run's row in the shard
        rows: the shard's number of rows
    """

    shard: str
    row: int
    rows: int


def shard_name(prefix: str, runs: Sequence[int]) -> str:
    """The file name of the shard of ``runs``: ``<prefix>-<first run>-<CRC-32 of the runs>.h5``.

    A pure function of the job's prefix and the run list: a task made again writes the same
    name, and two different run lists of one job (a resumed job's batches) practically never
    share one.
    """
    digest = zlib.crc32(np.asarray(runs, dtype="<i8").tobytes())
    return f"{prefix}-{int(runs[0]):09d}-{digest:08x}.h5"


def list_shards(folder: Path, prefix: str) -> list[Path]:
    """The shards of the job ``prefix`` in ``folder`` (temporaries apart), sorted by name."""
    if not folder.is_dir():
        return []
    return sorted(folder.glob(f"{prefix}-*.h5"))


class ShardWriter:
    """One shard being written under a temporary name (use as a ``with`` block).

    Rows are the positions of ``runs``; a run that failed leaves its row empty (``complete``
    0). The file is renamed to :func:`shard_name` when the block ends without an exception and
    removed otherwise.

    Args:
        folder: the shard folder
        prefix: the job's shard prefix
        runs: the runs of this shard, in row order
        samples: samples per run T
        dtype: the series' dtype
        layout: the data set's layout

    Raises:
        OutputFileError: the shard cannot be created, written or renamed (one line, with the
            shard's path and the system's reason).
    """

    def __init__(
        self,
        folder: Path,
        prefix: str,
        runs: Sequence[int],
        samples: int,
        dtype: str,
        layout: DatasetLayout,
    ) -> None:
        self.path = Path(folder) / shard_name(prefix, runs)
        self.runs = tuple(int(k) for k in runs)
        self._prefix = prefix
        self._samples = samples
        self._dtype = dtype
        self._layout = layout
        self._stack = ExitStack()
        self._handle: Any = None
        self._targets: dict[str, tuple[Any, list[tuple[int, ...]]]] = {}
        self.checksums: dict[int, tuple[int, ...]] = {}

    def __enter__(self) -> ShardWriter:
        import h5py

        with _shard_errors(self.path):
            try:
                temporary = self._stack.enter_context(atomic_output(self.path))
                handle = h5py.File(temporary, "w", track_order=True)
                self._stack.callback(handle.close)
                self._lay_out(handle)
            except BaseException as exc:  # the temporary file is removed
                self._stack.__exit__(type(exc), exc, exc.__traceback__)
                raise
            self._handle = handle
        return self

    def _lay_out(self, handle: Any) -> None:
        rows = len(self.runs)
        handle.attrs["format"] = SHARD_FORMAT
        handle.attrs["format_version"] = SHARD_FORMAT_VERSION
        handle.attrs["job"] = self._prefix
        handle.attrs["samples"] = self._samples
        handle.attrs["dtype"] = self._dtype
        handle.attrs["names_json"] = json.dumps(list(self._layout.names))
        for name, shape in self._layout.shapes(self._samples).items():
            dataset = handle.create_dataset(
                name,
                shape=(rows, *shape),
                dtype="float64" if name in self._layout.inputs else self._dtype,
                chunks=(1, *self._layout.chunk(name, shape)),
                compression="gzip",
                compression_opts=1,
                shuffle=True,
            )
            origins = list(chunk_origins(shape, dataset.chunks[1:]))
            self._targets[name] = (dataset.id.write_direct_chunk, origins)
        handle.create_dataset("run", data=np.asarray(self.runs, dtype=np.int64))
        handle.create_dataset("complete", shape=(rows,), dtype="u1", fillvalue=0)
        handle.create_dataset("checksum", shape=(rows, len(self._targets)), dtype="u4")

    def write_run(self, row: int, encoded: EncodedRun) -> tuple[int, ...]:
        """Store the run of row ``row`` (its encoded chunks); returns its checksums."""
        with _shard_errors(self.path):
            checksums = []
            for name, (write, origins) in self._targets.items():
                chunks, checksum = encoded[name]
                for origin, data in zip(origins, chunks, strict=True):
                    write((row, *origin), data)
                checksums.append(int(checksum))
            self._handle["checksum"][row] = checksums
            self._handle["complete"][row] = 1
        self.checksums[self.runs[row]] = tuple(checksums)
        return tuple(checksums)

    def __exit__(self, kind: Any, exc: Any, traceback: Any) -> None:
        with _shard_errors(self.path):
            self._stack.__exit__(kind, exc, traceback)


@contextmanager
def _shard_errors(path: Path) -> Iterator[None]:
    """Turn a failure to write a shard into one OutputFileError naming it."""
    try:
        yield
    except OutputFileError:
        raise
    except Exception as exc:
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else first_line(exc)
        raise OutputFileError(
            f"shard {path}: cannot be written ({reason})", parameter="path"
        ) from None


@dataclass(frozen=True)
class ShardContents:
    """What a shard on disk holds, checked.

    Attributes:
        name: its file name
        rows: its number of rows
        intact: run → (row, checksums) of every complete row whose chunks match its checksum
        bytes: its size [bytes]
    """

    name: str
    rows: int
    intact: dict[int, tuple[int, tuple[int, ...]]]
    bytes: int


def verify_shard(path: str | os.PathLike[str], prefix: str, names: Sequence[str]) -> ShardContents:
    """Read a shard's chunks and keep the rows whose CRC-32 matches (a damaged shard: none).

    Args:
        path: the shard
        prefix: the job's prefix (a shard of another job holds nothing of this one)
        names: the data set's per-run arrays, in file order
    """
    import h5py

    file = Path(path)
    intact: dict[int, tuple[int, tuple[int, ...]]] = {}
    rows = 0
    try:
        with h5py.File(file, "r") as handle:
            if handle.attrs.get("format") != SHARD_FORMAT or handle.attrs.get("job") != prefix:
                return ShardContents(file.name, 0, {}, file.stat().st_size)
            runs = handle["run"][()]
            complete = handle["complete"][()]
            checksums = handle["checksum"][()]
            rows = len(runs)
            for row in np.flatnonzero(complete):
                try:
                    _, plain, stored = read_run_chunks(handle, names, int(row))
                except (OSError, KeyError, ValueError, RuntimeError):
                    continue
                recorded = [int(c) for c in checksums[row]]
                if recorded in (plain, stored):  # stored: an older shard (compressed CRC-32s)
                    intact[int(runs[row])] = (int(row), tuple(recorded))
        size = file.stat().st_size
    except (OSError, KeyError, ValueError, RuntimeError):  # unreadable: nothing of it is kept
        return ShardContents(file.name, 0, {}, 0)
    return ShardContents(file.name, rows, intact, size)


def _blocks(locations: Mapping[int, RunLocation]) -> Iterator[tuple[int, int, RunLocation]]:
    """Runs of consecutive indices stored in consecutive rows of one shard: (first, count, loc)."""
    runs = sorted(locations)
    i = 0
    while i < len(runs):
        first, start = runs[i], locations[runs[i]]
        count = 1
        while i + count < len(runs):
            k = runs[i + count]
            here = locations[k]
            if k != first + count or here.shard != start.shard or here.row != start.row + count:
                break
            count += 1
        yield first, count, start
        i += count


@dataclass(frozen=True)
class ManifestShards:
    """Where a sharded data set's shards are, and what its manifest records.

    Attributes:
        folder: the shard folder
        prefix: the job's shard prefix
        raw_attributes: the manifest's attributes as stored, less those a manifest sets
            itself (kept by a resumed job)
    """

    folder: Path
    prefix: str
    raw_attributes: dict[str, Any]


@dataclass(frozen=True)
class ManifestContents:
    """What :func:`write_manifest` writes: the data set's shape and where each run is.

    Attributes:
        shards: the shard folder, the job's shard prefix (attribute ``shard_prefix``) and the
            attributes stored as they are (a resumed manifest's; ``{}`` for a new one)
        n_runs: number of runs N
        samples: samples per run T
        dtype: the series' dtype
        attributes: file attributes (as :meth:`~.store.DatasetFile.create` takes them)
        layout: what every run holds
        locations: where each stored run is (none yet: empty)
        checksums: each stored run's CRC-32 per array
        failures: failed runs and their errors
    """

    shards: ManifestShards
    n_runs: int
    samples: int
    dtype: str
    attributes: Mapping[str, Any]
    layout: DatasetLayout
    locations: Mapping[int, RunLocation] = field(default_factory=dict)
    checksums: Mapping[int, Sequence[int]] = field(default_factory=dict)
    failures: Mapping[int, str] = field(default_factory=dict)


def write_manifest(path: str | os.PathLike[str], contents: ManifestContents) -> None:
    """Write (atomically) a data set file whose per-run arrays are virtual, over the shards.

    One mapping per array for each block of consecutive runs in consecutive rows of a shard;
    the shards are named by their path relative to the manifest's folder. Runs without a
    location (not made, or failed) read as zeros and are not flagged complete.

    Args:
        path: the manifest (``.h5``)
        contents: what it records

    Raises:
        OutputFileError: the manifest cannot be written.
    """
    import h5py

    file = Path(path)
    folder = file.parent if str(file.parent) else Path(".")
    shards, layout, failures = contents.shards, contents.layout, contents.failures
    try:
        relative = os.path.relpath(Path(shards.folder).resolve(), folder.resolve())
    except ValueError:  # another drive (Windows): an absolute path
        relative = str(Path(shards.folder).resolve())
    relative = Path(relative).as_posix()
    shapes = layout.shapes(contents.samples)
    virtual = {}
    blocks = list(_blocks(contents.locations))
    for name, shape in shapes.items():
        stored_dtype = "float64" if name in layout.inputs else contents.dtype
        target = h5py.VirtualLayout(shape=(contents.n_runs, *shape), dtype=stored_dtype)
        for first, count, where in blocks:
            source = h5py.VirtualSource(
                f"{relative}/{where.shard}", name, shape=(where.rows, *shape), dtype=stored_dtype
            )
            target[first : first + count] = source[where.row : where.row + count]
        virtual[name] = target
    extra = {**shards.raw_attributes, "shard_dir": relative, "shard_prefix": shards.prefix}
    extra["failures_json"] = json.dumps({str(k): v for k, v in sorted(failures.items())})
    with atomic_output(file) as temporary:
        handle = _new_file(
            temporary,
            contents.n_runs,
            contents.samples,
            contents.dtype,
            contents.attributes,
            layout,
            extra,
            virtual=virtual,
        )
        try:
            stored = sorted(contents.locations)
            if stored:
                handle["checksum"][stored] = np.array([contents.checksums[k] for k in stored])
                handle["complete"][stored] = 1
            failed = sorted(failures)
            if failed:
                handle["failed"][failed] = 1
        finally:
            handle.close()


_MANIFEST_MARKS = (
    "format",
    "format_version",
    "N",
    "samples",
    "dtype",
    "layout_json",
    "failures_json",
    "shard_dir",
    "shard_prefix",
)


def read_manifest_shards(path: str | os.PathLike[str]) -> ManifestShards | None:
    """The shards of a data set written in shards; None for a one-file or unreadable one."""
    import h5py

    file = Path(path)
    try:
        with h5py.File(file, "r") as handle:
            attrs = dict(handle.attrs)
    except OSError:
        return None
    if "shard_prefix" not in attrs:
        return None
    folder = file.parent / str(attrs["shard_dir"])
    raw = {key: value for key, value in attrs.items() if key not in _MANIFEST_MARKS}
    return ManifestShards(folder, str(attrs["shard_prefix"]), raw)


def shard_files(handle: Any, path: str | os.PathLike[str]) -> list[Path]:
    """The shard files an open data set file maps its runs to (none for a one-file data set).

    HDF5 reads a missing source file of a virtual dataset as fill values (zeros) without an
    error, so a reader checks these exist (see :func:`missing_shards`).

    Args:
        handle: the open h5py file
        path: its path (sources are relative to its folder)
    """
    if "shard_prefix" not in handle.attrs or not handle["time"].is_virtual:
        return []
    folder = Path(path).parent
    names = {source.file_name for source in handle["time"].virtual_sources()}
    return sorted(folder / name for name in names)


def missing_shards(handle: Any, path: str | os.PathLike[str]) -> list[Path]:
    """The shards of a sharded data set that are not there (empty when all are, or one-file)."""
    return [file for file in shard_files(handle, path) if not file.is_file()]


def remove_unused_shards(folder: Path, prefix: str, used: set[str]) -> int:
    """Delete the job's shards that the manifest does not use, and their hidden companions.

    The companions are the temporaries and lock files a killed worker left
    (:func:`~aaria_pin.files.paths.atomic_output`). Only files of this job (its prefix) are
    touched. Returns the number of files removed.
    """
    removed = 0
    if not folder.is_dir():
        return 0
    for file in [*list_shards(folder, prefix), *folder.glob(f".{prefix}-*")]:
        if file.name not in used and file.is_file():
            file.unlink(missing_ok=True)
            removed += 1
    return removed
