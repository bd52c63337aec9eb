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

import contextlib
import json
import os
from collections.abc import Iterable, Iterator, Mapping, Sequence
from typing import Any

import numpy as np

from aaria_pin.core.record import HARDWARE_UNITS, SERIES, UNITS, ColumnSource, ColumnView
from aaria_pin.errors import AariaError, InputFileError, OutputFileError

__all__ = [
    "HDF5_READ_ERRORS",
    "JSON_SUFFIX",
    "NAME_LISTS",
    "STORED_NAMES",
    "TABLE_UNITS",
    "DamagedFileError",
    "crc32_function",
    "create_virtual_view",
    "damaged_errors",
    "damaged_file",
    "decode_attribute",
    "decode_attributes",
    "encode_attributes",
    "first_line",
    "require_arrays",
    "units_of",
    "view_blocks",
    "write_attributes",
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
    "inertial_parameters": "m kg, mx my mz kg m, Ixx Ixy Iyy Ixz Iyz Izz kg m^2 (joint origin)",
}
"""The ``units`` attribute of the known input tables (other tables get ``""``)."""

JSON_SUFFIX = "_json"
"""Suffix of the name of an attribute stored as a JSON string."""

SAME_FILE = "."
"""The source file of a virtual dataset in the same file (valid after a rename or a copy)."""


def crc32_function() -> Any:
    """The CRC-32 of stored bytes, ``crc32(data, start) -> int``: ISA-L's, else zlib's.

    The checksum of run files and data sets alike: ISA-L's (``isal``) computes the same
    standard CRC-32 as zlib's about 12 times faster (200 kB in 4 µs against 49 µs).
    """
    try:
        from isal.isal_zlib import crc32
    except ImportError:  # isal is optional here: zlib makes the same CRC-32
        from zlib import crc32
    return crc32


def units_of(name: str) -> str:
    """The ``units`` attribute of a stored array by name (``""`` for an unknown table)."""
    return UNITS.get(name, TABLE_UNITS.get(name, HARDWARE_UNITS.get(name, "")))


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

    The mappings go straight into a dataset-creation property list through h5py's low-level
    API (``h5p.set_virtual`` with hyperslab dataspaces): the file is the one h5py's
    ``VirtualLayout`` makes (the same mappings, fill value, type and attributes; a test compares
    them), but h5py's ``VirtualSource`` deep-copies itself at every slice (16 blocks in
    ``senSen``): 1.9 ms of CPU that way, 0.5 ms here (``aaria-fig2``, 2 cores).

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
    from h5py import h5d, h5p, h5s, h5t

    lead = tuple(shapes["time"])
    shape = (*lead, len(view.columns))
    origin = (0,) * len(lead)
    dcpl = h5p.create(h5p.DATASET_CREATE)
    dcpl.set_layout(h5d.VIRTUAL)
    if 0 not in lead:
        for first, count, source in view_blocks(view):
            target = h5s.create_simple(shape)
            target.select_hyperslab((*origin, first), (*lead, count))
            stored = h5s.create_simple(tuple(shapes[source.array]))
            if source.index:
                *fixed, last = source.index
                stored.select_hyperslab(
                    (*origin, *fixed, last), (*lead, *(1 for _ in fixed), count)
                )
            else:
                stored.select_hyperslab(origin, lead)
            dcpl.set_virtual(target, SAME_FILE.encode(), source.array.encode("utf-8"), stored)
    dcpl.set_fill_value(np.array([0]))  # as h5py's create_virtual_dataset(fillvalue=0)
    dataset_id = h5d.create(
        handle.id,
        name.encode("utf-8"),
        h5t.py_create(np.dtype(dtype), logical=True),
        h5s.create_simple(shape),
        dcpl=dcpl,
    )
    columns = np.array(list(view.columns), dtype=_utf8())
    write_attributes(dataset_id, [("columns", columns), ("units", units)])
    return h5py.Dataset(dataset_id)


# --- attributes ----------------------------------------------------------------------------------


