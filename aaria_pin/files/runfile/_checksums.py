"""Per-array checksums of a run file: made while writing, verified on every read.

A run file written by this version keeps, in one root attribute ``checksums`` (``attr_checksums``
in a ``.mat``), a JSON object mapping each numeric array (the series, ``imu_mount``, the tables)
to ``"crc32:<8 hex digits>"``: the CRC-32 of the array's values as little-endian float64 in C
order, in the record's shape. It is computed on the values, not on the file's bytes, so it is the
same for the HDF5 and ``.mat`` (v5, v7.3) forms of a run, for a compressed or uncompressed file,
and for a run written whole or streamed in time pieces (the CRC-32 of the pieces in time order is
that of the whole array). The CRC-32 function is :func:`aaria_pin.files._stored.crc32_function`
(ISA-L's where it is installed, else zlib's; the data set's checksums are the same CRC-32).

:func:`verify_checksums` compares what was read with them: a mismatch is one line naming the
array; a file without the attribute (written by 0.3.0 or earlier) still reads, with an
:class:`UnverifiedFileWarning`.
"""

from __future__ import annotations

import json
import os
import warnings
from collections.abc import Collection, Mapping
from typing import Any

import numpy as np

from aaria_pin.core.se3 import Array
from aaria_pin.errors import InputFileError
from aaria_pin.files._stored import crc32_function

CHECKSUMS_ATTRIBUTE = "checksums"
"""The root attribute (``attr_checksums`` in a ``.mat``) of the arrays' checksums, JSON."""

CHECKSUM_PREFIX = "crc32:"
"""How a stored checksum starts (its algorithm)."""


class UnverifiedFileWarning(UserWarning):
    """A run file written before checksums were stored: read, but its arrays are not verified."""


_BLOCK_BYTES = 2**24
"""Bytes of the copies :func:`crc_of_values` makes of an array not stored as its checksum's."""


def crc_of_values(crc32: Any, data: Array, start: int = 0) -> int:
    """The CRC-32 of an array's values (little-endian float64, C order), continued from ``start``.

    An array already so (what h5py reads, what the simulator makes) is read in place; another
    (a ``.mat`` read in MATLAB's column order, float32) is converted in blocks of rows of at most
    16 MiB, so memory does not double for a long run (the C order of the blocks in turn is that
    of the whole array).
    """
    values = np.asarray(data)
    if values.dtype == np.dtype("<f8") and values.flags.c_contiguous:
        return int(crc32(values, start))
    if values.ndim == 0 or values.size == 0:
        return int(crc32(np.ascontiguousarray(values, dtype="<f8"), start))
    rows = max(1, _BLOCK_BYTES // (8 * (values.size // values.shape[0])))
    crc = start
    for first in range(0, values.shape[0], rows):
        crc = crc32(np.ascontiguousarray(values[first : first + rows], dtype="<f8"), crc)
    return int(crc)


class Checksums:
    """Running CRC-32s of a run's arrays, fed piece by piece in time order.

    Example::

        sums = Checksums()
        sums.update("tau", first_piece.tau)
        sums.update("tau", second_piece.tau)
        sums.attribute()  # '{"tau": "crc32:…"}'
    """

    def __init__(self) -> None:
        self._crc32 = crc32_function()
        self._values: dict[str, int] = {}

    def update(self, name: str, data: Array) -> None:
        """Add the next values of array ``name`` (its next samples, or the whole array)."""
        self._values[name] = crc_of_values(self._crc32, data, self._values.get(name, 0))

    def attribute(self) -> str:
        """The ``checksums`` attribute: JSON, array name → ``"crc32:<hex>"``, names sorted."""
        values = {name: _text(value) for name, value in self._values.items()}
        return json.dumps(values, sort_keys=True)


def _text(value: int) -> str:
    """A CRC-32 as stored: ``crc32:`` and 8 hex digits."""
    return f"{CHECKSUM_PREFIX}{value & 0xFFFFFFFF:08x}"


def stored_checksums(file: str | os.PathLike[str], value: Any) -> dict[str, str] | None:
    """The decoded ``checksums`` attribute (None: the file has none).

    Raises:
        InputFileError: an attribute that is not a JSON object of strings (``parameter="file"``).
    """
    if value is None:
        return None
    if isinstance(value, bytes):
        value = value.decode("utf-8", errors="replace")
    try:
        decoded = json.loads(value) if isinstance(value, str) else None
    except ValueError:
        decoded = None
    if not isinstance(decoded, dict) or not all(isinstance(v, str) for v in decoded.values()):
        raise InputFileError(
            f"{file}: attribute {CHECKSUMS_ATTRIBUTE!r} is {str(value)[:40]!r}; allowed: a JSON "
            'object of "crc32:<hex>" strings by array name',
            parameter="file",
        )
    return decoded


def verify_checksums(
    file: str | os.PathLike[str],
    stored: Mapping[str, str] | None,
    arrays: Mapping[str, Array],
    unread: Collection[str] = (),
) -> None:
    """Compare read arrays with their stored checksums (a file without any: a warning).

    Args:
        file: the file read, for messages
        stored: its decoded checksums (:func:`stored_checksums`), None if it has none
        arrays: the arrays read, by name
        unread: the arrays left unread on purpose (the series, for the inputs only)

    Raises:
        InputFileError: an array whose values do not match its checksum, an array read that
            has none, or one the checksums list that the file no longer holds
            (``parameter="file"``).
    """
    if stored is None:
        warnings.warn(
            f"{file}: written without checksums (aaria_pin 0.3.0 or earlier); its arrays "
            "cannot be verified",
            UnverifiedFileWarning,
            stacklevel=4,
        )
        return
    crc32 = crc32_function()
    for name, data in arrays.items():
        expected = stored.get(name)
        if expected is None:
            raise InputFileError(
                f"{file}: array {name} has no checksum; allowed: a run file whose every array "
                "has one",
                parameter="file",
            )
        found = _text(crc_of_values(crc32, data))
        if found != expected:
            raise InputFileError(
                f"{file}: array {name} is damaged (checksum {found}, stored {expected}); "
                "allowed: an undamaged file (re-make it)",
                parameter="file",
            )
    gone = [name for name in stored if name not in arrays and name not in unread]
    if gone:
        raise InputFileError(
            f"{file}: array {gone[0]} is missing; allowed: every array its checksums list",
            parameter="file",
        )
