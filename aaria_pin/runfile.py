"""Writing and reading the run file of one simulation run (a :class:`RunRecord`).

Two formats, chosen by the file suffix:

``.h5`` / ``.hdf5`` (HDF5, through h5py)
    One float64 dataset per array at the file root, named and shaped as in the record:
    ``senSen`` T × 91, ``senSenDH`` 8 × 5, ``senSenJ`` 8 × 5, ``senSenB`` 2 × 4 or 6 × 4, ``q``,
    ``qd``, ``qdd``, ``tau``, ``base_wrench`` T × 6, ``tool_pose`` T × 4 × 4, ``imu_mount``
    14 × 4 × 4. Every dataset has a ``units`` attribute (a string); ``senSen`` also has
    ``columns``, its 91 column names as an array of variable-length UTF-8 strings (read by h5py
    and by MATLAB's ``h5readatt``). The time series (the datasets with T rows) are chunked along
    time, up to 4096 rows and at most 1 MiB per chunk, and compressed with gzip level 1 after
    the shuffle filter: gzip is the one filter every HDF5 build has (MATLAB included; lzf is
    h5py-only), level 1 is nearly as small as level 9 on float data once shuffled and several
    times faster. The small tables and ``imu_mount`` are stored contiguous and uncompressed.
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

import json
import math
import os
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin._se3 import Array
from aaria_pin.errors import InputFileError, OutputFileError
from aaria_pin.io import atomic_output
from aaria_pin.record import N_SENSEN_COLUMNS, SENSEN_COLUMNS, RunRecord

__all__ = [
    "JSON_SUFFIX",
    "RUN_FORMAT",
    "RUN_FORMAT_VERSION",
    "RUN_SUFFIXES",
    "read_run",
    "run_file_summary",
    "write_run",
]

RUN_FORMAT = "aaria_pin run"
"""Value of the ``format`` attribute that marks a run file."""

RUN_FORMAT_VERSION = 1
"""Layout version written, and the newest one read."""

RUN_SUFFIXES = (".h5", ".hdf5", ".mat")
"""File suffixes of run files (case-insensitive)."""

JSON_SUFFIX = "_json"
"""Suffix of the name of an attribute stored as a JSON string."""

_HDF5_SUFFIXES = (".h5", ".hdf5")
_RESERVED_ATTRIBUTES = ("format", "format_version")
_MAT_ATTRIBUTE_PREFIX = "attr_"
_MAT_COLUMNS_NAME = "senSen_columns"
_MAT_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]{0,62}")
_MAT_MAX_ARRAY_BYTES = 2**31 - 1
_CHUNK_ROWS = 4096
_CHUNK_BYTES = 2**20
_INT64 = np.iinfo(np.int64)

_ROW_SHAPES: dict[str, tuple[int, ...]] = {
    "senSen": (N_SENSEN_COLUMNS,),
    "q": (6,),
    "qd": (6,),
    "qdd": (6,),
    "tau": (6,),
    "base_wrench": (6,),
    "tool_pose": (4, 4),
}
"""Shape of one sample of each time series (the arrays with T rows)."""

_TABLE_SHAPES: dict[str, tuple[int, ...]] = {
    "senSenDH": (8, 5),
    "senSenJ": (8, 5),
    "senSenB": (-1, 4),
    "imu_mount": (14, 4, 4),
}
"""Shapes of the arrays without a time axis (-1: any number of rows)."""

_UNITS = {
    "senSen": "see columns: s, rad or m, rad/s, m/s^2",
    "senSenDH": "see docs",
    "senSenJ": "see docs",
    "senSenB": "see docs",
    "q": "rad or m",
    "qd": "rad/s or m/s",
    "qdd": "rad/s^2 or m/s^2",
    "tau": "N*m or N",
    "base_wrench": "N, N*m",
    "tool_pose": "m",
    "imu_mount": "m",
}


def write_run(path: str | os.PathLike[str], record: RunRecord) -> Path:
    """Write a run record to an HDF5 (``.h5``, ``.hdf5``) or MATLAB (``.mat``) file.

    The file is written beside its destination and renamed when complete, so a failure never
    leaves a partial file (see :func:`aaria_pin.io.atomic_output`). The layout is described in
    the module docstring.

    Args:
        path: the run file; its suffix selects the format
        record: the run to write

    Returns:
        The path written.

    Raises:
        OutputFileError: unknown suffix, missing folder, an array of the wrong shape, an
            attribute that cannot be stored, or a write failure.
    """
    final = Path(path)
    suffix = final.suffix.lower()
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
                _write_hdf5(temporary, arrays, attributes)
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


# --- arrays and shapes -----------------------------------------------------------------------


def _checked_arrays(final: Path, record: RunRecord) -> dict[str, Array]:
    """The record's arrays as float64, each checked against the layout."""
    arrays: dict[str, Array] = {}
    for name, value in record.arrays().items():
        try:
            arrays[name] = np.ascontiguousarray(value, dtype=np.float64)
        except (TypeError, ValueError):
            raise OutputFileError(
                f"{final}: array {name!r} is not numeric; expected float values"
            ) from None
    samples = arrays["senSen"].shape[0] if arrays["senSen"].ndim == 2 else -1
    for name, data in arrays.items():
        expected = _expected_shape(name, samples)
        if _fit_shape(data.shape, expected) != data.shape:
            raise OutputFileError(
                f"{final}: array {name!r} has shape {data.shape}; "
                f"expected {_describe_shape(name, expected)}"
            )
    return arrays


