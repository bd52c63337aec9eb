"""Encoding and decoding of run file attributes, and the run file format check.

"The module docstring" in the docstrings below is that of :mod:`aaria_pin.files.runfile`, which
describes the attribute encoding.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.errors import InputFileError, OutputFileError

RUN_FORMAT = "aaria_pin run"
"""Value of the ``format`` attribute that marks a run file."""

RUN_FORMAT_VERSION = 2
"""Layout version written, and the newest one read (1: the 0.1.0 Aaria layout)."""

JSON_SUFFIX = "_json"
"""Suffix of the name of an attribute stored as a JSON string."""

_RESERVED_ATTRIBUTES = ("format", "format_version")
_INT64 = np.iinfo(np.int64)


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


def _check_format(
    file: Path,
    fmt: Any,
    version: Any,
    expected: str = RUN_FORMAT,
    newest: int = RUN_FORMAT_VERSION,
) -> int:
    """Check the ``format`` marks a file of the expected kind and a known version.

    Args:
        file: the file, for messages
        fmt: its ``format`` attribute
        version: its ``format_version`` attribute
        expected: the ``format`` wanted (an Aaria run file by default)
        newest: the newest version this aaria_pin reads

    Returns:
        The version.
    """
    if isinstance(fmt, bytes):
        fmt = fmt.decode("utf-8", errors="replace")
    if fmt is None:
        raise InputFileError(f"{file}: not an aaria_pin run file (no 'format' attribute)")
    if fmt != expected:
        raise InputFileError(
            f"{file}: not an {expected} file (format is {fmt!r}; expected {expected!r})"
        )
    if isinstance(version, (float, np.floating)) and float(version).is_integer():
        version = int(version)  # MATLAB stores numbers as double unless told otherwise
    if not isinstance(version, (int, np.integer)) or isinstance(version, (bool, np.bool_)):
        raise InputFileError(
            f"{file}: format_version {version!r} is not allowed; expected an integer"
        )
    if not 1 <= int(version) <= newest:
        raise InputFileError(
            f"{file}: format_version {int(version)} is not supported; "
            f"this aaria_pin reads 1 to {newest}"
        )
    return int(version)


def _reason(exc: BaseException) -> str:
    """The first line of an exception's message, or its type name."""
    text = str(exc)
    return text.splitlines()[0] if text else type(exc).__name__
