"""Writing, reading and summarising the MATLAB v5 ``.mat`` layout of a run file (scipy).

scipy is imported inside the functions, so importing this module stays light. "The module
docstring" in the docstrings below is that of :mod:`aaria_pin.files.runfile`, which describes the
layout.
"""

from __future__ import annotations

import contextlib
import re
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.aaria.sensen import SENSEN_COLUMNS, RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.errors import InputFileError, OutputFileError
from aaria_pin.files.runfile._attributes import (
    _RESERVED_ATTRIBUTES,
    RUN_FORMAT,
    RUN_FORMAT_VERSION,
    _check_format,
    _decode_attribute,
    _reason,
)
from aaria_pin.files.runfile._shapes import _fit_shapes

_MAT_ATTRIBUTE_PREFIX = "attr_"
_MAT_COLUMNS_NAME = "senSen_columns"
_MAT_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]{0,62}")
_MAT_MAX_ARRAY_BYTES = 2**31 - 1


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


@contextlib.contextmanager
def _mat_errors(file: Path, read_error: type[Exception]) -> Iterator[None]:
    """Turn scipy's errors on reading ``file`` into one-line :class:`InputFileError`."""
    try:
        yield
    except NotImplementedError:
        raise InputFileError(
            f"{file}: is a MATLAB v7.3 file; allowed: MATLAB v5 .mat run files or .h5"
        ) from None
    except (read_error, OSError, ValueError, TypeError, EOFError) as exc:
        raise InputFileError(
            f"{file}: cannot be read as a .mat run file ({_reason(exc)})"
        ) from None


def _load_mat(file: Path, names: list[str] | None = None) -> dict[str, Any]:
    """Variables of a MATLAB v5 file, unsqueezed, in MATLAB's own classes."""
    from scipy.io import loadmat
    from scipy.io.matlab import MatReadError

    with _mat_errors(file, MatReadError):
        return loadmat(
            file, appendmat=False, squeeze_me=False, mat_dtype=True, variable_names=names
        )


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

    with _mat_errors(file, MatReadError):
        variables = whosmat(file, appendmat=False)
    attribute_names = [name for name, _, _ in variables if name.startswith(_MAT_ATTRIBUTE_PREFIX)]
    contents = _load_mat(file, attribute_names) if attribute_names else {}
    attributes, version = _mat_attributes(file, contents)
    shapes = {name: tuple(shape) for name, shape, _ in variables}
    for name in RunRecord.ARRAY_NAMES:
        if name not in shapes:
            raise InputFileError(f"{file}: not an aaria_pin run file (no array {name!r})")
    return shapes, attributes, version