def _expected_shape(name: str, samples: int) -> tuple[int, ...]:
    """Expected shape of an array (-1: any number of rows; ``samples`` -1: T not known yet)."""
    if name in _ROW_SHAPES:
        return (samples, *_ROW_SHAPES[name])
    return _TABLE_SHAPES[name]


def _describe_shape(name: str, expected: tuple[int, ...]) -> str:
    """An expected shape for a message, e.g. ``(T, 6)`` or ``(rows, 4)``."""
    rows = "T" if name in _ROW_SHAPES else "rows"
    dims = [rows if dim == -1 else str(dim) for dim in expected]
    return f"({', '.join(dims)})"


def _fit_shape(shape: tuple[int, ...], expected: tuple[int, ...]) -> tuple[int, ...] | None:
    """The expected shape that ``shape`` fills, allowing only singleton axes to differ.

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
    if tuple(shape) == full:
        return full
    squeezed = tuple(dim for dim in shape if dim != 1)
    return full if squeezed == tuple(dim for dim in full if dim != 1) else None


def _fit_shapes(file: Path, shapes: Mapping[str, tuple[int, ...]]) -> dict[str, tuple[int, ...]]:
    """The record shapes of stored arrays, in record order; InputFileError if one does not fit."""
    fitted: dict[str, tuple[int, ...]] = {}
    samples = -1
    for name in RunRecord.ARRAY_NAMES:
        expected = _expected_shape(name, samples)
        full = _fit_shape(shapes[name], expected)
        if full is None:
            raise InputFileError(
                f"{file}: array {name!r} has shape {tuple(shapes[name])}; "
                f"expected {_describe_shape(name, expected)}"
            )
        if name == "senSen":
            samples = full[0]
        fitted[name] = full
    return fitted


# --- attributes --------------------------------------------------------------------------------


def _encode_attributes(final: Path, attributes: Mapping[str, Any]) -> list[tuple[str, Any]]:
    """Stored (name, value) pairs of the record's attributes (see the module docstring)."""
    encoded: list[tuple[str, Any]] = []
    for key, value in attributes.items():
        if not isinstance(key, str) or not key:
            raise OutputFileError(
                f"{final}: attribute name {key!r} is not allowed; expected a non-empty string"
            )
        if key in _RESERVED_ATTRIBUTES:
            raise OutputFileError(
                f"{final}: attribute name {key!r} is reserved; "
                f"not allowed: {', '.join(_RESERVED_ATTRIBUTES)}"
            )
        plain = None if key.endswith(JSON_SUFFIX) else _plain_value(value)
        if plain is not None:
            encoded.append((key, plain))
            continue
        try:
            text = json.dumps(value, default=_json_default, ensure_ascii=False)
        except (TypeError, ValueError) as exc:
            raise OutputFileError(
                f"{final}: attribute {key!r} cannot be stored ({_reason(exc)}); allowed: str, "
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


def _decode_attribute(file: Path, name: str, value: Any) -> tuple[str, Any]:
    """Record (key, value) of a stored attribute: JSON-decoded, numpy values made plain."""
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
                f"{file}: attribute {name!r} is not valid JSON ({_reason(exc)})"
            ) from None
    if isinstance(value, np.ndarray):
        return name, value.tolist()
    if isinstance(value, np.generic):
        return name, value.item()
    return name, value


