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


class _Hdf5Stream:
    """An open HDF5 run file whose series are preallocated and filled piece by piece.

    :meth:`open` writes everything but the series' values and the root attributes: the series
    as datasets of the run's full length, ``imu_mount``, the tables, the views (virtual
    datasets over the full-length series), the names and the URDF. :meth:`write` fills rows
    of the series; :meth:`close` writes the root attributes (those of the last piece, which
    cover the whole run) and closes the file.
    """

    def __init__(
        self,
        file: Path,
        first: RunRecord,
        arrays: Mapping[str, Array],
        samples: int,
        compression: str | None = None,
    ) -> None:
        import h5py

        self.samples = samples
        self.handle = h5py.File(file, "w", track_order=True)
        try:
            self._lay_out(first, arrays, samples, compression)
        except BaseException:
            self.handle.close()  # the caller removes the temporary file
            raise

    def _lay_out(
        self,
        first: RunRecord,
        arrays: Mapping[str, Array],
        samples: int,
        compression: str | None,
    ) -> None:
        """Create every dataset of the run at its full length (the rest of ``__init__``)."""
        import h5py

        self.handle.attrs["format"] = RUN_FORMAT
        self.handle.attrs["format_version"] = RUN_FORMAT_VERSION
        strings = h5py.string_dtype("utf-8")
        names = {
            "joint_names": list(first.joint_names),
            "imu_names": list(first.imu_names),
            "imu_parents": [mount.parent for mount in first.imu_mounts],
        }
        shapes: dict[str, tuple[int, ...]] = {}
        self.series: dict[str, Any] = {}
        for name, data in arrays.items():
            if name in SERIES:
                shape = (samples, *data.shape[1:])
                row_bytes = max(1, data[0].nbytes if data.shape[0] else 8)
                chunks = None
                if compression is not None and 0 not in shape:
                    rows = max(1, min(samples, _CHUNK_ROWS, _CHUNK_BYTES // row_bytes))
                    chunks = (rows, *shape[1:])
                dataset = self.handle.create_dataset(
                    name,
                    shape=shape,
                    dtype=np.float64,
                    chunks=chunks,
                    compression=compression if chunks else None,
                    compression_opts=1 if chunks and compression == "gzip" else None,
                    shuffle=chunks is not None,
                )
                self.series[name] = dataset
            else:
                shape = data.shape
                dataset = self.handle.create_dataset(name, data=data)
            shapes[name] = shape
            dataset.attrs["units"] = units_of(name)
        for name, view in first.views.items():
            units = view.units or VIEW_UNITS
            create_virtual_view(self.handle, name, view, shapes, np.float64, units)
        for name, values in names.items():
            self.handle.create_dataset(name, data=np.array(values, dtype=object), dtype=strings)
        self.handle.create_dataset("urdf", data=first.urdf, dtype=strings)

    def write(self, start: int, arrays: Mapping[str, Array]) -> None:
        """Store the series of samples ``start`` … (contiguous float64 arrays by name)."""
        for name, dataset in self.series.items():
            data = arrays[name]
            if data.shape[0]:
                dataset.write_direct(data, dest_sel=np.s_[start : start + data.shape[0]])

    def close(self, attributes: list[tuple[str, Any]] | None) -> None:
        """Write the root attributes (unless None: a failed file) and close the file."""
        try:
            if attributes is not None:
                for key, value in attributes:
                    self.handle.attrs[key] = value
        finally:
            self.handle.close()


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


def _read_hdf5_v2(file: Path, handle: Any, series: bool = True) -> RunRecord:
    """The record of an open version 2 HDF5 run file (without ``series``: no samples)."""
    datasets, names, others = _v2_parts(file, handle)
    samples = int(np.prod(datasets["time"].shape)) if series else 0
    expected = record_shapes(samples, len(names["joint_names"]), len(names["imu_names"]))
    check_names(file, names, expected["imu_mount"][0])
    arrays = {
        name: fitted(file, name, datasets[name][()], shape)
        if series or name not in SERIES
        else np.zeros(shape)
        for name, shape in expected.items()
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