def _attribute_types(kind: str, dtype: Any) -> tuple[Any, Any]:
    """The file and memory HDF5 types of attribute values of a dtype (cached by ``kind``)."""
    from h5py import h5t

    types = _ATTRIBUTE_TYPES.get(kind)
    if types is None:
        types = _ATTRIBUTE_TYPES[kind] = (
            h5t.py_create(dtype, logical=True),
            h5t.py_create(dtype),
        )
    return types


_ATTRIBUTE_TYPES: dict[str, tuple[Any, Any]] = {}
"""HDF5 types of attribute values by kind (``str:<encoding>`` or a numpy dtype's ``str``)."""

_UTF8: list[Any] = []
"""h5py's variable-length UTF-8 string dtype, made once (``np.dtype`` with metadata)."""


def _utf8() -> Any:
    """h5py's ``string_dtype("utf-8")``, made on first use."""
    if not _UTF8:
        import h5py

        _UTF8.append(h5py.string_dtype("utf-8"))
    return _UTF8[0]


def _attribute_array(value: Any) -> tuple[str, Any] | None:
    """An attribute value's kind and the array h5py would store, or None for other values."""
    if isinstance(value, str):
        return "str:utf-8", np.array(value, dtype=_utf8())
    if isinstance(value, (bool, int, float, np.bool_, np.integer, np.floating)):
        try:
            data = np.asarray(value)
        except OverflowError:
            return None
        return (data.dtype.str, data) if data.dtype.kind in "biuf" else None
    if isinstance(value, np.ndarray):
        if value.dtype.kind in "biuf":
            return value.dtype.str, np.ascontiguousarray(value)
        if (  # h5py stores an object array by its items' type: str items as UTF-8
            value.dtype.kind == "O"
            and value.dtype.metadata == _utf8().metadata
            and all(isinstance(item, str) for item in value.flat)
        ):
            return "str:utf-8", np.ascontiguousarray(value)
    return None


def _high_level(object_id: Any) -> Any:
    """The h5py object of a low-level file, group or dataset identifier (a file: its root)."""
    import h5py
    from h5py import h5d, h5f, h5g

    if isinstance(object_id, h5d.DatasetID):
        return h5py.Dataset(object_id)
    if isinstance(object_id, h5f.FileID):
        return h5py.Group(h5g.open(object_id, b"/"))
    return h5py.Group(object_id)


