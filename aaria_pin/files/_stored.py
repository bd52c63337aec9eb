"""What run files and data sets store alike: dataset names, ``units`` attributes, virtual views.

A run file holds one run's arrays; a data set holds the same arrays with a leading run axis.
Both name them as the record does (:data:`~aaria_pin.core.record.SERIES`, ``imu_mount``, the
name lists, ``urdf``), give them the same ``units`` attributes, and store a column view (the
paper's ``senSen``, the flat ``signals``) as an HDF5 virtual dataset over the series of the same
file, built here. Their attributes are encoded alike (:func:`encode_attributes`): a string, a
number, a bool or a list of two or more numbers is stored as it is; anything else (a dict, a list
of strings, a one-item list, None, ...) and every attribute whose name already ends in ``_json``
is stored as a JSON string under its name plus the suffix ``_json``, and is JSON-decoded on
reading under its name without the suffix (:func:`decode_attribute`).
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from aaria_pin.core.record import SERIES, UNITS, ColumnSource, ColumnView
from aaria_pin.errors import InputFileError, OutputFileError

__all__ = [
    "JSON_SUFFIX",
    "NAME_LISTS",
    "STORED_NAMES",
    "TABLE_UNITS",
    "create_virtual_view",
    "decode_attribute",
    "decode_attributes",
    "encode_attributes",
    "first_line",
    "units_of",
    "view_blocks",
]

NAME_LISTS = ("joint_names", "imu_names", "imu_parents")
"""The string lists stored beside the arrays (string datasets in HDF5, cell arrays in ``.mat``)."""

STORED_NAMES = (*SERIES, "imu_mount", *NAME_LISTS, "urdf")
"""Every name a run file or a data set always holds (a table or a view cannot take one)."""

TABLE_UNITS = {
    "senSenDH": "columns: alpha rad, a m, theta rad, d m, "
    "link type (0 empty, 1 revolute, 2 prismatic)",
    "senSenJ": "columns: amplitude rad, prismatic amplitude m, bias rad or m, frequency rad/s, "
    "phase rad",
    "senSenB": "columns: amplitude m or rad, bias m or rad, frequency rad/s, phase rad",
    "joint_table": "columns: amplitude rad, prismatic amplitude m, bias rad or m, "
    "frequency rad/s, phase rad",
    "base_table": "columns: amplitude m or rad, bias m or rad, frequency rad/s, phase rad",
}
"""The ``units`` attribute of the known input tables (other tables get ``""``)."""

JSON_SUFFIX = "_json"
"""Suffix of the name of an attribute stored as a JSON string."""

SAME_FILE = "."
"""The source file of a virtual dataset in the same file (valid after a rename or a copy)."""


def units_of(name: str) -> str:
    """The ``units`` attribute of a stored array by name (``""`` for an unknown table)."""
    return UNITS.get(name, TABLE_UNITS.get(name, ""))


def view_blocks(view: ColumnView) -> list[tuple[int, int, ColumnSource]]:
    """A view's columns grouped into blocks that each map to one slice of one series.

    Returns:
        ``(first column, column count, source of the first column)`` per block: consecutive
        columns of one series whose last index runs on by one make one block (``senSen`` is
        16 blocks: time, q, one per IMU slot).
    """
    blocks: list[tuple[int, int, ColumnSource]] = []
    for column, source in enumerate(view.sources):
        if blocks:
            first, count, start = blocks[-1]
            if (
                source.index
                and start.array == source.array
                and start.index[:-1] == source.index[:-1]
                and source.index[-1] == start.index[-1] + count
            ):
                blocks[-1] = (first, count + 1, start)
                continue
        blocks.append((column, 1, source))
    return blocks


def create_virtual_view(
    handle: Any,
    name: str,
    view: ColumnView,
    shapes: Mapping[str, tuple[int, ...]],
    dtype: Any,
    units: str,
) -> Any:
    """Store a view as an HDF5 virtual dataset over the series of the same file.

    The sources name the file ``"."`` (this file, whatever its name or folder), so the view stays
    valid when the file is renamed or moved; HDF5 1.10 or newer reads it (h5py, MATLAB's
    ``h5read``). Each block of :func:`view_blocks` is one mapping.

    Args:
        handle: the open, writable h5py file
        name: the view's dataset name
        view: its columns and their sources
        shapes: the stored shape of each series the view refers to; ``time``'s shape gives the
            view's leading axes (T in a run file, N × T in a data set)
        dtype: the stored series' dtype (the view's too)
        units: the view's ``units`` attribute

    Returns:
        The h5py dataset, with its ``columns`` and ``units`` attributes.
    """
    import h5py

    lead = tuple(shapes["time"])
    everything = (slice(None),) * len(lead)
    layout = h5py.VirtualLayout(shape=(*lead, len(view.columns)), dtype=dtype)
    if 0 not in lead:
        sources: dict[str, Any] = {}
        for first, count, source in view_blocks(view):
            if source.array not in sources:
                sources[source.array] = h5py.VirtualSource(
                    SAME_FILE, source.array, shape=shapes[source.array], dtype=dtype
                )
            vsource = sources[source.array]
            if not source.index:
                layout[(*everything, first)] = vsource[everything]
            else:
                *fixed, last = source.index
                block = (*everything, *fixed, slice(last, last + count))
                layout[(*everything, slice(first, first + count))] = vsource[block]
    dataset = handle.create_virtual_dataset(name, layout, fillvalue=0)
    dataset.attrs.create("columns", list(view.columns), dtype=h5py.string_dtype("utf-8"))
    dataset.attrs["units"] = units
    return dataset


# --- attributes ----------------------------------------------------------------------------------

_INT64 = np.iinfo(np.int64)


def encode_attributes(
    final: str | os.PathLike[str],
    attributes: Mapping[str, Any],
    reserved: Sequence[str] = ("format", "format_version"),
) -> list[tuple[str, Any]]:
    """Stored (name, value) pairs of attributes (the encoding: the module docstring).

    Args:
        final: the file written, for messages
        attributes: the attributes by name
        reserved: names the file sets itself, refused here

    Raises:
        OutputFileError: an empty or reserved name, or a value JSON cannot hold.
    """
    encoded: list[tuple[str, Any]] = []
    for key, value in attributes.items():
        if not isinstance(key, str) or not key:
            raise OutputFileError(
                f"{final}: attribute name {key!r} is not allowed; expected a non-empty string"
            )
        if key in reserved:
            raise OutputFileError(
                f"{final}: attribute name {key!r} is reserved; not allowed: {', '.join(reserved)}"
            )
        plain = None if key.endswith(JSON_SUFFIX) else _plain_value(value)
        if plain is not None:
            encoded.append((key, plain))
            continue
        try:
            text = json.dumps(value, default=_json_default, ensure_ascii=False)
        except (TypeError, ValueError) as exc:
            raise OutputFileError(
                f"{final}: attribute {key!r} cannot be stored ({first_line(exc)}); allowed: str, "
                "int, float, bool, lists of numbers, or JSON-serialisable lists and dicts"
            ) from None
        encoded.append((key + JSON_SUFFIX, text))
    return encoded


def _plain_value(value: Any) -> Any:
    """The value as a plain scalar or numeric vector attribute, or None if it needs JSON."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value) if _INT64.min <= int(value) <= _INT64.max else None
    if isinstance(value, (float, np.floating)):
        return float(value)
    if isinstance(value, str):
        return value
    if isinstance(value, np.ndarray):
        items = value.tolist() if value.ndim == 1 else None
    elif isinstance(value, (list, tuple)):
        items = list(value)
    else:
        items = None
    if items is None or len(items) < 2:
        return None
    if not all(
        isinstance(item, (int, float, np.integer, np.floating))
        and not isinstance(item, (bool, np.bool_))
        for item in items
    ):
        return None
    if all(isinstance(item, (int, np.integer)) for item in items):
        try:
            return np.array(items, dtype=np.int64)
        except OverflowError:
            return None
    return np.array(items, dtype=np.float64)


