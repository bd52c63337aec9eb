"""Resuming a data set: open it read-only, verify each complete run's chunks, keep the intact.

A run flagged complete is intact when its stored chunks inflate and their CRC-32s are those
``checksum`` recorded (:func:`~.layout.read_run_chunks`); a resumed job copies the intact
runs into a fresh file (:func:`copy_intact_runs`) or, with no room for a copy, clears the flags
of the damaged ones in place (:func:`unflag_damaged_runs`).
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.errors import InputFileError
from aaria_pin.files._stored import NAME_LISTS, decode_attributes
from aaria_pin.files.dataset.layout import (
    DATASET_FORMAT,
    DATASET_FORMAT_VERSION,
    DatasetLayout,
    read_layout,
    read_run_chunks,
)
from aaria_pin.files.dataset.verify import check_arrays

__all__ = [
    "COPY_BLOCK_RUNS",
    "copy_intact_runs",
    "damaged_runs",
    "dataset_progress",
    "open_read_only",
    "read_dataset_attributes",
    "unflag_damaged_runs",
]


def open_read_only(file: Path) -> Any:
    """Open a data set to resume it, refusing anything but a complete version 2 layout."""
    import h5py

    if not file.is_file():
        raise InputFileError(f"{file}: no such file to resume", parameter="path")
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
        raise InputFileError(
            f"{file}: not a complete aaria_pin data set; cannot resume it", parameter="path"
        )
    version = int(handle.attrs.get("format_version", 1))
    if version != DATASET_FORMAT_VERSION:
        handle.close()
        raise InputFileError(
            f"{file}: is a format version {version} data set (aaria_pin 0.1), which cannot be "
            "resumed; allowed: make it again, or write the rest to a new output file",
            parameter="path",
            value=str(file),
            allowed=f"a format version {DATASET_FORMAT_VERSION} data set (this one is format "
            f"version {version}, aaria_pin 0.1: make it again, or write the rest to a new "
            "output file)",
        )
    complete = "layout_json" in handle.attrs and all(
        name in handle for name in (*NAME_LISTS, "checksum", "complete")
    )
    missing = not complete or any(name not in handle for name in read_layout(handle).names)
    if missing:
        handle.close()
        raise InputFileError(
            f"{file}: not a complete aaria_pin data set; cannot resume it", parameter="path"
        )
    try:
        check_arrays(handle, file, int(handle["complete"].shape[0]), {"checksum": None})
    except InputFileError:
        handle.close()
        raise
    return handle


def read_dataset_attributes(path: str | os.PathLike[str]) -> dict[str, Any]:
    """A resumable data set's attributes (decoded), opening it read-only.

    Raises:
        InputFileError: as :meth:`DatasetFile.open_for_resume`.
    """
    handle = open_read_only(Path(path))
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


def copy_intact_runs(old: Any, new: Any, layout: DatasetLayout) -> list[int]:
    """Copy the chunk bytes of every complete run whose CRC-32 matches into ``new``.

    Returns:
        The runs flagged complete that were damaged (left out, to be made again).
    """
    damaged_runs: list[int] = []
    for intact, damaged in _verified_runs(old, layout):
        damaged_runs += damaged
        for _, chunks, _ in intact:
            for name, where, data in chunks:
                new[name].id.write_direct_chunk(where, data)
        if intact:
            runs = [run for run, _, _ in intact]
            new["checksum"][runs] = np.array([plain for _, _, plain in intact], dtype="u4")
            new["complete"][runs] = 1
    new.flush()
    return damaged_runs


def unflag_damaged_runs(handle: Any, layout: DatasetLayout) -> list[int]:
    """In place, clear the flag of every damaged complete run (to redo); returns those runs.

    The intact ones get their plain CRC-32s, as a copy would store them.
    """
    damaged_runs: list[int] = []
    for intact, damaged in _verified_runs(handle, layout):
        damaged_runs += damaged
        if damaged:
            handle["complete"][damaged] = 0
            handle["failed"][damaged] = 0
        if intact:
            runs = [run for run, _, _ in intact]
            handle["checksum"][runs] = np.array([plain for _, _, plain in intact], dtype="u4")
    handle.flush()
    return damaged_runs


def damaged_runs(path: str | os.PathLike[str]) -> list[int]:
    """The runs flagged complete whose chunks do not inflate or differ from their checksums.

    Read-only: every complete run's stored chunks are read and their CRC-32s compared with
    ``checksum`` (as a resumed job does before it keeps a run).

    Raises:
        InputFileError: as :meth:`DatasetFile.open_for_resume`.
    """
    handle = open_read_only(Path(path))
    try:
        layout = read_layout(handle)
        return [run for _, damaged in _verified_runs(handle, layout) for run in damaged]
    finally:
        handle.close()


def dataset_progress(path: str | os.PathLike[str]) -> tuple[int, int, bool]:
    """A resumable data set's complete runs, its N, and whether it holds no failed run.

    Reads the ``complete`` flags :data:`COPY_BLOCK_RUNS` at a time, read-only.

    Raises:
        InputFileError: as :meth:`DatasetFile.open_for_resume`.
    """
    handle = open_read_only(Path(path))
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
