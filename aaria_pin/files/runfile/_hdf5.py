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

from aaria_pin.core.record import SERIES, VIEW_UNITS, ColumnView, RunRecord, record_shapes
from aaria_pin.core.se3 import Array
from aaria_pin.errors import InputFileError
from aaria_pin.files._stored import (
    NAME_LISTS,
    STORED_NAMES,
    create_virtual_view,
    decode_attribute,
    first_line,
    units_of,
)
from aaria_pin.files.runfile._attributes import (
    _RESERVED_ATTRIBUTES,
    RUN_FORMAT,
    RUN_FORMAT_VERSION,
)
from aaria_pin.files.runfile._layout import (
    check_names,
    fitted,
    read_view,
    record_from_arrays,
)

_CHUNK_ROWS = 4096
_CHUNK_BYTES = 2**20


def _write_hdf5(
    file: Path,
    record: RunRecord,
    arrays: Mapping[str, Array],
    attributes: list[tuple[str, Any]],
    compression: str | None = None,
) -> None:
    """Write the HDF5 layout (see the module docstring)."""
    import h5py

    strings = h5py.string_dtype("utf-8")
    names = {
        "joint_names": list(record.joint_names),
        "imu_names": list(record.imu_names),
        "imu_parents": [mount.parent for mount in record.imu_mounts],
    }
    with h5py.File(file, "w", track_order=True) as handle:
        handle.attrs["format"] = RUN_FORMAT
        handle.attrs["format_version"] = RUN_FORMAT_VERSION
        for key, value in attributes:
            handle.attrs[key] = value
        for name, data in arrays.items():
            if compression is not None and name in SERIES and data.size > 0:
                row_bytes = max(1, data[0].nbytes)
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
            dataset.attrs["units"] = units_of(name)
        shapes = {name: data.shape for name, data in arrays.items()}
        for name, view in record.views.items():
            units = view.units or VIEW_UNITS
            create_virtual_view(handle, name, view, shapes, np.float64, units)
        for name, values in names.items():
            handle.create_dataset(name, data=np.array(values, dtype=object), dtype=strings)
        handle.create_dataset("urdf", data=record.urdf, dtype=strings)


@contextlib.contextmanager
def _hdf5_errors(file: Path) -> Iterator[None]:
    """Turn h5py's errors on reading ``file`` into one-line :class:`InputFileError`."""
    try:
        yield
    except InputFileError:
        raise
    except (OSError, ValueError, TypeError, KeyError) as exc:
        raise InputFileError(
            f"{file}: cannot be read as an HDF5 run file ({first_line(exc)})"
        ) from None


def _strings(item: Any) -> list[str]:
    """A string dataset or attribute value as a list of str."""
    values = np.atleast_1d(item[()] if hasattr(item, "shape") and hasattr(item, "dtype") else item)
    return [v.decode("utf-8") if isinstance(v, bytes) else str(v) for v in values]


def _hdf5_attributes(file: Path, attrs: Any) -> dict[str, Any]:
    """The record attributes of an HDF5 root group, decoded."""
    attributes: dict[str, Any] = {}
    for name in attrs:
        if name not in _RESERVED_ATTRIBUTES:
            key, value = decode_attribute(file, name, attrs[name])
            attributes[key] = value
    return attributes


def _v2_parts(
    file: Path, handle: Any
) -> tuple[dict[str, Any], dict[str, list[str]], dict[str, Any]]:
    """The datasets of a version 2 file: the fixed arrays, the names and the others by name."""
    import h5py

    datasets: dict[str, Any] = {}
    for name in STORED_NAMES:
        item = handle.get(name)
        if not isinstance(item, h5py.Dataset):
            raise InputFileError(f"{file}: not an aaria_pin run file (no dataset {name!r})")
        datasets[name] = item
    names = {name: _strings(datasets[name]) for name in NAME_LISTS}
    others = {
        name: item
        for name, item in handle.items()
        if name not in STORED_NAMES and isinstance(item, h5py.Dataset)
    }
    return datasets, names, others


def _read_hdf5_v2(file: Path, handle: Any) -> RunRecord:
    """The record of an open version 2 HDF5 run file."""
    datasets, names, others = _v2_parts(file, handle)
    samples = int(np.prod(datasets["time"].shape))
    expected = record_shapes(samples, len(names["joint_names"]), len(names["imu_names"]))
    check_names(file, names, expected["imu_mount"][0])
    arrays = {
        name: fitted(file, name, datasets[name][()], shape) for name, shape in expected.items()
    }
    tables: dict[str, Array] = {}
    views: dict[str, ColumnView] = {}
    for name, item in others.items():
        if "columns" in item.attrs:
            view = read_view(
                file,
                name,
                _strings(item.attrs["columns"]),
                (names["joint_names"], names["imu_names"]),
            )
            units = item.attrs.get("units", VIEW_UNITS)
            views[name] = ColumnView(
                view.columns, view.sources, units.decode() if isinstance(units, bytes) else units
            )
        elif item.dtype.kind in "biuf":
            tables[name] = np.asarray(item[()], dtype=np.float64)
    return record_from_arrays(
        file,
        arrays,
        names,
        urdf=datasets["urdf"].asstr()[()],
        tables=tables,
        views=views,
        attributes=_hdf5_attributes(file, handle.attrs),
    )


def _summarise_hdf5_v2(file: Path, handle: Any) -> dict[str, Any]:
    """Names, shapes and attributes of an open version 2 HDF5 run file, arrays unread."""
    datasets, names, others = _v2_parts(file, handle)
    arrays = {name: tuple(datasets[name].shape) for name in (*SERIES, "imu_mount")}
    views: dict[str, tuple[int, ...]] = {}
    for name, item in others.items():
        if "columns" in item.attrs:
            views[name] = tuple(item.shape)
        elif item.dtype.kind in "biuf":
            arrays[name] = tuple(item.shape)
    return {
        "joints": names["joint_names"],
        "imus": names["imu_names"],
        "arrays": arrays,
        "views": views,
        "attributes": _hdf5_attributes(file, handle.attrs),
    }
