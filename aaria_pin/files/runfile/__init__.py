"""Writing and reading the run file of one simulation run (a :class:`RunRecord`).

Two formats, chosen by the file suffix:

``.h5`` / ``.hdf5`` (HDF5, through h5py)
    One float64 dataset per array at the file root, named and shaped as in the record:
    ``senSen`` T × 91, ``senSenDH`` 8 × 5, ``senSenJ`` 8 × 5, ``senSenB`` 2 × 4 or 6 × 4, ``q``,
    ``qd``, ``qdd``, ``tau``, ``base_wrench`` T × 6, ``tool_pose`` T × 4 × 4, ``imu_mount``
    14 × 4 × 4. Every dataset has a ``units`` attribute (a string); ``senSen`` also has
    ``columns``, its 91 column names as an array of variable-length UTF-8 strings (read by h5py
    and by MATLAB's ``h5readatt``). By default every dataset is stored contiguous and
    uncompressed: writing is then bound by the disk, not the CPU (a 200,000-sample run writes
    in about 0.4 s uncompressed and 4.8 s with gzip). With ``compression="gzip"`` (level 1 after
    the shuffle filter; the one filter every HDF5 build has, MATLAB included, about 30 % smaller)
    or ``"lzf"`` (h5py-only, faster than gzip) the time series (the datasets with T rows) are
    chunked along time, up to 4096 rows and at most 1 MiB per chunk.
    The root group carries ``format = "aaria_pin run"``, ``format_version = 1`` and one
    attribute per item of ``RunRecord.attributes`` (insertion order is kept).

``.mat`` (MATLAB v5 through ``scipy.io.savemat``, compressed)
    The same arrays under the same names (``tool_pose`` and ``imu_mount`` are 3-D arrays in
    MATLAB), ``senSen_columns`` a 1 × 91 cell array of the column names, and every attribute
    as a variable ``attr_<name>``, including ``attr_format`` and ``attr_format_version``. A v5
    file holds at most 2 GiB per array; write HDF5 for longer runs.

Attribute encoding (both formats): a str, bool, int (64-bit) or float is stored as a plain
scalar attribute (an HDF5 bool is an enum that MATLAB reads as ``'TRUE'``/``'FALSE'``); a list,
tuple or 1-D array of two or more numbers (no bools) as a numeric vector (int64 if all are
integers, else float64; it reads back as a list). Anything else (a dict, a list of strings,
a one-item list, None, ...) and every attribute whose name already ends in ``_json`` is stored
as a JSON string under its name plus the suffix ``_json``, e.g. ``noise_parameters`` →
``noise_parameters_json`` (``attr_noise_parameters_json`` in a ``.mat``), and is JSON-decoded
when read back (so tuples come back as lists and dict keys as strings). The names ``format``
and ``format_version`` are reserved; in a ``.mat`` file ``attr_<name>`` must be a MATLAB
variable name (letters, digits and ``_``, at most 63 characters).
"""

from __future__ import annotations

import os
from pathlib import Path

from aaria_pin.aaria.sensen import RunRecord
from aaria_pin.core.record import GenericRunRecord
from aaria_pin.errors import InputFileError, OutputFileError
from aaria_pin.files.io import atomic_output
from aaria_pin.files.runfile._attributes import (
    JSON_SUFFIX,
    RUN_FORMAT,
    RUN_FORMAT_VERSION,
    _encode_attributes,
    _reason,
)
from aaria_pin.files.runfile._generic import (
    GENERIC_FORMAT,
    is_generic_hdf5,
    read_generic_hdf5,
    summarise_generic_hdf5,
    write_generic_hdf5,
)
from aaria_pin.files.runfile._hdf5 import _read_hdf5, _summarise_hdf5, _write_hdf5
from aaria_pin.files.runfile._mat import _check_mat_contents, _read_mat, _summarise_mat, _write_mat
from aaria_pin.files.runfile._shapes import _checked_arrays, _fit_shapes

__all__ = [
    "COMPRESSIONS",
    "GENERIC_FORMAT",
    "JSON_SUFFIX",
    "RUN_FORMAT",
    "RUN_FORMAT_VERSION",
    "RUN_SUFFIXES",
    "generic_run_summary",
    "is_generic_run_file",
    "read_generic_run",
    "read_run",
    "run_file_summary",
    "write_generic_run",
    "write_run",
]

COMPRESSIONS = (None, "gzip", "lzf")
"""HDF5 filters :func:`write_run` offers for the time series (None: uncompressed)."""

RUN_SUFFIXES = (".h5", ".hdf5", ".mat")
"""File suffixes of run files (case-insensitive)."""

_HDF5_SUFFIXES = (".h5", ".hdf5")


def write_run(
    path: str | os.PathLike[str], record: RunRecord, compression: str | None = None
) -> Path:
    """Write a run record to an HDF5 (``.h5``, ``.hdf5``) or MATLAB (``.mat``) file.

    The file is written beside its destination and renamed when complete, so a failure never
    leaves a partial file (see :func:`aaria_pin.files.io.atomic_output`). The layout is described in
    the module docstring.

    Args:
        path: the run file; its suffix selects the format
        record: the run to write
        compression: HDF5 filter of the time series: ``None`` (default, fastest), ``"gzip"``
            or ``"lzf"``; a ``.mat`` file is always compressed

    Returns:
        The path written.

    Raises:
        OutputFileError: unknown suffix, missing folder, an array of the wrong shape, an
            attribute that cannot be stored, or a write failure.
    """
    final = Path(path)
    suffix = final.suffix.lower()
    if compression not in COMPRESSIONS:
        raise OutputFileError(
            f"compression {compression!r} is not allowed; allowed: None, 'gzip', 'lzf'"
        )
    if suffix not in RUN_SUFFIXES:
        raise OutputFileError(
            f"{final}: unknown run file type {suffix!r}; allowed: {', '.join(RUN_SUFFIXES)}"
        )
    arrays = _checked_arrays(final, record)
    attributes = _encode_attributes(final, record.attributes)
    if suffix == ".mat":
        _check_mat_contents(final, arrays, attributes)
    with atomic_output(final) as temporary:
        try:
            if suffix == ".mat":
                _write_mat(temporary, arrays, attributes)
            else:
                _write_hdf5(temporary, arrays, attributes, compression)
        except OSError as exc:
            raise OutputFileError(f"{final}: cannot be written ({_reason(exc)})") from None
    return final


