"""The run file's ``format`` and ``format_version`` marks, and their check.

The attributes themselves are encoded as a data set's are (:mod:`aaria_pin.files._stored`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.errors import InputFileError

RUN_FORMAT = "aaria_pin run"
"""Value of the ``format`` attribute that marks a run file."""

RUN_FORMAT_VERSION = 2
"""Layout version written, and the newest one read (1: the 0.1.0 Aaria layout)."""

_RESERVED_ATTRIBUTES = ("format", "format_version")

NOT_RECORD_ATTRIBUTES = (*_RESERVED_ATTRIBUTES, "checksums")
"""Root attributes of a run file that are the file's own, not its record's: the format marks
and the arrays' checksums (:mod:`._checksums`); an attribute of a record cannot take one."""


def _check_format(
    file: Path,
    fmt: Any,
    version: Any,
    expected: str = RUN_FORMAT,
    newest: int = RUN_FORMAT_VERSION,
) -> int:
    """Check the ``format`` marks a file of the expected kind and a known version.

    Args:
        file: the file, for messages
        fmt: its ``format`` attribute
        version: its ``format_version`` attribute
        expected: the ``format`` wanted (an Aaria run file by default)
        newest: the newest version this aaria_pin reads

    Returns:
        The version.
    """
    if isinstance(fmt, bytes):
        fmt = fmt.decode("utf-8", errors="replace")
    if fmt is None:
        raise InputFileError(
            f"{file}: not an aaria_pin run file (no 'format' attribute)", parameter="file"
        )
    if fmt != expected:
        raise InputFileError(
            f"{file}: not an {expected} file (format is {fmt!r}; expected {expected!r})",
            parameter="file",
        )
    if isinstance(version, (float, np.floating)) and float(version).is_integer():
        version = int(version)  # MATLAB stores numbers as double unless told otherwise
    if not isinstance(version, (int, np.integer)) or isinstance(version, (bool, np.bool_)):
        raise InputFileError(
            f"{file}: format_version {version!r} is not allowed; expected an integer",
            parameter="file",
        )
    if not 1 <= int(version) <= newest:
        raise InputFileError(
            f"{file}: format_version {int(version)} is not supported; "
            f"this aaria_pin reads 1 to {newest}",
            parameter="file",
        )
    return int(version)
