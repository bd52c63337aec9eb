"""Writing, reading and summarising the MATLAB v5 ``.mat`` layout of a run file (scipy).

scipy is imported inside the functions, so importing this module stays light. "The module
docstring" in the docstrings below is that of :mod:`aaria_pin.files.runfile`, which describes the
layout.
"""

from __future__ import annotations

import contextlib
import re
from collections.abc import Container, Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.record import SERIES, ColumnView, RunRecord, record_shapes
from aaria_pin.core.se3 import Array
from aaria_pin.errors import InputFileError, OutputFileError
from aaria_pin.files._stored import (
    NAME_LISTS,
    STORED_NAMES,
    damaged_file,
    decode_attribute,
    first_line,
)
from aaria_pin.files.runfile._attributes import (
    _RESERVED_ATTRIBUTES,
    NOT_RECORD_ATTRIBUTES,
    RUN_FORMAT,
    RUN_FORMAT_VERSION,
)
from aaria_pin.files.runfile._columns import (
    COLUMNS_SUFFIX,
    check_names,
    fitted,
    numeric,
    read_view,
    record_from_arrays,
)

MAT_ATTRIBUTE_PREFIX = "attr_"
_MAT_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]{0,62}")
_MAT_MAX_ARRAY_BYTES = 2**31 - 1


def mat_attribute_variables(
    final: Path, attributes: list[tuple[str, Any]]
) -> list[tuple[str, Any]]:
    """The ``attr_`` variables of encoded attributes, the format marks first.

    Raises:
        OutputFileError: an attribute whose ``attr_<name>`` is not a MATLAB variable name.
    """
    for key, _ in attributes:
        if not _MAT_NAME.fullmatch(MAT_ATTRIBUTE_PREFIX + key):
            raise OutputFileError(
                f"{final}: attribute {key!r} cannot be a MATLAB variable "
                f"{MAT_ATTRIBUTE_PREFIX}{key}; allowed: letters, digits and _, at most "
                f"{63 - len(MAT_ATTRIBUTE_PREFIX)} characters",
                parameter="attributes",
            )
    return [
        (MAT_ATTRIBUTE_PREFIX + "format", RUN_FORMAT),
        (MAT_ATTRIBUTE_PREFIX + "format_version", np.int64(RUN_FORMAT_VERSION)),
        *((MAT_ATTRIBUTE_PREFIX + key, value) for key, value in attributes),
    ]


def _mat_contents(
    final: Path,
    record: RunRecord,
    arrays: Mapping[str, Array],
    attributes: list[tuple[str, Any]],
) -> dict[str, Any]:
    """The variables of the ``.mat`` layout; OutputFileError for what v5 cannot hold."""
    variables = mat_attribute_variables(final, attributes)
    contents: dict[str, Any] = dict(arrays)
    for name, view in record.views.items():
        contents[name] = view.materialise(arrays)
        contents[name + COLUMNS_SUFFIX] = _cell(view.columns)
    contents["joint_names"] = _cell(record.joint_names)
    contents["imu_names"] = _cell(record.imu_names)
    contents["imu_parents"] = _cell(mount.parent for mount in record.imu_mounts)
    contents["urdf"] = record.urdf
    for name, data in contents.items():
        if isinstance(data, np.ndarray) and data.nbytes > _MAT_MAX_ARRAY_BYTES:
            raise OutputFileError(
                f"{final}: array {name!r} is {data.nbytes / 2**30:.1f} GiB; a .mat v5 file "
                "holds at most 2 GiB per array, write it as v7.3 (mat_version='7.3') or .h5",
                parameter="record",
            )
    contents.update(variables)
    return contents


def _cell(values: Any) -> Array:
    """Strings as a MATLAB 1 × n cell array."""
    items = list(values)
    cell = np.empty(len(items), dtype=object)
    cell[:] = items
    return cell


def _write_mat(file: Path, contents: Mapping[str, Any]) -> None:
    """Write the ``.mat`` variables (see the module docstring)."""
    from scipy.io import savemat

    savemat(file, dict(contents), appendmat=False, format="5", do_compression=True, oned_as="row")


