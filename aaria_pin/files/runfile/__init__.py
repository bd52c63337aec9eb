"""The run file: the one file of one :class:`~aaria_pin.core.record.RunRecord`, for every robot.

Two formats, chosen by the file suffix, holding the same names and shapes (T samples, n joints,
S IMUs; the record's module docstring gives units and frames):

``.h5`` / ``.hdf5`` (HDF5, through h5py)
    Float64 datasets at the root: ``time`` (T), ``q``, ``qd``, ``qdd``, ``tau`` (T × n),
    ``base_pose`` (T × 4 × 4), ``base_wrench`` (T × 6), ``tool_pose`` (T × 4 × 4), ``imu``
    (T × S × 6), ``imu_mount`` (S × 4 × 4), then each input table under its name (e.g.
    ``senSenDH``, ``senSenJ``, ``senSenB``, ``joint_table``, ``base_table``; a table of fewer
    than two axes is stored, and reads back, as a 1 × k row, as in MATLAB); each has a ``units``
    attribute (a string). Each column view (e.g. the Aaria ``senSen``, T × 91) is an HDF5
    **virtual dataset** over those series in the same file (source file ``"."``, so it stays
    valid when the file is renamed or copied; h5py and MATLAB's ``h5read`` read it as a plain
    T × C array), with ``units`` and ``columns``, its column names as variable-length UTF-8
    strings. ``joint_names`` (n), ``imu_names`` and ``imu_parents`` (S, ``""`` for an empty
    slot) are UTF-8 string datasets and ``urdf`` a UTF-8 string dataset (``""`` if none).
    By default every dataset is contiguous and uncompressed (writing is then bound by the disk:
    a 200,000-sample run writes in about 0.4 s uncompressed, 4.8 s with gzip). With
    ``compression="gzip"`` (level 1 after the shuffle filter, the one filter every HDF5 build
    has, MATLAB included; about 30 % smaller) or ``"lzf"`` (h5py only, faster) the series are
    chunked along time, up to 4096 rows and at most 1 MiB per chunk.
    The root group carries ``format = "aaria_pin run"``, ``format_version = 2`` and one
    attribute per item of ``RunRecord.attributes`` (insertion order kept; ``kind``, ``robot``,
    ``rate``, ... are ordinary attributes).

``.mat`` (MATLAB v5 through ``scipy.io.savemat``, compressed)
    The same arrays under the same names (3-D arrays stay 3-D, ``time`` is 1 × T), each view
    materialised as a real T × C array with its column names as the 1 × C cell array
    ``<view>_columns`` (``senSen_columns``), ``joint_names``, ``imu_names``, ``imu_parents`` as
    1 × n / 1 × S cell arrays, ``urdf`` a char array, and every attribute as a variable
    ``attr_<name>``, including ``attr_format`` and ``attr_format_version``. A v5 file holds at
    most 2 GiB per array; write HDF5 for longer runs.

Views are read back from their column names (both formats): ``time`` → ``time``; ``q<j>``
(1-based) or ``q:<joint>`` → a column of ``q`` (also ``qd``, ``qdd``, ``tau``);
``<imu>_<signal>`` → one signal of one IMU. :func:`write_run` refuses a view whose column names
do not read back as its columns. Any other numeric array of the file reads back as a table.

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

:func:`read_run` also reads every run file aaria_pin 0.1.0 wrote (:mod:`._legacy`: Aaria DH
``.h5``/``.mat``, URDF robot and pick-place ``.h5``, wrist ``.h5``/``.mat``).
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.record import RunRecord
from aaria_pin.errors import InputFileError, OutputFileError
from aaria_pin.files._stored import JSON_SUFFIX, NAME_LISTS, encode_attributes, first_line
from aaria_pin.files.io import atomic_output, existing_input
from aaria_pin.files.runfile._attributes import RUN_FORMAT, RUN_FORMAT_VERSION
from aaria_pin.files.runfile._hdf5 import (
    _hdf5_errors,
    _read_hdf5_v2,
    _summarise_hdf5_v2,
    _write_hdf5,
)
from aaria_pin.files.runfile._layout import (
    COLUMNS_SUFFIX,
    checked_arrays,
    column_source,
    view_from_columns,
)
from aaria_pin.files.runfile._legacy import (
    LAYOUT_V2,
    URDF_V1_FORMAT,
    hdf5_layout,
    mat_layout,
    read_legacy_hdf5,
    read_legacy_mat,
)
from aaria_pin.files.runfile._mat import (
    MAT_ATTRIBUTE_PREFIX,
    _mat_contents,
    _read_mat_v2,
    _summarise_mat_v2,
    _write_mat,
    load_mat,
    mat_variables,
)

__all__ = [
    "COMPRESSIONS",
    "JSON_SUFFIX",
    "RUN_FORMAT",
    "RUN_FORMAT_VERSION",
    "RUN_SUFFIXES",
    "URDF_V1_FORMAT",
    "column_source",
    "is_run_file",
    "read_run",
    "run_file_summary",
    "view_from_columns",
    "write_run",
]

COMPRESSIONS = (None, "gzip", "lzf")
"""HDF5 filters :func:`write_run` offers for the time series (None: uncompressed)."""

RUN_SUFFIXES = (".h5", ".hdf5", ".mat")
"""File suffixes of run files (case-insensitive)."""


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
        OutputFileError: unknown suffix, missing folder, an array of the wrong shape, a table or
            view that cannot be stored, an attribute that cannot be stored, or a write failure.
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
    arrays = checked_arrays(final, record)
    attributes = encode_attributes(final, record.attributes)
    contents = _mat_contents(final, record, arrays, attributes) if suffix == ".mat" else None
    with atomic_output(final) as temporary:
        try:
            if contents is not None:
                _write_mat(temporary, contents)
            else:
                _write_hdf5(temporary, record, arrays, attributes, compression)
        except OSError as exc:
            raise OutputFileError(f"{final}: cannot be written ({first_line(exc)})") from None
    return final


def read_run(path: str | os.PathLike[str]) -> RunRecord:
    """Read any run file: written by :func:`write_run`, or by aaria_pin 0.1.0 (every kind).

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
    file = existing_input(path, RUN_SUFFIXES, "run")
    if file.suffix.lower() == ".mat":
        contents = load_mat(file)
        layout = mat_layout(file, contents, contents)
        if layout == LAYOUT_V2:
            return _read_mat_v2(file, contents)
        return read_legacy_mat(file, contents, layout)
    import h5py

    with _hdf5_errors(file), h5py.File(file, "r") as handle:
        layout = hdf5_layout(file, handle)
        if layout == LAYOUT_V2:
            return _read_hdf5_v2(file, handle)
        return read_legacy_hdf5(file, handle, layout)


