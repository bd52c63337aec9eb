"""Writing a data set file: lay it out, store runs as they come, resume it after a crash.

The main process is the only writer. Each run arrives encoded (:func:`~.layout.encode_run`: the
workers compress it) and is stored chunk by chunk as it is (HDF5's direct chunk write); its
CRC-32 (of the chunks before deflate) goes into ``checksum`` and its flag into ``complete`` at
the next flush, so a run damaged by a crash is found and redone on resume.
"""

from __future__ import annotations

import contextlib
import json
import os
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.errors import InputFileError, NoSpaceError, OutputFileError
from aaria_pin.files._stored import (
    NAME_LISTS,
    create_virtual_view,
    decode_attributes,
    encode_attributes,
    units_of,
)
from aaria_pin.files.dataset.layout import (
    DATASET_FORMAT,
    DATASET_FORMAT_VERSION,
    DatasetLayout,
    EncodedRun,
    chunk_origins,
    codec,
)
from aaria_pin.files.io import atomic_output

__all__ = [
    "DatasetFile",
    "check_dataset_path",
    "dataset_progress",
    "decode_attributes",
    "read_dataset_attributes",
    "read_layout",
]


_DATASET_MARKS = (
    "format",
    "format_version",
    "N",
    "samples",
    "dtype",
    "failures",
    "layout",
    "shard_dir",
    "shard_prefix",
)
"""Attributes a data set file sets itself (a spec's attributes cannot take these names)."""


def read_layout(handle: Any) -> DatasetLayout:
    """The layout of an open version 2 data set file."""
    names = {name: tuple(handle[name].asstr()[()]) for name in NAME_LISTS}
    urdf = handle["urdf"].asstr()[()] if "urdf" in handle else ""
    return DatasetLayout.from_json(handle.attrs["layout_json"], names, urdf)