@contextlib.contextmanager
def _mat_errors(file: Path, damaged: bool = False) -> Iterator[None]:
    """Turn scipy's errors on reading ``file`` into one-line :class:`InputFileError`.

    Args:
        file: the file read
        damaged: whether its variables were listed already (an error reading them is
            damage: "FILE is damaged (...)"), else it "cannot be read as a .mat run file"
    """
    import zlib

    from scipy.io.matlab import MatReadError

    try:
        yield
    except NotImplementedError:
        raise InputFileError(
            f"{file}: is a MATLAB v7.3 file; allowed: MATLAB v5 .mat run files or .h5",
            parameter="file",
        ) from None
    except InputFileError:
        raise
    except (MatReadError, OSError, ValueError, TypeError, EOFError, IndexError, zlib.error) as exc:
        if damaged:
            raise damaged_file(file, first_line(exc)) from None
        raise InputFileError(
            f"{file}: cannot be read as a .mat run file ({first_line(exc)})", parameter="file"
        ) from None


def load_mat(file: Path, names: list[str] | None = None) -> dict[str, Any]:
    """Variables of a MATLAB v5 or v7.3 file, unsqueezed, in MATLAB's own classes.

    A v7.3 file (HDF5) is read by :func:`~aaria_pin.files.runfile._mat73.load_mat73` into
    the same forms as scipy gives a v5 file's variables.
    """
    from aaria_pin.files.detection import is_mat73
    from aaria_pin.files.runfile._mat73 import load_mat73

    if is_mat73(file):
        return load_mat73(file, names)
    from scipy.io import loadmat

    with _mat_errors(file, damaged=True):
        return loadmat(
            file, appendmat=False, squeeze_me=False, mat_dtype=True, variable_names=names
        )


def mat_variables(file: Path) -> dict[str, tuple[int, ...]]:
    """The names and shapes of a MATLAB v5 or v7.3 file's variables, without reading them.

    Raises:
        InputFileError: not a MAT-file, or a MAT-file v5 whose variables do not end where
            the file does ("FILE is damaged (...)": truncated, or a variable's size broken).
    """
    from aaria_pin.files.detection import is_mat73
    from aaria_pin.files.runfile._mat73 import mat73_variables

    if is_mat73(file):
        return mat73_variables(file)
    from scipy.io import whosmat

    damaged = _mat5_end(file)
    with _mat_errors(file, damaged=damaged is not None):
        variables = {name: tuple(shape) for name, shape, _ in whosmat(file, appendmat=False)}
    if damaged is not None and damaged != file.stat().st_size:
        reason = f"its variables end at byte {damaged}, the file at byte {file.stat().st_size}"
        raise damaged_file(file, reason)
    return variables


_MAT5_HEADER = b"MATLAB 5.0 MAT-file"
_MI_MATRIX = 14
"""The data type of an uncompressed MAT-file v5 variable (padded to 8 bytes)."""


def _mat5_end(file: Path) -> int | None:
    """Where a MAT-file v5's last variable ends, from the tags (None: not a v5 file).

    Each variable is a tag (data type, byte count: two uint32) and its bytes, one after the
    other from byte 128; a whole file ends where its last variable does, a truncated one
    before it.
    """
    import struct

    try:
        size = file.stat().st_size
        with file.open("rb") as stream:
            header = stream.read(128)
            if len(header) < 128 or not header.startswith(_MAT5_HEADER):
                return None
            order = "<" if header[126:128] == b"IM" else ">"
            offset = 128
            while offset < size:
                stream.seek(offset)
                tag = stream.read(8)
                if len(tag) < 8:
                    return offset + len(tag) + 1  # past the end: a cut tag
                kind, count = struct.unpack(order + "II", tag)
                offset += 8 + (0 if kind >> 16 else count)
                if kind == _MI_MATRIX:
                    offset += -offset % 8
            return offset
    except OSError:
        return None


def mat_value(value: Any) -> Any:
    """A ``.mat`` attribute variable as a plain Python value (scalar, str or list)."""
    data = np.asarray(value)
    if data.dtype.kind == "U":
        if data.size == 0:
            return ""
        return str(data.ravel()[0]) if data.size == 1 else [str(item) for item in data.ravel()]
    if data.dtype.kind in "biuf":
        return data.ravel()[0].item() if data.size == 1 else data.ravel().tolist()
    return data.tolist()


def mat_strings(value: Any) -> list[str]:
    """A cell array (or char matrix) of strings as a list of str, in column order."""
    data = np.asarray(value)
    if data.dtype.kind == "U":
        return [str(item) for item in data.ravel()] if data.ndim > 1 else [mat_value(data)]
    return [str(mat_value(item)) for item in data.ravel(order="F")]