def _json_default(value: Any) -> Any:
    """JSON form of numpy scalars and arrays inside an attribute."""
    if isinstance(value, (np.generic, np.ndarray)):
        return value.tolist()
    raise TypeError(f"{type(value).__name__} is not JSON serialisable")


def decode_attribute(file: str | os.PathLike[str], name: str, value: Any) -> tuple[str, Any]:
    """The (key, value) of a stored attribute: JSON-decoded, numpy values made plain.

    Raises:
        InputFileError: a ``_json`` attribute that is not a valid JSON string.
    """
    if isinstance(value, bytes):
        value = value.decode("utf-8", errors="replace")
    if name.endswith(JSON_SUFFIX):
        if not isinstance(value, str):
            raise InputFileError(
                f"{file}: attribute {name!r} is a {type(value).__name__}; expected a JSON string"
            )
        try:
            return name[: -len(JSON_SUFFIX)], json.loads(value)
        except ValueError as exc:
            raise InputFileError(
                f"{file}: attribute {name!r} is not valid JSON ({first_line(exc)})"
            ) from None
    if isinstance(value, np.ndarray):
        return name, value.tolist()
    if isinstance(value, np.generic):
        return name, value.item()
    return name, value


def decode_attributes(
    attrs: Mapping[str, Any], file: str | os.PathLike[str] = "HDF5 file"
) -> dict[str, Any]:
    """Stored attributes (an h5py ``attrs``) decoded by :func:`decode_attribute`, by key."""
    return dict(decode_attribute(file, name, value) for name, value in attrs.items())


def first_line(exc: BaseException) -> str:
    """The first line of an exception's message, or its type name."""
    text = str(exc)
    return text.splitlines()[0] if text else type(exc).__name__
