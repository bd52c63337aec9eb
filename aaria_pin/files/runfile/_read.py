"""Reading run files of every version: the record, its inputs only, a summary, a probe.

One probe per format (:func:`_probe_mat`, :func:`_probe_hdf5`) finds a file's layout from its
marks; the format itself comes from :func:`aaria_pin.files.source.file_format`.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.arguments import checked
from aaria_pin.core.record import SERIES, RunRecord
from aaria_pin.core.record_checks import check_kind_layout, check_record
from aaria_pin.errors import InputFileError
from aaria_pin.files._stored import NAME_LISTS, DamagedFileError, damaged_errors
from aaria_pin.files.detection import RUN_SUFFIXES, file_format
from aaria_pin.files.paths import existing_input
from aaria_pin.files.runfile._attributes import RUN_FORMAT_VERSION
from aaria_pin.files.runfile._checksums import (
    CHECKSUMS_ATTRIBUTE,
    stored_checksums,
    verify_checksums,
)
from aaria_pin.files.runfile._columns import COLUMNS_SUFFIX
from aaria_pin.files.runfile._hdf5 import _hdf5_errors, _read_hdf5_v2, _summarise_hdf5_v2
from aaria_pin.files.runfile._legacy_runs import (
    LAYOUT_V2,
    hdf5_layout,
    mat_layout,
    read_legacy_hdf5,
    read_legacy_mat,
)
from aaria_pin.files.runfile._mat import (
    MAT_ATTRIBUTE_PREFIX,
    _read_mat_v2,
    _summarise_mat_v2,
    load_mat,
    mat_value,
    mat_variables,
)
from aaria_pin.files.runfile._recorded import is_recorded_run, refuse_recorded


@checked
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
    return _read(path, series=True)


@checked
def read_run_inputs(path: str | os.PathLike[str]) -> RunRecord:
    """The record of a run file without its time series: what re-making the run needs.

    A version 2 file's series and views are not read (a 2,000,000-sample ``.h5`` holds
    2.4 GB of them); the record has no samples (``n_samples == 0``, every series of length
    0) and the file's names, IMU mounts, URDF, tables, views and attributes (``duration``,
    ``rate``, ``seed``, ...). A 0.1.0 file, whose inputs partly live in its series (a wrist
    run's time grid), is read whole, as by :func:`read_run`.

    Args:
        path: the run file

    Raises:
        InputFileError: as :func:`read_run`.
    """
    return _read(path, series=False)


@dataclass(frozen=True)
class _MatProbe:
    """A ``.mat`` run file's variable names and shapes, its small variables and its layout."""

    variables: dict[str, tuple[int, ...]]
    contents: dict[str, Any]  # the ``attr_`` variables, name lists and column names
    layout: str


def _probe_mat(file: Path) -> _MatProbe:
    """The layout of a ``.mat`` run file from its marks; its arrays are not read."""
    variables = mat_variables(file)
    small = [
        name
        for name in variables
        if name.startswith(MAT_ATTRIBUTE_PREFIX)
        or name in NAME_LISTS
        or name.endswith(COLUMNS_SUFFIX)
    ]
    contents = load_mat(file, small) if small else {}
    return _MatProbe(variables, contents, mat_layout(file, contents, variables))


@contextlib.contextmanager
def _probe_hdf5(file: Path) -> Iterator[tuple[Any, str]]:
    """An HDF5 run file open for reading, and its layout from its marks."""
    import h5py

    with _hdf5_errors(file), h5py.File(file, "r") as handle:
        yield handle, hdf5_layout(file, handle)


def _is_mat(file: Path) -> bool:
    """Whether an existing run file is a MAT-file (v5 or v7.3)."""
    return file_format(file) in ("mat5", "mat73")


def _read(path: str | os.PathLike[str], series: bool) -> RunRecord:
    """:func:`read_run` (``series``) or :func:`read_run_inputs`: read, verified, checked.

    The record's kind must have its tables, the arrays read must match their checksums
    (:mod:`._checksums`), then the record is checked
    (:func:`~aaria_pin.core.record_checks.check_record`: attributes, finite values).
    """
    file = existing_input(path, RUN_SUFFIXES, "run")
    record, checksums = _read_stored(file, series)
    unread = () if series else SERIES
    arrays = {name: data for name, data in record.arrays().items() if name not in unread}
    check_kind_layout(record, str(file))  # a table of its kind missing: said as such
    verify_checksums(file, checksums, arrays, unread)
    check_record(record, str(file), series)
    return record


def _read_stored(file: Path, series: bool) -> tuple[RunRecord, dict[str, str] | None]:
    """The record as stored and its checksums (None: a file written without them)."""
    if _is_mat(file):
        probe = _probe_mat(file)
        variables = probe.variables
        if probe.layout != LAYOUT_V2:
            return read_legacy_mat(file, load_mat(file), probe.layout), None
        views = [name for name in variables if name + COLUMNS_SUFFIX in variables]
        skipped = set(views) if series else {*views, *SERIES}
        contents = load_mat(file, [name for name in variables if name not in skipped])
        contents.update(dict.fromkeys(views))  # a view is read from its column names
        record = _read_mat_v2(file, contents, None if series else variables)
        stored = contents.get(MAT_ATTRIBUTE_PREFIX + CHECKSUMS_ATTRIBUTE)
        return record, stored_checksums(file, None if stored is None else mat_value(stored))
    with _probe_hdf5(file) as (handle, layout), damaged_errors(file):
        if is_recorded_run(handle):  # measured signals, no truth: not a RunRecord
            raise refuse_recorded(file)
        if layout == LAYOUT_V2:
            record = _read_hdf5_v2(file, handle, series)
            return record, stored_checksums(file, handle.attrs.get(CHECKSUMS_ATTRIBUTE))
        return read_legacy_hdf5(file, handle, layout), None


def run_file_summary(path: str | os.PathLike[str]) -> dict[str, Any]:
    """Describe a run file (for ``aaria info``); a version 2 file's arrays are not read.

    Args:
        path: the run file (any kind :func:`read_run` reads)

    Returns:
        ``path`` (str), ``format`` (``"HDF5"``, ``"MATLAB v5"`` or ``"MATLAB v7.3"``),
        ``format_version`` (int; 1 for every 0.1.0 file), ``layout`` (``"aaria_pin run"`` or
        the 0.1.0 layout, e.g. ``"0.1.0 wrist run"``), ``kind``, ``robot``, ``samples`` (T),
        ``rate`` [Hz] (the attribute, else from the first two sample times; None for one
        sample), ``joints`` and
        ``imus`` (names), ``arrays`` (name → shape, as :func:`read_run` gives them: the series,
        ``imu_mount`` and the tables), ``views`` (name → shape) and ``attributes`` (decoded as
        by :func:`read_run`).

    Raises:
        InputFileError: as :func:`read_run`.
    """
    file = existing_input(path, RUN_SUFFIXES, "run")
    kind = file_format(file)
    time_head: Any
    if kind in ("mat5", "mat73"):
        probe = _probe_mat(file)
        layout = probe.layout
        if layout == LAYOUT_V2:
            parts = _summarise_mat_v2(file, probe.variables, probe.contents)
            time_head = (
                load_mat(file, ["time"])["time"] if "rate" not in parts["attributes"] else None
            )
        else:
            parts = _record_parts(read_legacy_mat(file, load_mat(file), layout))
            time_head = parts.pop("time")
    else:
        with _probe_hdf5(file) as (handle, layout):
            if layout == LAYOUT_V2:
                parts = _summarise_hdf5_v2(file, handle)
                time_head = handle["time"][:2] if handle["time"].ndim == 1 else None
            else:
                parts = _record_parts(read_legacy_hdf5(file, handle, layout))
                time_head = parts.pop("time")
    attributes = parts["attributes"]
    return {
        "path": str(file),
        "format": _FORMAT_NAMES.get(kind, "HDF5"),
        "format_version": RUN_FORMAT_VERSION if layout == LAYOUT_V2 else 1,
        "layout": layout,
        "kind": attributes.get("kind"),
        "robot": attributes.get("robot"),
        "samples": parts["arrays"]["time"][0],
        "rate": _rate(attributes, time_head),
        **parts,
    }


_FORMAT_NAMES = {"hdf5": "HDF5", "mat5": "MATLAB v5", "mat73": "MATLAB v7.3"}
"""How :func:`run_file_summary` names a format."""


def is_run_file(path: str | os.PathLike[str]) -> bool:
    """Whether ``path`` is an existing run file :func:`read_run` reads (any version or kind).

    Only the file's marks and names are looked at, not its arrays; a data set is not a run file.

    Raises:
        DamagedFileError: a file of a run file's format that is damaged (truncated, a broken
            variable): it is neither a run file nor another file, and says so in one line.
    """
    try:
        file = existing_input(path, RUN_SUFFIXES, "run")
        if _is_mat(file):
            _probe_mat(file)
        else:
            with _probe_hdf5(file):
                pass
        return True
    except DamagedFileError:
        raise
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