def run_file_summary(path: str | os.PathLike[str]) -> dict[str, Any]:
    """Describe a run file (for ``aaria info``); a version 2 file's arrays are not read.

    Args:
        path: the run file (any kind :func:`read_run` reads)

    Returns:
        ``path`` (str), ``format`` (``"HDF5"`` or ``"MATLAB v5"``), ``format_version`` (int; 1
        for every 0.1.0 file), ``layout`` (``"aaria_pin run"`` or the 0.1.0 layout, e.g.
        ``"0.1.0 wrist run"``), ``kind``, ``robot``, ``samples`` (T), ``rate`` [Hz] (the
        attribute, else from the first two sample times; None for one sample), ``joints`` and
        ``imus`` (names), ``arrays`` (name → shape, as :func:`read_run` gives them: the series,
        ``imu_mount`` and the tables), ``views`` (name → shape) and ``attributes`` (decoded as
        by :func:`read_run`).

    Raises:
        InputFileError: as :func:`read_run`.
    """
    file = existing_input(path, RUN_SUFFIXES, "run")
    time_head: Any
    if file.suffix.lower() == ".mat":
        kind = "MATLAB v5"
        variables = mat_variables(file)
        small = [
            name
            for name in variables
            if name.startswith(MAT_ATTRIBUTE_PREFIX)
            or name in NAME_LISTS
            or name.endswith(COLUMNS_SUFFIX)
        ]
        contents = load_mat(file, small) if small else {}
        layout = mat_layout(file, contents, variables)
        if layout == LAYOUT_V2:
            parts = _summarise_mat_v2(file, variables, contents)
            time_head = (
                load_mat(file, ["time"])["time"] if "rate" not in parts["attributes"] else None
            )
        else:
            parts = _record_parts(read_legacy_mat(file, load_mat(file), layout))
            time_head = parts.pop("time")
    else:
        import h5py

        kind = "HDF5"
        with _hdf5_errors(file), h5py.File(file, "r") as handle:
            layout = hdf5_layout(file, handle)
            if layout == LAYOUT_V2:
                parts = _summarise_hdf5_v2(file, handle)
                time_head = handle["time"][:2] if handle["time"].ndim == 1 else None
            else:
                parts = _record_parts(read_legacy_hdf5(file, handle, layout))
                time_head = parts.pop("time")
    attributes = parts["attributes"]
    return {
        "path": str(file),
        "format": kind,
        "format_version": RUN_FORMAT_VERSION if layout == LAYOUT_V2 else 1,
        "layout": layout,
        "kind": attributes.get("kind"),
        "robot": attributes.get("robot"),
        "samples": parts["arrays"]["time"][0],
        "rate": _rate(attributes, time_head),
        **parts,
    }


def is_run_file(path: str | os.PathLike[str]) -> bool:
    """Whether ``path`` is an existing run file :func:`read_run` reads (any version or kind).

    Only the file's marks and names are looked at, not its arrays; a data set is not a run file.
    """
    try:
        file = existing_input(path, RUN_SUFFIXES, "run")
        if file.suffix.lower() == ".mat":
            variables = mat_variables(file)
            attribute_names = [n for n in variables if n.startswith(MAT_ATTRIBUTE_PREFIX)]
            mat_layout(file, load_mat(file, attribute_names) if attribute_names else {}, variables)
            return True
        import h5py

        with _hdf5_errors(file), h5py.File(file, "r") as handle:
            hdf5_layout(file, handle)
        return True
    except InputFileError:
        return False


# --- helpers -------------------------------------------------------------------------------------


def _record_parts(record: RunRecord) -> dict[str, Any]:
    """The summary parts of a record read in full (a 0.1.0 file), plus its first sample times."""
    return {
        "joints": list(record.joint_names),
        "imus": list(record.imu_names),
        "arrays": {name: tuple(np.shape(array)) for name, array in record.arrays().items()},
        "views": {
            name: (record.n_samples, len(view.columns)) for name, view in record.views.items()
        },
        "attributes": record.attributes,
        "time": record.time[:2],
    }


def _rate(attributes: Mapping[str, Any], time_head: Any) -> float | None:
    """The sample rate [Hz]: the ``rate`` attribute, else from the first two sample times."""
    rate = attributes.get("rate")
    if isinstance(rate, (int, float)) and not isinstance(rate, bool):
        return float(rate)
    head = np.ravel(np.asarray(time_head, dtype=float)) if time_head is not None else np.empty(0)
    if head.size < 2 or not head[1] > head[0]:
        return None
    return float(round(1.0 / (head[1] - head[0]), 9))