class DatasetFile:
    """An open data set file, for writing runs into it or resuming it.

    Use :meth:`create` or :meth:`open_for_resume`; close with :meth:`close` (or a ``with``
    block).
    """

    def __init__(self, handle: Any, path: Path) -> None:
        self._handle = handle
        self.path = path
        self.layout = read_layout(handle)
        self._chunks = {name: _chunk_targets(handle[name]) for name in self.layout.names}
        self._pending: dict[int, list[int]] = {}  # run -> checksums, written at the next flush

    @classmethod
    def create(
        cls,
        path: str | os.PathLike[str],
        n_runs: int,
        samples: int,
        dtype: str,
        attributes: Mapping[str, Any],
        layout: DatasetLayout,
    ) -> DatasetFile:
        """Create a new data set file (an existing file at ``path`` is replaced).

        The file is made under a temporary name and renamed when its layout is complete, so a
        crash during creation leaves no half-made file at ``path``.

        Args:
            path: the ``.h5`` file
            n_runs: number of runs N
            samples: samples per run T
            dtype: ``"float32"`` or ``"float64"`` (the series; inputs are float64)
            attributes: file attributes (numbers and strings as they are, others as JSON)
            layout: what every run holds

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
        pointing past the end of the file; the copy starts from clean metadata. When the device
        has no room for the copy (a job stopped by a full disk, resumed after a little space
        was freed), the file is continued where it is instead: the flags of damaged runs are
        cleared in place and only the runs to redo need room.

        Raises:
            InputFileError: missing, unreadable, of format version 1, or not a complete data
                set layout.
        """
        file = Path(path)
        try:
            cls._copy_for_resume(file)
        except NoSpaceError:  # no room for a second copy: continue the file in place
            resumed = cls._open(file)
            _unflag_damaged_runs(resumed._handle, resumed.layout)
            return resumed
        return cls._open(file)

    @classmethod
    def _copy_for_resume(cls, file: Path) -> None:
        """Replace ``file`` by a fresh copy of its intact runs (see :meth:`open_for_resume`)."""
        old = _open_dataset_read_only(file)
        try:
            attrs = dict(old.attrs)
            n_runs, samples = int(attrs.pop("N")), int(attrs.pop("samples"))
            dtype = str(attrs.pop("dtype"))
            for key in ("format", "format_version", "layout_json", "card_json"):
                attrs.pop(key, None)  # set again in their places; the card at the job's end
            layout = read_layout(old)
            with atomic_output(file) as temporary:
                new = _new_file(temporary, n_runs, samples, dtype, {}, layout, raw_attributes=attrs)
                _copy_intact_runs(old, new, layout)
                new.close()
        finally:
            old.close()

    @property
    def attributes(self) -> dict[str, Any]:
        """File attributes, JSON ones decoded (keys without the ``_json`` suffix)."""
        return decode_attributes(self._handle.attrs, self.path)

    @property
    def n_runs(self) -> int:
        """Number of runs N."""
        return int(self._handle.attrs["N"])

    def complete_runs(self) -> np.ndarray:
        """Boolean mask of the runs that are complete."""
        return np.asarray(self._handle["complete"][()], dtype=bool)

    def write_run(self, run: int, encoded: EncodedRun) -> None:
        """Store run ``run``'s encoded chunks (see :func:`~.layout.encode_run`).

        It is marked complete by the next :meth:`flush`; a crash before then loses the run, and
        a crash during it leaves a run whose checksum fails, which a resumed job redoes.
        """
        checksums = []
        for name in self.layout.names:
            chunks, checksum = encoded[name]
            write, origins = self._chunks[name]
            for origin, data in zip(origins, chunks, strict=True):
                write((run, *origin), data)
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
        self._set_failures(json.dumps(failures))
        self._handle["failed"][run] = 1
        self._handle.flush()

    def clear_failures(self) -> None:
        """Forget earlier failures (before a resumed job retries them)."""
        self._set_failures("{}")
        self._handle["failed"][...] = 0

    def _set_failures(self, text: str) -> None:
        """Change ``failures_json`` in its place.

        Assigning it anew would move it last, and a resumed file's attributes would come in
        another order than an uninterrupted one's.
        """
        self._handle.attrs.modify("failures_json", text)

    def failures(self) -> dict[int, str]:
        """Failed runs and their error messages."""
        return {int(k): v for k, v in json.loads(self._handle.attrs["failures_json"]).items()}

    def close(self) -> None:
        """Flush and close the file."""
        self.flush()
        self._handle.close()

    def abandon(self) -> None:
        """Close the file after a failed write, without flagging the runs not yet flushed.

        Errors while closing (HDF5 after a full disk) are ignored: the runs flagged before
        stay flagged, and a resumed job checks each one's CRC-32.
        """
        self._pending.clear()
        with contextlib.suppress(Exception):
            self._handle.close()

    def __enter__(self) -> DatasetFile:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _chunk_targets(dataset: Any) -> tuple[Any, list[tuple[int, ...]]]:
    """A dataset's direct chunk writer and the origins of one run's chunks, in storage order.

    Looked up once per file: h5py's ``shape`` and ``chunks`` properties cost about 8 µs per
    call, 0.35 ms of a run's 43 chunk writes when asked per chunk.
    """
    origins = list(chunk_origins(dataset.shape[1:], dataset.chunks[1:]))
    return dataset.id.write_direct_chunk, origins


def _new_file(
    path: Path,
    n_runs: int,
    samples: int,
    dtype: str,
    attributes: Mapping[str, Any],
    layout: DatasetLayout,
    raw_attributes: Mapping[str, Any] | None = None,
    virtual: Mapping[str, Any] | None = None,
) -> Any:
    """Write the empty layout of a data set into ``path`` and return the open h5py file.

    ``virtual`` maps per-run arrays to ``h5py.VirtualLayout`` objects: those arrays are virtual
    datasets over other files (a sharded data set's manifest, :mod:`.shards`), the others
    chunked datasets of this file.
    """
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
    for key, value in encode_attributes(path, attributes, _DATASET_MARKS):
        handle.attrs[key] = value
    for key, value in (raw_attributes or {}).items():
        handle.attrs[key] = value
    handle.attrs.setdefault("failures_json", "{}")
    handle.attrs["layout_json"] = layout.to_json()
    strings = h5py.string_dtype("utf-8")
    shapes = layout.shapes(samples)
    for name, shape in shapes.items():
        if virtual is not None and name in virtual:
            dataset = handle.create_virtual_dataset(name, virtual[name], fillvalue=0)
            dataset.attrs["units"] = units_of(name)
            continue
        dataset = handle.create_dataset(
            name,
            shape=(n_runs, *shape),
            dtype="float64" if name in layout.inputs else dtype,
            chunks=(1, *layout.chunk(name, shape)),
            compression="gzip",
            compression_opts=1,
            shuffle=True,
        )
        dataset.attrs["units"] = units_of(name)
    stored = {name: (n_runs, *shape) for name, shape in shapes.items()}
    for name, view in layout.views.items():
        create_virtual_view(handle, name, view, stored, dtype, view.units)
    for name in NAME_LISTS:
        handle.create_dataset(name, data=list(getattr(layout, name)), dtype=strings)
    handle.create_dataset("urdf", data=layout.urdf, dtype=strings)
    handle.create_dataset("checksum", shape=(n_runs, len(shapes)), dtype="u4")
    handle.create_dataset("complete", shape=(n_runs,), dtype="u1", fillvalue=0)
    handle.create_dataset("failed", shape=(n_runs,), dtype="u1", fillvalue=0)
    handle.flush()
    return handle


