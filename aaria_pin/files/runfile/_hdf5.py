"""Writing, reading and summarising the HDF5 layout of a run file (through h5py).

h5py is imported inside the functions, so importing this module stays light. "The module
docstring" in the docstrings below is that of :mod:`aaria_pin.files.runfile`, which describes the
layout.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.aaria.sensen import SENSEN_COLUMNS, RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.errors import InputFileError
from aaria_pin.files.runfile._attributes import (
    _RESERVED_ATTRIBUTES,
    RUN_FORMAT,
    RUN_FORMAT_VERSION,
    _check_format,
    _decode_attribute,
    _reason,
)
from aaria_pin.files.runfile._shapes import _ROW_SHAPES, _fit_shapes

_CHUNK_ROWS = 4096
_CHUNK_BYTES = 2**20

_UNITS = {
    "senSen": "see columns: s, rad or m, rad/s, m/s^2",
    "senSenDH": "columns: alpha rad, a m, theta rad, d m, "
    "link type (0 empty, 1 revolute, 2 prismatic)",
    "senSenJ": "columns: amplitude rad, prismatic amplitude m, bias rad or m, frequency rad/s, "
    "phase rad",
    "senSenB": "columns: amplitude m or rad, bias m or rad, frequency rad/s, phase rad",
    "q": "rad or m",
    "qd": "rad/s or m/s",
    "qdd": "rad/s^2 or m/s^2",
    "tau": "N*m or N",
    "base_wrench": "N, N*m",
    "tool_pose": "m",
    "imu_mount": "m",
}


def _write_hdf5(
    file: Path,
    arrays: Mapping[str, Array],
    attributes: list[tuple[str, Any]],
    compression: str | None = None,
) -> None:
    """Write the HDF5 layout (see the module docstring)."""
    import h5py

    with h5py.File(file, "w", track_order=True) as handle:
        handle.attrs["format"] = RUN_FORMAT
        handle.attrs["format_version"] = RUN_FORMAT_VERSION
        for key, value in attributes:
            handle.attrs[key] = value
        for name, data in arrays.items():
            if compression is not None and name in _ROW_SHAPES and data.shape[0] > 0:
                row_bytes = data[0].nbytes
                rows = max(1, min(data.shape[0], _CHUNK_ROWS, _CHUNK_BYTES // row_bytes))
                dataset = handle.create_dataset(
                    name,
                    data=data,
                    chunks=(rows, *data.shape[1:]),
                    compression=compression,
                    compression_opts=1 if compression == "gzip" else None,
                    shuffle=True,
                )
            else:
                dataset = handle.create_dataset(name, data=data)
            dataset.attrs["units"] = _UNITS[name]
        handle["senSen"].attrs.create(
            "columns", list(SENSEN_COLUMNS), dtype=h5py.string_dtype("utf-8")
        )


@contextlib.contextmanager
def _hdf5_errors(file: Path) -> Iterator[None]:
    """Turn h5py's errors on reading ``file`` into one-line :class:`InputFileError`."""
    try:
        yield
    except InputFileError:
        raise
    except (OSError, ValueError, TypeError, KeyError) as exc:
        raise InputFileError(
            f"{file}: cannot be read as an HDF5 run file ({_reason(exc)})"
        ) from None


def _read_hdf5(file: Path) -> tuple[dict[str, Array], dict[str, Any]]:
    """Arrays (fitted to the record shapes) and decoded attributes of an HDF5 run file."""
    import h5py

    with _hdf5_errors(file), h5py.File(file, "r") as handle:
        _check_format(file, handle.attrs.get("format"), handle.attrs.get("format_version"))
        datasets = _hdf5_datasets(file, handle, h5py.Dataset)
        shapes = _fit_shapes(file, {name: item.shape for name, item in datasets.items()})
        arrays = {
            name: np.asarray(item[()], dtype=np.float64).reshape(shapes[name])
            for name, item in datasets.items()
        }
        attributes = _hdf5_attributes(file, handle.attrs)
    return arrays, attributes


def _summarise_hdf5(file: Path) -> tuple[dict[str, tuple[int, ...]], dict[str, Any], int]:
    """Stored shapes, decoded attributes and format version of an HDF5 run file."""
    import h5py

    with _hdf5_errors(file), h5py.File(file, "r") as handle:
        version = _check_format(
            file, handle.attrs.get("format"), handle.attrs.get("format_version")
        )
        datasets = _hdf5_datasets(file, handle, h5py.Dataset)
        shapes = {name: tuple(item.shape) for name, item in datasets.items()}
        attributes = _hdf5_attributes(file, handle.attrs)
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