def write_attributes(target: Any, attributes: Iterable[tuple[str, Any]]) -> None:
    """Create attributes on an HDF5 object, each as h5py's ``attrs[name] = value`` does.

    A ``str`` becomes a scalar variable-length UTF-8 string, a bool an HDF5 enum (h5py's),
    an int an int64, a float a float64, a numpy array (numbers, or strings of h5py's string
    dtype) an array of its shape: the types and dataspaces h5py's ``AttributeManager`` gives
    them (``tests/files/test_runfile_lowlevel.py`` compares the files). It calls HDF5 through
    h5py's low-level API with the types made once per process: h5py's ``attrs.create``
    converts the value, builds both types and looks for an existing attribute each time,
    140 µs an attribute against 24 µs here (measured on a busy machine; 14 µs of it is
    HDF5's own ``H5Acreate`` and write); a run file has 31. A value of any other type goes
    through ``attrs.create``.

    Args:
        target: an h5py object (file, group, dataset) or its low-level identifier
        attributes: (name, value) pairs, stored in order; an existing attribute of the same
            name is replaced
    """
    import h5py
    from h5py import h5a, h5s

    high_level = isinstance(target, (h5py.Group, h5py.Dataset, h5py.Datatype))
    object_id = target.id if high_level else target
    scalar = None
    for name, value in attributes:
        converted = _attribute_array(value)
        if converted is None:
            h5py.AttributeManager(_high_level(object_id)).create(name, data=value)
            continue
        kind, data = converted
        file_type, memory_type = _attribute_types(kind, data.dtype)
        key = name.encode("utf-8")
        if h5a.exists(object_id, key):
            h5a.delete(object_id, key)
        if data.ndim:
            space = h5s.create_simple(data.shape)
        else:
            space = scalar = scalar or h5s.create(h5s.SCALAR)
        attribute = h5a.create(object_id, key, file_type, space)
        try:
            attribute.write(data, mtype=memory_type)
        finally:
            attribute.close()


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
                f"{final}: attribute name {key!r} is not allowed; expected a non-empty string",
                parameter="attributes",
            )
        if key in reserved:
            raise OutputFileError(
                f"{final}: attribute name {key!r} is reserved; not allowed: {', '.join(reserved)}",
                parameter="attributes",
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
                "int, float, bool, lists of numbers, or JSON-serialisable lists and dicts",
                parameter="attributes",
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
                f"{file}: attribute {name!r} is a {type(value).__name__}; expected a JSON string",
                parameter="file",
            )
        try:
            return name[: -len(JSON_SUFFIX)], json.loads(value)
        except ValueError as exc:
            raise InputFileError(
                f"{file}: attribute {name!r} is not valid JSON ({first_line(exc)})",
                parameter="file",
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


HDF5_READ_ERRORS = (OSError, RuntimeError, ValueError, TypeError, KeyError)
"""What h5py raises reading a damaged file (RuntimeError: damaged metadata)."""


@contextlib.contextmanager
def read_errors(file: str | os.PathLike[str], what: str) -> Iterator[None]:
    """Turn h5py's (or the OS's) errors on reading ``file`` into a one-line InputFileError.

    Args:
        file: the file read
        what: what it was read as, for the message (``"an HDF5 run file"``)
    """
    try:
        yield
    except InputFileError:
        raise
    except HDF5_READ_ERRORS as exc:
        raise InputFileError(
            f"{file}: cannot be read as {what} ({first_line(exc)})",
            parameter="file",
            value=str(file),
        ) from None


def require_arrays(handle: Any, file: str | os.PathLike[str], names: Iterable[str]) -> None:
    """Refuse a member of ``names`` of an open HDF5 file that is not an array (InputFileError)."""
    import h5py

    for name in names:
        if name in handle and not isinstance(handle.get(name), h5py.Dataset):
            what = f"{file}: {name!r} is not an array; allowed: an array (re-make the file)"
            raise InputFileError(what, parameter="file", value=str(file))


class DamagedFileError(InputFileError):
    """A file of the expected format whose data cannot be read: damaged or truncated."""


def damaged_file(
    file: str | os.PathLike[str], reason: str, source: str | None = None
) -> DamagedFileError:
    """The one line of a damaged file: ``"FILE is damaged (<reason>); allowed: ..."``.

    Args:
        file: the file
        reason: what is wrong, in a few words (the first line of h5py's or scipy's error)
        source: how the message names what was read (default the file; ``run K of FILE``)
    """
    return DamagedFileError(
        f"{source or file} is damaged ({reason}); allowed: an undamaged file (re-make it)",
        parameter="file",
        value=str(file),
    )


@contextlib.contextmanager
def damaged_errors(file: str | os.PathLike[str], source: str | None = None) -> Iterator[None]:
    """Turn h5py's, scipy's or zlib's errors while reading a file's data into one line.

    For errors past the opening of a file that is of the expected kind: a damaged chunk
    (``Can't synchronously read data (filter returned failure during read)``), a truncated
    array, a broken deflate stream.

    Args:
        file: the file read
        source: how the message names what was read (default the file; ``run K of FILE``)

    Raises:
        DamagedFileError: ``"FILE is damaged (<the first line of the error>); ..."``
            (``parameter="file"``).
    """
    import zlib

    try:
        yield
    except InputFileError:
        raise
    except (*HDF5_READ_ERRORS, EOFError, zlib.error) as exc:
        if isinstance(exc, AariaError):
            raise
        raise damaged_file(file, first_line(exc), source) from None