def mat_format(contents: Mapping[str, Any]) -> tuple[Any, Any]:
    """The stored ``format`` and ``format_version`` of loaded ``.mat`` variables (None: absent)."""
    prefix = MAT_ATTRIBUTE_PREFIX
    fmt, version = (
        mat_value(contents[prefix + name]) if prefix + name in contents else None
        for name in _RESERVED_ATTRIBUTES
    )
    return fmt, version


def mat_attributes(file: Path, contents: Mapping[str, Any]) -> dict[str, Any]:
    """Decoded record attributes of loaded ``.mat`` variables (``attr_<name>``)."""
    prefix = MAT_ATTRIBUTE_PREFIX
    attributes: dict[str, Any] = {}
    for name, value in contents.items():
        if not name.startswith(prefix) or name[len(prefix) :] in NOT_RECORD_ATTRIBUTES:
            continue
        key, decoded = decode_attribute(file, name[len(prefix) :], mat_value(value))
        attributes[key] = decoded
    return attributes


def _mat_names(
    file: Path, contents: Mapping[str, Any], present: Container[str]
) -> dict[str, list[str]]:
    """The string lists of a version 2 ``.mat`` file; InputFileError if a variable is missing."""
    for name in STORED_NAMES:
        if name not in present:
            raise InputFileError(
                f"{file}: not an aaria_pin run file (no array {name!r})", parameter="file"
            )
    return {name: mat_strings(contents[name]) for name in NAME_LISTS}


def _read_mat_v2(
    file: Path, contents: Mapping[str, Any], present: Container[str] | None = None
) -> RunRecord:
    """The record of loaded version 2 ``.mat`` variables.

    Args:
        file: the file, for messages
        contents: its variables (a view's data may be left out or None: only its column
            names are read)
        present: the file's variable names, when ``contents`` leaves out the series: the
            record then has no samples (what re-making the run needs, :func:`read_run_inputs`)
    """
    names = _mat_names(file, contents, contents if present is None else present)
    samples = int(np.size(contents["time"])) if "time" in contents else 0
    expected = record_shapes(samples, len(names["joint_names"]), len(names["imu_names"]))
    check_names(file, names, expected["imu_mount"][0])
    arrays = {
        name: fitted(file, name, contents[name], shape) if name in contents else np.zeros(shape)
        for name, shape in expected.items()
    }
    record_names = (names["joint_names"], names["imu_names"])
    views: dict[str, ColumnView] = {}
    tables: dict[str, Array] = {}
    for name, value in contents.items():
        if name.startswith("__") or name in STORED_NAMES or name.startswith(MAT_ATTRIBUTE_PREFIX):
            continue
        if name + COLUMNS_SUFFIX in contents:
            views[name] = read_view(
                file, name, mat_strings(contents[name + COLUMNS_SUFFIX]), record_names
            )
        elif not (name.endswith(COLUMNS_SUFFIX) and name[: -len(COLUMNS_SUFFIX)] in contents):
            data = np.asarray(value)
            if data.dtype.kind in "biuf":
                tables[name] = numeric(file, name, data)
    return record_from_arrays(
        file,
        arrays,
        names,
        urdf=str(mat_value(contents["urdf"])),
        tables=tables,
        views=views,
        attributes=mat_attributes(file, contents),
    )


def _summarise_mat_v2(
    file: Path, variables: Mapping[str, tuple[int, ...]], contents: Mapping[str, Any]
) -> dict[str, Any]:
    """Names, shapes and attributes of a version 2 ``.mat`` file (small variables loaded)."""
    names = _mat_names(file, contents, variables)
    samples = int(np.prod(variables["time"]))
    expected = record_shapes(samples, len(names["joint_names"]), len(names["imu_names"]))
    arrays: dict[str, tuple[int, ...]] = dict(expected)
    views: dict[str, tuple[int, ...]] = {}
    for name, shape in variables.items():
        if name in STORED_NAMES or name.startswith(MAT_ATTRIBUTE_PREFIX):
            continue
        if name + COLUMNS_SUFFIX in variables:
            views[name] = (samples, int(np.prod(variables[name + COLUMNS_SUFFIX])))
        elif not (name.endswith(COLUMNS_SUFFIX) and name[: -len(COLUMNS_SUFFIX)] in variables):
            arrays[name] = shape
    return {
        "joints": names["joint_names"],
        "imus": names["imu_names"],
        "arrays": {
            name: arrays[name] for name in (*SERIES, "imu_mount", *arrays) if name in arrays
        },
        "views": views,
        "attributes": mat_attributes(file, contents),
    }