def _open_dataset_read_only(file: Path) -> Any:
    """Open a data set to resume it, refusing anything but a complete version 2 layout."""
    import h5py

    if not file.is_file():
        raise InputFileError(f"{file}: no such file to resume")
    try:
        handle = h5py.File(file, "r")
    except OSError as exc:
        raise InputFileError(
            parameter="resume",
            value=True,
            allowed=f"False ({file} cannot be opened: {exc}; overwrite it to start again)",
        ) from None
    if handle.attrs.get("format") != DATASET_FORMAT:
        handle.close()
        raise InputFileError(f"{file}: not a complete aaria_pin data set; cannot resume it")
    version = int(handle.attrs.get("format_version", 1))
    if version != DATASET_FORMAT_VERSION:
        handle.close()
        raise InputFileError(
            f"{file}: is a format version {version} data set (aaria_pin 0.1), which cannot be "
            "resumed; allowed: make it again, or write the rest to a new output file",
            value=version,
            allowed=f"format version {DATASET_FORMAT_VERSION}",
            element=str(file),
        )
    complete = "layout_json" in handle.attrs and all(
        name in handle for name in (*NAME_LISTS, "checksum", "complete")
    )
    missing = not complete or any(name not in handle for name in read_layout(handle).names)
    if missing:
        handle.close()
        raise InputFileError(f"{file}: not a complete aaria_pin data set; cannot resume it")
    return handle


def read_dataset_attributes(path: str | os.PathLike[str]) -> dict[str, Any]:
    """A resumable data set's attributes (decoded), opening it read-only.

    Raises:
        InputFileError: as :meth:`DatasetFile.open_for_resume`.
    """
    handle = _open_dataset_read_only(Path(path))
    try:
        return decode_attributes(handle.attrs, path)
    finally:
        handle.close()


COPY_BLOCK_RUNS = 4096
"""Runs whose flags and checksums a resumed copy reads at once (its memory stays flat in N)."""


def _verified_runs(
    handle: Any, layout: DatasetLayout
) -> Iterator[
    tuple[list[tuple[int, list[tuple[str, tuple[int, ...], bytes]], list[int]]], list[int]]
]:
    """Per block of runs flagged complete, the intact ones and the damaged ones.

    Intact runs come as (run, chunks, plain CRC-32s). A run whose chunks cannot be read (a
    ``complete`` flag set on a run never written: HDF5 has no chunk there, "Can't get storage
    size of chunk") is damaged, as is one whose CRC-32 differs. The flags and checksums are
    read :data:`COPY_BLOCK_RUNS` runs at a time.
    """
    n_runs = int(handle["complete"].shape[0])
    for begin in range(0, n_runs, COPY_BLOCK_RUNS):
        end = min(n_runs, begin + COPY_BLOCK_RUNS)
        complete = np.asarray(handle["complete"][begin:end], dtype=bool)
        if not complete.any():
            continue
        checksums = handle["checksum"][begin:end]
        intact = []
        damaged: list[int] = []
        for offset in np.flatnonzero(complete):
            run = begin + int(offset)
            try:
                chunks, plain, stored = read_run_chunks(handle, layout.names, run)
            except (OSError, ValueError, KeyError, RuntimeError):
                damaged.append(run)
                continue
            if [int(c) for c in checksums[offset]] not in (plain, stored):
                damaged.append(run)
                continue
            intact.append((run, chunks, plain))
        yield intact, damaged


def _copy_intact_runs(old: Any, new: Any, layout: DatasetLayout) -> None:
    """Copy the chunk bytes of every complete run whose CRC-32 matches into ``new``."""
    for intact, _ in _verified_runs(old, layout):
        for _, chunks, _ in intact:
            for name, where, data in chunks:
                new[name].id.write_direct_chunk(where, data)
        if intact:
            runs = [run for run, _, _ in intact]
            new["checksum"][runs] = np.array([plain for _, _, plain in intact], dtype="u4")
            new["complete"][runs] = 1
    new.flush()