def _check_format(file: Path, fmt: Any, version: Any) -> int:
    """Check the ``format`` marks a run file of a known version; return the version."""
    if isinstance(fmt, bytes):
        fmt = fmt.decode("utf-8", errors="replace")
    if fmt is None:
        raise InputFileError(f"{file}: not an aaria_pin run file (no 'format' attribute)")
    if fmt != RUN_FORMAT:
        raise InputFileError(
            f"{file}: not an aaria_pin run file (format is {fmt!r}; expected {RUN_FORMAT!r})"
        )
    if isinstance(version, (float, np.floating)) and float(version).is_integer():
        version = int(version)  # MATLAB stores numbers as double unless told otherwise
    if not isinstance(version, (int, np.integer)) or isinstance(version, (bool, np.bool_)):
        raise InputFileError(
            f"{file}: format_version {version!r} is not allowed; expected an integer"
        )
    if not 1 <= int(version) <= RUN_FORMAT_VERSION:
        raise InputFileError(
            f"{file}: format_version {int(version)} is not supported; "
            f"this aaria_pin reads 1 to {RUN_FORMAT_VERSION}"
        )
    return int(version)


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


def _reason(exc: BaseException) -> str:
    """The first line of an exception's message, or its type name."""
    text = str(exc)
    return text.splitlines()[0] if text else type(exc).__name__