def read_run(path: str | os.PathLike[str]) -> RunRecord:
    """Read a run file written by :func:`write_run` (HDF5 or MATLAB v5 ``.mat``).

    Shapes are restored from the known layout, so a ``.mat`` file re-saved by MATLAB (or a
    one-sample run) gives back the record's shapes.

    Args:
        path: the run file

    Returns:
        The run record, attributes decoded as described in the module docstring.

    Raises:
        InputFileError: the file is missing, unreadable, of an unknown kind, not a run file,
            of a newer format version, or holds an array of the wrong shape.
    """
    file = _existing_run_file(path)
    if file.suffix.lower() == ".mat":
        arrays, attributes = _read_mat(file)
    else:
        arrays, attributes = _read_hdf5(file)
    return RunRecord(**arrays, attributes=attributes)


def run_file_summary(path: str | os.PathLike[str]) -> dict[str, object]:
    """Describe a run file without reading its arrays (for ``aaria info``).

    Args:
        path: the run file

    Returns:
        ``path`` (str), ``format`` (``"HDF5"`` or ``"MATLAB v5"``), ``format_version`` (int),
        ``samples`` (T), ``arrays`` (name → shape tuple, as :func:`read_run` gives them) and
        ``attributes`` (decoded as by :func:`read_run`).

    Raises:
        InputFileError: as :func:`read_run`.
    """
    file = _existing_run_file(path)
    if file.suffix.lower() == ".mat":
        kind = "MATLAB v5"
        shapes, attributes, version = _summarise_mat(file)
    else:
        kind = "HDF5"
        shapes, attributes, version = _summarise_hdf5(file)
    fitted = _fit_shapes(file, shapes)
    return {
        "path": str(file),
        "format": kind,
        "format_version": version,
        "samples": fitted["senSen"][0],
        "arrays": fitted,
        "attributes": attributes,
    }


def write_generic_run(path: str | os.PathLike[str], record: GenericRunRecord) -> Path:
    """Write the run of a URDF robot to an HDF5 file (layout: :mod:`._generic`).

    Written beside its destination and renamed when complete.

    Args:
        path: the run file, ``.h5`` or ``.hdf5``
        record: the run to write

    Returns:
        The path written.

    Raises:
        OutputFileError: another suffix, a missing folder, an attribute that cannot be stored,
            or a write failure.
    """
    final = Path(path)
    if final.suffix.lower() not in _HDF5_SUFFIXES:
        raise OutputFileError(
            f"{final}: a URDF robot's run is written as HDF5; allowed suffixes: "
            f"{', '.join(_HDF5_SUFFIXES)}"
        )
    with atomic_output(final) as temporary:
        write_generic_hdf5(temporary, final, record)
    return final


def read_generic_run(path: str | os.PathLike[str]) -> GenericRunRecord:
    """Read a generic run file written by :func:`write_generic_run`.

    Raises:
        InputFileError: missing, not HDF5, not a generic run file, or damaged.
    """
    file = _existing_run_file(path)
    if file.suffix.lower() not in _HDF5_SUFFIXES:
        raise InputFileError(f"{file}: a generic run file is HDF5 (.h5, .hdf5)")
    return read_generic_hdf5(file)


def generic_run_summary(path: str | os.PathLike[str]) -> dict[str, object]:
    """Describe a generic run file (for ``aaria info``), as :func:`run_file_summary` does.

    Besides the keys of :func:`run_file_summary` it gives ``columns`` (of ``signals``),
    ``joints`` and ``imus`` (names).
    """
    file = _existing_run_file(path)
    if file.suffix.lower() not in _HDF5_SUFFIXES:
        raise InputFileError(f"{file}: a generic run file is HDF5 (.h5, .hdf5)")
    summary = summarise_generic_hdf5(file)
    return {
        "path": str(file),
        "format": "HDF5, generic layout",
        "format_version": 1,
        "samples": summary["arrays"]["signals"][0],
        **summary,
    }


def is_generic_run_file(path: str | os.PathLike[str]) -> bool:
    """Whether ``path`` is an existing HDF5 file marked as a generic (URDF robot) run file."""
    file = Path(path)
    return file.suffix.lower() in _HDF5_SUFFIXES and file.is_file() and is_generic_hdf5(file)


# --- files ---------------------------------------------------------------------------------------


def _existing_run_file(path: str | os.PathLike[str]) -> Path:
    """The path of an existing run file of a known suffix; InputFileError otherwise."""
    file = Path(path)
    suffix = file.suffix.lower()
    if suffix not in RUN_SUFFIXES:
        raise InputFileError(
            f"{file}: unknown run file type {suffix!r}; allowed: {', '.join(RUN_SUFFIXES)}"
        )
    if not file.is_file():
        raise InputFileError(f"{file}: no such file")
    return file
