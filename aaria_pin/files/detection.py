"""What a run file or data set is: the one format detection of the files layer.

:func:`file_format`: an ``.h5``/``.hdf5`` file is a data set when its ``format`` attribute says
so (any format version), else an HDF5 run file; a ``.mat`` file is a MAT-file v7.3 when its
128-byte header says so (it is HDF5), else a MAT-file v5. Only marks are read, never arrays.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Literal, get_args

from aaria_pin.errors import InputFileError
from aaria_pin.files.paths import existing_input

__all__ = [
    "DATASET_FORMAT",
    "FILE_FORMATS",
    "MAT73_HEADER",
    "RUN_SUFFIXES",
    "FileFormat",
    "existing_run_source",
    "file_format",
    "is_dataset_file",
    "is_mat73",
]

FileFormat = Literal["hdf5", "mat5", "mat73", "dataset"]
"""A file's format: an HDF5 run file, a MAT-file v5 or v7.3 run file, or a data set."""

FILE_FORMATS: tuple[FileFormat, ...] = get_args(FileFormat)
"""Every :data:`FileFormat`."""

RUN_SUFFIXES = (".h5", ".hdf5", ".mat")
"""File suffixes of run files and data sets (case-insensitive)."""

MAT73_HEADER = b"MATLAB 7.3 MAT-file"
"""How the text of a MAT-file v7.3's header starts."""

DATASET_FORMAT = "aaria_pin dataset"
"""The ``format`` attribute of a data set (any format version; the layout is
:mod:`aaria_pin.files.dataset.layout`'s, which imports this mark)."""


def file_format(path: str | os.PathLike[str]) -> FileFormat:
    """The format of an existing run file or data set, from its suffix and marks only.

    Args:
        path: a ``.h5``, ``.hdf5`` or ``.mat`` file

    Returns:
        ``"dataset"`` (an HDF5 file whose ``format`` is the data set's), ``"hdf5"`` (another
        HDF5 file), ``"mat73"`` (a ``.mat`` whose header is a v7.3 one) or ``"mat5"``.

    Raises:
        InputFileError: another suffix, a missing or unreadable file, or an ``.h5`` file HDF5
            cannot open (``parameter="file"``): a
            :class:`~aaria_pin.files._stored.DamagedFileError` if it starts as an HDF5 file
            does (truncated, a broken superblock).
    """
    file = existing_run_source(path)
    if file.suffix.lower() == ".mat":
        return "mat73" if is_mat73(file) else "mat5"
    import h5py

    from aaria_pin.files._stored import damaged_errors, read_errors

    with read_errors(file, "an HDF5 run file or data set"):
        try:
            with h5py.File(file, "r") as handle:
                mark = handle.attrs.get("format")
        except (OSError, RuntimeError) as exc:
            if not has_hdf5_signature(file) or "unable to lock" in str(exc).lower():
                raise  # not HDF5 at all, or held by a writer: not damage
            with damaged_errors(file):
                raise
    return "dataset" if mark == DATASET_FORMAT else "hdf5"


HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"
"""The first bytes of an HDF5 superblock (at byte 0, 512, 1024, 2048, ... of the file)."""


def has_hdf5_signature(file: Path) -> bool:
    """Whether a file starts as an HDF5 file does (a file HDF5 then cannot open is damaged).

    The superblock is looked for where HDF5 looks: at byte 0 and after a user block of 512,
    1024, 2048, ... bytes (a MAT-file v7.3's is 512), up to the file's size.
    """
    try:
        with file.open("rb") as stream:
            offset = 0
            while True:
                stream.seek(offset)
                head = stream.read(len(HDF5_SIGNATURE))
                if head == HDF5_SIGNATURE:
                    return True
                if len(head) < len(HDF5_SIGNATURE):
                    return False
                offset = 512 if offset == 0 else offset * 2
    except OSError:
        return False


def is_mat73(file: Path) -> bool:
    """Whether a ``.mat`` file is a MAT-file v7.3 (its header says so); False if unreadable."""
    try:
        with file.open("rb") as stream:
            return stream.read(len(MAT73_HEADER)) == MAT73_HEADER
    except OSError:
        return False


def is_dataset_file(path: str | os.PathLike[str]) -> bool:
    """Whether a file is an aaria_pin data set of any format version (HDF5, its ``format``).

    A missing file, a folder or another suffix is not one (False).

    Raises:
        InputFileError: an ``.h5`` file that HDF5 cannot read.
    """
    file = Path(path)
    if file.suffix.lower() not in (".h5", ".hdf5") or not file.is_file():
        return False
    return file_format(file) == "dataset"


def existing_run_source(path: str | os.PathLike[str]) -> Path:
    """The existing run file or data set ``path``.

    Raises:
        InputFileError: another suffix, or a missing or unreadable file (``parameter="file"``).
    """
    try:
        return existing_input(path, RUN_SUFFIXES, "run")
    except InputFileError as exc:
        raise InputFileError(str(exc), parameter="file", value=str(path)) from None