def _write_hdf5(file: Path, arrays: Mapping[str, Array], attributes: list[tuple[str, Any]]) -> None:
    """Write the HDF5 layout (see the module docstring)."""
    import h5py

    with h5py.File(file, "w", track_order=True) as handle:
        handle.attrs["format"] = RUN_FORMAT
        handle.attrs["format_version"] = RUN_FORMAT_VERSION
        for key, value in attributes:
            handle.attrs[key] = value
        for name, data in arrays.items():
            if name in _ROW_SHAPES and data.shape[0] > 0:
                row_bytes = data[0].nbytes
                rows = max(1, min(data.shape[0], _CHUNK_ROWS, _CHUNK_BYTES // row_bytes))
                dataset = handle.create_dataset(
                    name,
                    data=data,
                    chunks=(rows, *data.shape[1:]),
                    compression="gzip",
                    compression_opts=1,
                    shuffle=True,
                )
            else:
                dataset = handle.create_dataset(name, data=data)
            dataset.attrs["units"] = _UNITS[name]
        handle["senSen"].attrs.create(
            "columns", list(SENSEN_COLUMNS), dtype=h5py.string_dtype("utf-8")
        )


def _read_hdf5(file: Path) -> tuple[dict[str, Array], dict[str, Any]]:
    """Arrays (fitted to the record shapes) and decoded attributes of an HDF5 run file."""
    import h5py

    try:
        with h5py.File(file, "r") as handle:
            _check_format(file, handle.attrs.get("format"), handle.attrs.get("format_version"))
            datasets = _hdf5_datasets(file, handle, h5py.Dataset)
            shapes = _fit_shapes(file, {name: item.shape for name, item in datasets.items()})
            arrays = {
                name: np.asarray(item[()], dtype=np.float64).reshape(shapes[name])
                for name, item in datasets.items()
            }
            attributes = _hdf5_attributes(file, handle.attrs)
    except InputFileError:
        raise
    except (OSError, ValueError, TypeError, KeyError) as exc:
        raise InputFileError(
            f"{file}: cannot be read as an HDF5 run file ({_reason(exc)})"
        ) from None
    return arrays, attributes


def _summarise_hdf5(file: Path) -> tuple[dict[str, tuple[int, ...]], dict[str, Any], int]:
    """Stored shapes, decoded attributes and format version of an HDF5 run file."""
    import h5py

    try:
        with h5py.File(file, "r") as handle:
            version = _check_format(
                file, handle.attrs.get("format"), handle.attrs.get("format_version")
            )
            datasets = _hdf5_datasets(file, handle, h5py.Dataset)
            shapes = {name: tuple(item.shape) for name, item in datasets.items()}
            attributes = _hdf5_attributes(file, handle.attrs)
    except InputFileError:
        raise
    except (OSError, ValueError, TypeError, KeyError) as exc:
        raise InputFileError(
            f"{file}: cannot be read as an HDF5 run file ({_reason(exc)})"
        ) from None
    return shapes, attributes, version


def _hdf5_datasets(file: Path, handle: Any, dataset_type: type) -> dict[str, Any]:
    """The record's datasets of an open HDF5 file; InputFileError if one is missing."""
    datasets: dict[str, Any] = {}
    for name in RunRecord.ARRAY_NAMES:
        item = handle.get(name)
        if not isinstance(item, dataset_type):
            raise InputFileError(f"{file}: not an aaria_pin run file (no dataset {name!r})")
        datasets[name] = item
    return datasets


def _hdf5_attributes(file: Path, attrs: Any) -> dict[str, Any]:
    """The record attributes of an HDF5 root group, decoded."""
    attributes: dict[str, Any] = {}
    for name in attrs:
        if name not in _RESERVED_ATTRIBUTES:
            key, value = _decode_attribute(file, name, attrs[name])
            attributes[key] = value
    return attributes


def _check_mat_contents(
    final: Path, arrays: Mapping[str, Array], attributes: list[tuple[str, Any]]
) -> None:
    """Raise OutputFileError for what a MATLAB v5 file cannot hold."""
    for key, _ in attributes:
        if not _MAT_NAME.fullmatch(_MAT_ATTRIBUTE_PREFIX + key):
            raise OutputFileError(
                f"{final}: attribute {key!r} cannot be a MATLAB variable "
                f"{_MAT_ATTRIBUTE_PREFIX}{key}; allowed: letters, digits and _, at most "
                f"{63 - len(_MAT_ATTRIBUTE_PREFIX)} characters"
            )
    for name, data in arrays.items():
        if data.nbytes > _MAT_MAX_ARRAY_BYTES:
            raise OutputFileError(
                f"{final}: array {name!r} is {data.nbytes / 2**30:.1f} GiB; a .mat (v5) file "
                "holds at most 2 GiB per array, write .h5 instead"
            )


def _write_mat(file: Path, arrays: Mapping[str, Array], attributes: list[tuple[str, Any]]) -> None:
    """Write the MATLAB v5 layout (see the module docstring)."""
    from scipy.io import savemat

    contents: dict[str, Any] = dict(arrays)
    contents[_MAT_COLUMNS_NAME] = np.array(SENSEN_COLUMNS, dtype=object)
    contents[_MAT_ATTRIBUTE_PREFIX + "format"] = RUN_FORMAT
    contents[_MAT_ATTRIBUTE_PREFIX + "format_version"] = np.int64(RUN_FORMAT_VERSION)
    for key, value in attributes:
        contents[_MAT_ATTRIBUTE_PREFIX + key] = value
    savemat(file, contents, appendmat=False, format="5", do_compression=True, oned_as="row")


def _load_mat(file: Path, names: list[str] | None = None) -> dict[str, Any]:
    """Variables of a MATLAB v5 file, unsqueezed, in MATLAB's own classes."""
    from scipy.io import loadmat
    from scipy.io.matlab import MatReadError

    try:
        return loadmat(
            file, appendmat=False, squeeze_me=False, mat_dtype=True, variable_names=names
        )
    except NotImplementedError:
        raise InputFileError(
            f"{file}: is a MATLAB v7.3 file; allowed: MATLAB v5 .mat run files or .h5"
        ) from None
    except (MatReadError, OSError, ValueError, TypeError, EOFError) as exc:
        raise InputFileError(
            f"{file}: cannot be read as a .mat run file ({_reason(exc)})"
        ) from None


def _mat_value(value: Any) -> Any:
    """A ``.mat`` attribute variable as a plain Python value (scalar, str or list)."""
    data = np.asarray(value)
    if data.dtype.kind == "U":
        if data.size == 0:
            return ""
        return str(data.ravel()[0]) if data.size == 1 else [str(item) for item in data.ravel()]
    if data.dtype.kind in "biuf":
        return data.ravel()[0].item() if data.size == 1 else data.ravel().tolist()
    return data.tolist()


def _mat_attributes(file: Path, contents: Mapping[str, Any]) -> tuple[dict[str, Any], int]:
    """Decoded record attributes and format version of loaded ``.mat`` variables."""
    prefix = _MAT_ATTRIBUTE_PREFIX
    fmt, version = (
        _mat_value(contents[prefix + name]) if prefix + name in contents else None
        for name in _RESERVED_ATTRIBUTES
    )
    version = _check_format(file, fmt, version)
    attributes: dict[str, Any] = {}
    for name, value in contents.items():
        if not name.startswith(prefix) or name[len(prefix) :] in _RESERVED_ATTRIBUTES:
            continue
        key, decoded = _decode_attribute(file, name[len(prefix) :], _mat_value(value))
        attributes[key] = decoded
    return attributes, version


def _read_mat(file: Path) -> tuple[dict[str, Array], dict[str, Any]]:
    """Arrays (fitted to the record shapes) and decoded attributes of a ``.mat`` run file."""
    contents = _load_mat(file)
    attributes, _ = _mat_attributes(file, contents)
    stored: dict[str, Array] = {}
    for name in RunRecord.ARRAY_NAMES:
        if name not in contents:
            raise InputFileError(f"{file}: not an aaria_pin run file (no array {name!r})")
        try:
            stored[name] = np.asarray(contents[name], dtype=np.float64)
        except (TypeError, ValueError):
            raise InputFileError(
                f"{file}: array {name!r} is not numeric; expected float values"
            ) from None
    shapes = _fit_shapes(file, {name: data.shape for name, data in stored.items()})
    arrays = {name: data.reshape(shapes[name]) for name, data in stored.items()}
    return arrays, attributes


def _summarise_mat(file: Path) -> tuple[dict[str, tuple[int, ...]], dict[str, Any], int]:
    """Stored shapes, decoded attributes and format version of a ``.mat`` run file."""
    from scipy.io import whosmat
    from scipy.io.matlab import MatReadError

    try:
        variables = whosmat(file, appendmat=False)
    except NotImplementedError:
        raise InputFileError(
            f"{file}: is a MATLAB v7.3 file; allowed: MATLAB v5 .mat run files or .h5"
        ) from None
    except (MatReadError, OSError, ValueError, TypeError, EOFError) as exc:
        raise InputFileError(
            f"{file}: cannot be read as a .mat run file ({_reason(exc)})"
        ) from None
    attribute_names = [name for name, _, _ in variables if name.startswith(_MAT_ATTRIBUTE_PREFIX)]
    contents = _load_mat(file, attribute_names) if attribute_names else {}
    attributes, version = _mat_attributes(file, contents)
    shapes = {name: tuple(shape) for name, shape, _ in variables}
    for name in RunRecord.ARRAY_NAMES:
        if name not in shapes:
            raise InputFileError(f"{file}: not an aaria_pin run file (no array {name!r})")
    return shapes, attributes, version
