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
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.errors import InputFileError, NoSpaceError, OutputFileError
from aaria_pin.files._space import close_hdf5
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
    read_layout,
)
from aaria_pin.files.dataset.resume import copy_intact_runs, open_read_only, unflag_damaged_runs
from aaria_pin.files.io import atomic_output

__all__ = [
    "DatasetFile",
    "check_dataset_path",
    "partial_path",
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
        self.damaged: list[int] = []  # runs flagged complete found damaged on resume (redone)

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
            close_hdf5(handle, failed=False)
        return cls._open(file)

    @classmethod
    def _open(cls, file: Path) -> DatasetFile:
        import h5py

        try:
            handle = h5py.File(file, "r+")
        except OSError as exc:
            raise InputFileError(f"{file}: cannot be opened ({exc})", parameter="path") from None
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
        cleared in place and only the runs to redo need room. The runs flagged complete but
        found damaged are :attr:`damaged`.

        Raises:
            InputFileError: missing, unreadable, of format version 1, or not a complete data
                set layout.
        """
        file = Path(path)
        try:
            damaged = cls._copy_for_resume(file)
        except NoSpaceError:  # no room for a second copy: continue the file in place
            resumed = cls._open(file)
            resumed.damaged = unflag_damaged_runs(resumed._handle, resumed.layout)
            return resumed
        resumed = cls._open(file)
        resumed.damaged = damaged
        return resumed

    @classmethod
    def _copy_for_resume(cls, file: Path) -> list[int]:
        """Replace ``file`` by a fresh copy of its intact runs; the damaged ones (flagged complete).

        See :meth:`open_for_resume`.
        """
        old = open_read_only(file)
        try:
            attrs = dict(old.attrs)
            n_runs, samples = int(attrs.pop("N")), int(attrs.pop("samples"))
            dtype = str(attrs.pop("dtype"))
            for key in ("format", "format_version", "layout_json", "card_json"):
                attrs.pop(key, None)  # set again in their places; the card at the job's end
            layout = read_layout(old)
            with atomic_output(file) as temporary:
                new = _new_file(temporary, n_runs, samples, dtype, {}, layout, raw_attributes=attrs)
                damaged = copy_intact_runs(old, new, layout)
                new.close()
        finally:
            old.close()
        return damaged

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
    datasets over other files (a sharded data set's manifest, :mod:`.manifest`), the others
    chunked datasets of this file.
    """
    import h5py

    try:
        handle = h5py.File(path, "w", track_order=True)
    except OSError as exc:
        raise OutputFileError(f"{path}: cannot be created ({exc})", parameter="path") from None
    try:
        _lay_out(handle, n_runs, samples, dtype, attributes, layout, raw_attributes, virtual)
    except BaseException:
        close_hdf5(handle, failed=True)  # a full device: no identifier left to crash on
        raise
    return handle


def _lay_out(
    handle: Any,
    n_runs: int,
    samples: int,
    dtype: str,
    attributes: Mapping[str, Any],
    layout: DatasetLayout,
    raw_attributes: Mapping[str, Any] | None,
    virtual: Mapping[str, Any] | None,
) -> None:
    """The body of :func:`_new_file`: everything but the file."""
    import h5py

    path = Path(handle.filename)
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


def partial_path(path: str | os.PathLike[str]) -> Path:
    """Where an overwrite builds the new data set beside the old one: ``.NAME.partial.h5``.

    A hidden sibling, so it is on the same file system and replaces the old file with one
    ``os.replace`` once complete; a killed overwrite leaves it there, and the same command
    (or ``--resume``) continues it.
    """
    file = Path(path)
    return file.with_name(f".{file.stem}.partial{file.suffix}")


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
            "again while it is written)",
            parameter="path",
        )
    if path.suffix.lower() not in (".h5", ".hdf5"):
        raise OutputFileError(
            f"{path}: unknown data set type {path.suffix!r}; allowed: .h5, .hdf5", parameter="path"
        )
    if not exists:
        return
    if path.exists() and not (resume or overwrite):
        raise OutputFileError(
            parameter="resume",
            value=False,
            allowed=f"True to continue {path}, which exists (or overwrite it)",
        )
    if resume and not path.is_file():
        raise InputFileError(f"{path}: no such file to resume", parameter="path")