def _unflag_damaged_runs(handle: Any, layout: DatasetLayout) -> None:
    """In place, clear the flag of every damaged complete run (to redo).

    The intact ones get their plain CRC-32s, as a copy would store them.
    """
    for intact, damaged in _verified_runs(handle, layout):
        if damaged:
            handle["complete"][damaged] = 0
            handle["failed"][damaged] = 0
        if intact:
            runs = [run for run, _, _ in intact]
            handle["checksum"][runs] = np.array([plain for _, _, plain in intact], dtype="u4")
    handle.flush()


def read_run_chunks(
    handle: Any, names: Sequence[str], row: int
) -> tuple[list[tuple[str, tuple[int, ...], bytes]], list[int], list[int]]:
    """The stored chunk bytes of one run (row ``row`` of each array) and each array's CRC-32s.

    Returns:
        ``(name, chunk origin with the row, bytes)`` of every chunk in storage order; the
        CRC-32 of each array's chunks once inflated, in ``names`` order (what ``checksum``
        records, :func:`~.layout.encode_run`); and the CRC-32 of their stored (deflated) bytes
        (what files written before the checksums were of uncompressed bytes recorded).

    Raises:
        OSError, KeyError, RuntimeError, zlib.error: a chunk or an array cannot be read or
            inflated.
    """
    _, decompress, crc32 = codec()  # ISA-L's CRC-32: 4 µs a 200 kB chunk against zlib's 49
    chunks, plain, stored = [], [], []
    for name in names:
        dataset = handle[name]
        plain_crc = stored_crc = 0
        for origin in chunk_origins(dataset.shape[1:], dataset.chunks[1:]):
            where = (row, *origin)
            _, data = dataset.id.read_direct_chunk(where)
            stored_crc = crc32(data, stored_crc)
            try:
                plain_crc = crc32(decompress(data), plain_crc)
            except Exception as exc:  # isal's and zlib's own error classes
                raise OSError(f"chunk {where} of {name} cannot be inflated ({exc})") from None
            chunks.append((name, where, data))
        plain.append(plain_crc)
        stored.append(stored_crc)
    return chunks, plain, stored


def dataset_progress(path: str | os.PathLike[str]) -> tuple[int, int, bool]:
    """A resumable data set's complete runs, its N, and whether it holds no failed run.

    Reads the ``complete`` flags :data:`COPY_BLOCK_RUNS` at a time, read-only.

    Raises:
        InputFileError: as :meth:`DatasetFile.open_for_resume`.
    """
    handle = _open_dataset_read_only(Path(path))
    try:
        flags = handle["complete"]
        total = int(flags.shape[0])
        complete = sum(
            int(np.count_nonzero(flags[begin : begin + COPY_BLOCK_RUNS]))
            for begin in range(0, total, COPY_BLOCK_RUNS)
        )
        failed = "failed" in handle and bool(np.any(handle["failed"][()]))
        return complete, total, not failed
    finally:
        handle.close()


def check_dataset_path(path: Path, resume: bool, overwrite: bool, exists: bool = True) -> None:
    """Refuse an output that exists without ``resume``/``overwrite``, or a missing folder.

    Args:
        path: the data set file
        resume: the job continues it
        overwrite: the job replaces it
        exists: check whether it exists too (False: the flags, folder and suffix only, as
            before taking the output's lock)

    Raises:
        OutputFileError: as above, naming the parameter to set (``resume``, ``overwrite``).
    """
    if resume and overwrite:
        raise OutputFileError(
            parameter="overwrite",
            value=True,
            allowed="False when resuming (resume and overwrite exclude each other)",
        )
    from aaria_pin.files.paths import check_output

    check_output(path)  # "-", a name too long, a missing or unwritable folder, a locked output
    if path.exists() and not path.is_file():
        raise OutputFileError(
            f"{path}: is not a regular file; allowed: a regular .h5 file (a data set is read "
            "again while it is written)"
        )
    if path.suffix.lower() not in (".h5", ".hdf5"):
        raise OutputFileError(f"{path}: unknown data set type {path.suffix!r}; allowed: .h5, .hdf5")
    if not exists:
        return
    if path.exists() and not (resume or overwrite):
        raise OutputFileError(
            parameter="resume",
            value=False,
            allowed=f"True to continue {path}, which exists (or overwrite it)",
        )
    if resume and not path.is_file():
        raise InputFileError(f"{path}: no such file to resume")
