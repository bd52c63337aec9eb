"""Array shapes of the run file layout, shared by the HDF5 and ``.mat`` formats.

The layout is described in the docstring of :mod:`aaria_pin.files.runfile`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from aaria_pin.aaria.sensen import N_SENSEN_COLUMNS, RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.errors import InputFileError, OutputFileError

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
