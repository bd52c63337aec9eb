"""The run file layout shared by the HDF5 and ``.mat`` formats: names, shapes, views.

"The module docstring" in the docstrings below is that of :mod:`aaria_pin.files.runfile`, which
describes the layout.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.record import (
    IMU_SIGNALS,
    SERIES,
    VIEW_UNITS,
    ColumnSource,
    ColumnView,
    ImuMount,
    RunRecord,
    record_shapes,
)
from aaria_pin.core.se3 import Array
from aaria_pin.errors import InputFileError, OutputFileError, ParameterError
from aaria_pin.files._stored import STORED_NAMES

COLUMNS_SUFFIX = "_columns"
"""A view's column names in a ``.mat`` file: ``<view>_columns``."""

_CHUNK_ROWS = 4096
_CHUNK_BYTES = 2**20


def chunk_rows(samples: int, row_bytes: int) -> int:
    """Samples per chunk of a compressed series, in both formats: at most 4096 and 1 MiB.

    Args:
        samples: the series' samples
        row_bytes: the bytes of one sample [bytes]

    Returns:
        At least 1, at most ``samples``, 4096 and 1 MiB of rows.
    """
    return max(1, min(samples, _CHUNK_ROWS, _CHUNK_BYTES // max(1, row_bytes)))


class RunStream:
    """An open run file whose series are preallocated, then filled piece by piece.

    The protocol of both formats' streams (``_hdf5._Hdf5Stream``, ``_mat73._Mat73Stream``):
    ``__init__`` opens the file (:meth:`_open`) and lays out everything but the series' values
    and the attributes (:meth:`_lay_out`; on failure the file is closed and the caller removes
    it), :meth:`write` fills samples, :meth:`close` writes the attributes and closes it.

    Args:
        file: the file to write (a temporary beside the destination)
        first: the run's first piece (its names, tables, views and URDF)
        arrays: the first piece's arrays by stored name
        samples: the run's samples
        compression: ``None`` or the series' compression
    """

    def __init__(
        self,
        file: Path,
        first: RunRecord,
        arrays: Mapping[str, Array],
        samples: int,
        compression: str | None = None,
    ) -> None:
        self.file = file
        self.samples = samples
        self.handle = self._open(file)
        try:
            self._lay_out(first, arrays, samples, compression)
        except BaseException:
            self.close(None)  # a failed file: closed safely; the caller removes it
            raise

    def _open(self, file: Path) -> Any:
        """The open h5py file."""
        raise NotImplementedError

    def _lay_out(
        self, first: RunRecord, arrays: Mapping[str, Array], samples: int, compression: str | None
    ) -> None:
        """Create every dataset of the run at its full length."""
        raise NotImplementedError

    def write(self, start: int, arrays: Mapping[str, Array]) -> None:
        """Store samples ``start`` … of the series (contiguous float64 by name)."""
        raise NotImplementedError

    def close(self, attributes: list[tuple[str, Any]] | None) -> None:
        """Write the attributes (None: an aborted write, none) and close the file."""
        raise NotImplementedError


_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]{0,62}")
_JOINT_SERIES = ("q", "qd", "qdd", "tau")
_NUMBERED = re.compile(r"(q|qd|qdd|tau)([1-9][0-9]*)")
_COLUMN_RULE = "time, q<j>, q:<joint> (also qd, qdd, tau), <imu>_<signal>"


def describe_shape(shape: tuple[int, ...]) -> str:
    """A shape for a message or a summary, e.g. ``(37, 6)``."""
    return f"({', '.join(str(dim) for dim in shape)})"


def fit_shape(shape: tuple[int, ...], expected: tuple[int, ...]) -> tuple[int, ...] | None:
    """The expected shape that ``shape`` fills, allowing only axes of length 1 to differ.

    Args:
        shape: shape as stored (a ``.mat`` reader may add or drop axes of length 1)
        expected: expected shape, at most one -1 (any length)

    Returns:
        The full expected shape, or None if ``shape`` does not fit it.
    """
    size = math.prod(shape)
    known = math.prod(dim for dim in expected if dim != -1)
    if -1 in expected:
        if known == 0 or size % known:
            return None
        full = tuple(size // known if dim == -1 else dim for dim in expected)
    else:
        full = expected
        if size != known:
            return None
    if tuple(shape) == full or size == 0:
        return full
    squeezed = tuple(dim for dim in shape if dim != 1)
    return full if squeezed == tuple(dim for dim in full if dim != 1) else None


NUMBER_KINDS = "iuf"
"""The numpy dtype kinds a stored array may have: integers and floats (not bools or text)."""


def numeric(file: Path, name: str, data: Any) -> Array:
    """A stored array as float64; InputFileError if it is not numbers (text, bools, objects)."""
    stored = np.asarray(data)
    if stored.dtype.kind not in NUMBER_KINDS:
        raise InputFileError(
            f"{file}: array {name} is of type {stored.dtype}; allowed: numbers (float64)",
            parameter="file",
        )
    return np.asarray(stored, dtype=np.float64)


def fitted(file: Path, name: str, data: Array, expected: tuple[int, ...]) -> Array:
    """A stored array as float64 in its expected shape; InputFileError if it does not fit."""
    array = numeric(file, name, data)
    full = fit_shape(array.shape, expected)
    if full is None:
        wanted = describe_shape(expected).replace("-1", "T")
        raise InputFileError(
            f"{file}: array {name!r} has shape {describe_shape(array.shape)}; expected {wanted}",
            parameter="file",
        )
    return array.reshape(full)


# --- views ---------------------------------------------------------------------------------------


def column_source(
    column: str, joint_names: Sequence[str], imu_names: Sequence[str]
) -> ColumnSource | None:
    """Where a view column comes from, read from its name (None: the name is not readable).

    ``time`` → ``time``; ``q<j>`` (1-based) or ``q:<joint>`` → a column of ``q`` (likewise
    ``qd``, ``qdd``, ``tau``); ``<imu>_<signal>`` → a signal of one IMU of ``imu``.
    """
    if column == "time":
        return ColumnSource("time", ())
    series, colon, joint = column.partition(":")
    if colon and series in _JOINT_SERIES and joint in joint_names:
        return ColumnSource(series, (list(joint_names).index(joint),))
    numbered = _NUMBERED.fullmatch(column)
    if numbered and int(numbered[2]) <= len(joint_names):
        return ColumnSource(numbered[1], (int(numbered[2]) - 1,))
    imu, underscore, signal = column.rpartition("_")
    if underscore and signal in IMU_SIGNALS and imu in imu_names:
        return ColumnSource("imu", (list(imu_names).index(imu), IMU_SIGNALS.index(signal)))
    return None


def view_from_columns(
    columns: Sequence[str],
    joint_names: Sequence[str],
    imu_names: Sequence[str],
    units: str = VIEW_UNITS,
) -> ColumnView:
    """A column view rebuilt from its column names (rule: :func:`column_source`).

    Raises:
        ParameterError: a column name that names no column of the record.
    """
    sources = []
    for column in columns:
        source = column_source(column, joint_names, imu_names)
        if source is None:
            raise ParameterError(
                f"view column {column!r} names no column of the run; allowed: {_COLUMN_RULE}",
                parameter="columns",
            )
        sources.append(source)
    return ColumnView(tuple(columns), tuple(sources), units)


def read_view(
    file: Path, name: str, columns: Sequence[str], record_names: tuple[Sequence[str], ...]
) -> ColumnView:
    """A stored view rebuilt from its column names; InputFileError if one is not readable."""
    joint_names, imu_names = record_names
    try:
        return view_from_columns(list(columns), joint_names, imu_names)
    except ParameterError as exc:
        raise InputFileError(f"{file}: view {name!r}: {exc}", parameter="file") from None


# --- writing -------------------------------------------------------------------------------------


def checked_arrays(final: Path, record: RunRecord) -> dict[str, Array]:
    """The record's stored arrays as contiguous float64, names and views checked.

    Returns:
        The series, ``imu_mount`` and the tables by name, in file order; a table of fewer than
        two axes as a 1 × k row (MATLAB has no 1-D arrays, so both formats store it so).

    Raises:
        OutputFileError: an array of the wrong shape or not numeric, a table or view name that
            is not allowed, or a view whose column names do not read back as its columns.
    """
    taken = set(STORED_NAMES)
    for kind, names in (("table", list(record.tables)), ("view", list(record.views))):
        for name in names:
            if not isinstance(name, str) or not _NAME.fullmatch(name) or name in taken:
                raise OutputFileError(
                    f"{final}: {kind} name {name!r} is not allowed; allowed: letters, digits "
                    "and _ (a letter first, at most 63 characters), none of "
                    + ", ".join(sorted(taken)),
                    parameter="record",
                )
            taken.add(name)
            if kind == "view":
                taken.add(name + COLUMNS_SUFFIX)
    samples = int(np.shape(record.time)[0]) if np.ndim(record.time) == 1 else -1
    expected = record_shapes(samples, len(record.joint_names), len(record.imu_mounts))
    arrays: dict[str, Array] = {}
    stored = record.arrays()
    for name, value in stored.items():
        try:
            data = np.ascontiguousarray(value, dtype=np.float64)
            arrays[name] = data if name in expected else np.atleast_2d(data)
        except (TypeError, ValueError):
            raise OutputFileError(
                f"{final}: array {name!r} is not numeric; expected float values", parameter="record"
            ) from None
        if name in expected and arrays[name].shape != expected[name]:
            raise OutputFileError(
                f"{final}: array {name!r} has shape {describe_shape(arrays[name].shape)}; "
                f"expected {describe_shape(expected[name])}",
                parameter="record",
            )
    joint_names, imu_names = record.joint_names, record.imu_names  # built once, not per column
    for name, view in record.views.items():
        for column, source in zip(view.columns, view.sources, strict=True):
            read = column_source(column, joint_names, imu_names)
            if read != source:
                raise OutputFileError(
                    f"{final}: view {name!r} column {column!r} is {source.array}"
                    f"{list(source.index)} but its name reads back as "
                    f"{'nothing' if read is None else f'{read.array}{list(read.index)}'}; "
                    f"allowed names: {_COLUMN_RULE}",
                    parameter="record",
                )
    return arrays


def record_from_arrays(
    file: Path,
    arrays: Mapping[str, Array],
    names: Mapping[str, Sequence[str]],
    *,
    urdf: str,
    tables: dict[str, Array],
    views: dict[str, ColumnView],
    attributes: dict[str, Any],
) -> RunRecord:
    """A run record from read arrays and names; InputFileError if they do not agree."""
    mounts = tuple(
        ImuMount(name, parent, pose)
        for name, parent, pose in zip(
            names["imu_names"], names["imu_parents"], arrays["imu_mount"], strict=True
        )
    )
    try:
        return RunRecord(
            **{name: arrays[name] for name in SERIES},
            joint_names=tuple(names["joint_names"]),
            imu_mounts=mounts,
            urdf=urdf,
            tables=tables,
            views=views,
            attributes=attributes,
        )
    except ParameterError as exc:
        raise InputFileError(f"{file}: {exc}", parameter="file") from None


def check_names(file: Path, names: Mapping[str, Sequence[str]], imus: int) -> None:
    """Refuse IMU names and parents whose counts differ from ``imu_mount``'s."""
    for key in ("imu_names", "imu_parents"):
        if len(names[key]) != imus:
            raise InputFileError(
                f"{file}: {key} holds {len(names[key])} names; expected {imus}, one per imu_mount",
                parameter="file",
            )
