"""Writing, reading and summarising the HDF5 layout of a run file (through h5py).

h5py is imported inside the functions, so importing this module stays light. "The module
docstring" in the docstrings below is that of :mod:`aaria_pin.files.runfile`, which describes the
layout.
"""

from __future__ import annotations

import contextlib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.record import SERIES, VIEW_UNITS, ColumnView, RunRecord, record_shapes
from aaria_pin.core.se3 import Array
from aaria_pin.errors import InputFileError
from aaria_pin.files._space import close_hdf5
from aaria_pin.files._stored import (
    NAME_LISTS,
    STORED_NAMES,
    create_virtual_view,
    decode_attribute,
    read_errors,
    units_of,
    write_attributes,
)
from aaria_pin.files.runfile._attributes import (
    NOT_RECORD_ATTRIBUTES,
    RUN_FORMAT,
    RUN_FORMAT_VERSION,
)
from aaria_pin.files.runfile._columns import (
    RunStream,
    check_names,
    chunk_rows,
    fitted,
    numeric,
    read_view,
    record_from_arrays,
)


class _Hdf5Stream(RunStream):
    """An open HDF5 run file whose series are preallocated and filled piece by piece.

    :meth:`open` writes everything but the series' values and the root attributes: the series
    as datasets of the run's full length, ``imu_mount``, the tables, the views (virtual
    datasets over the full-length series), the names and the URDF. :meth:`write` fills rows
    of the series; :meth:`close` writes the root attributes (those of the last piece, which
    cover the whole run) and closes the file.
    """

    def _open(self, file: Path) -> Any:
        """The open h5py file, links in creation order."""
        import h5py

        return h5py.File(file, "w", track_order=True)

    def _lay_out(
        self,
        first: RunRecord,
        arrays: Mapping[str, Array],
        samples: int,
        compression: str | None,
    ) -> None:
        """Create every dataset of the run at its full length (the rest of ``__init__``).

        The uncompressed datasets, the names and the URDF are created through h5py's low-level
        API with one dataset-creation property list (:func:`_new_dataset`); the file is the
        one ``create_dataset`` makes (the same types, layouts, creation properties and
        attributes; ``tests/files/test_runfile_lowlevel.py`` compares them), without h5py's
        argument handling per dataset (``make_new_dset``: 72 µs a dataset against 34 µs here,
        measured on a busy machine; 17 datasets a run file). With the attributes
        (:func:`~aaria_pin.files._stored.write_attributes`) and the view
        (:func:`~aaria_pin.files._stored.create_virtual_view`) also low-level, laying out a
        10,000-sample run file takes 2.4 ms of CPU instead of 5.0 ms, and the whole write 6.3 ms
        instead of 10.5 ms (``aaria-fig2``, 2 cores). Compressed series (chunked, filtered) still
        go through ``create_dataset``.
        """
        import h5py
        from h5py import h5p

        root = self.handle.id
        write_attributes(root, [("format", RUN_FORMAT), ("format_version", RUN_FORMAT_VERSION)])
        strings = h5py.string_dtype("utf-8")
        names = {
            "joint_names": list(first.joint_names),
            "imu_names": list(first.imu_names),
            "imu_parents": [mount.parent for mount in first.imu_mounts],
        }
        # h5py's create_dataset: no timestamps, attribute order untracked (its defaults)
        dcpl = h5p.create(h5p.DATASET_CREATE)
        dcpl.set_obj_track_times(False)
        dcpl.set_attr_creation_order(0)
        shapes: dict[str, tuple[int, ...]] = {}
        self.series: dict[str, Any] = {}
        for name, data in arrays.items():
            if name in SERIES:
                shape = (samples, *data.shape[1:])
                if compression is None or 0 in shape:
                    dataset = _new_dataset(root, name, np.dtype(np.float64), shape, dcpl)
                else:
                    row_bytes = max(1, data[0].nbytes if data.shape[0] else 8)
                    rows = chunk_rows(samples, row_bytes)
                    dataset = self.handle.create_dataset(
                        name,
                        shape=shape,
                        dtype=np.float64,
                        chunks=(rows, *shape[1:]),
                        compression=compression,
                        compression_opts=1 if compression == "gzip" else None,
                        shuffle=True,
                    ).id
                self.series[name] = dataset
            else:
                shape = data.shape
                dataset = _new_dataset(root, name, data.dtype, shape, dcpl, data)
            shapes[name] = shape
            write_attributes(dataset, [("units", units_of(name))])
        for name, view in first.views.items():
            units = view.units or VIEW_UNITS
            create_virtual_view(self.handle, name, view, shapes, np.float64, units)
        for name, values in names.items():
            _new_dataset(root, name, strings, (len(values),), dcpl, np.array(values, strings))
        _new_dataset(root, "urdf", strings, (), dcpl, np.array(first.urdf, strings))

    def write(self, start: int, arrays: Mapping[str, Array]) -> None:
        """Store the series of samples ``start`` … (contiguous float64 arrays by name).

        Straight from the caller's arrays through the low-level ``DatasetID.write`` (a piece
        that fills a dataset with ``h5s.ALL``, else a hyperslab of the file's dataspace): no
        copy, and none of ``write_direct``'s selection objects (the 12 MB of a 10,000-sample
        run: 2.7 ms of CPU against 3.6 ms through ``write_direct``; writing them with one
        ``os.pwrite`` takes about 2 ms on this machine).
        """
        from h5py import h5s

        for name, dataset in self.series.items():
            data = arrays[name]
            rows = data.shape[0]
            if not rows:
                continue
            if start == 0 and rows == self.samples:
                dataset.write(h5s.ALL, h5s.ALL, data)
                continue
            stored = dataset.get_space()
            stored.select_hyperslab((start, *(0 for _ in data.shape[1:])), data.shape)
            dataset.write(h5s.create_simple(data.shape), stored, data)

    def close(self, attributes: list[tuple[str, Any]] | None) -> None:
        """Write the root attributes (unless None: a failed file) and close the file.

        Through :func:`~aaria_pin.files._space.close_hdf5` (flushed, then closed; a failed file
        emptied first), so a full device never leaves HDF5 identifiers to crash the process.
        """
        try:
            if attributes is not None:
                write_attributes(self.handle.id, attributes)
        except BaseException:
            close_hdf5(self.handle, failed=True)
            raise
        close_hdf5(self.handle, failed=attributes is None)


def _new_dataset(
    parent: Any,
    name: str,
    dtype: Any,
    shape: tuple[int, ...],
    dcpl: Any,
    data: Array | None = None,
) -> Any:
    """A new dataset (low-level ``DatasetID``) as h5py's ``create_dataset`` makes it.

    Args:
        parent: the low-level identifier of the group (or file) it goes in
        name: its name
        dtype: its numpy dtype (h5py's string dtype for strings)
        shape: its shape (``()``: a scalar)
        dcpl: the dataset-creation property list
        data: its values (an array of ``dtype`` and ``shape``), or None to write later
    """
    from h5py import h5d, h5s, h5t

    dataset = h5d.create(
        parent,
        name.encode("utf-8"),
        h5t.py_create(dtype, logical=True),
        h5s.create_simple(shape),
        dcpl=dcpl,
    )
    if data is not None and data.size:
        dataset.write(h5s.ALL, h5s.ALL, data)
    return dataset


def _hdf5_errors(file: Path) -> contextlib.AbstractContextManager[None]:
    """Turn h5py's errors on reading ``file`` into one-line :class:`InputFileError`."""
    return read_errors(file, "an HDF5 run file")


def _strings(item: Any) -> list[str]:
    """A string dataset or attribute value as a list of str."""
    values = np.atleast_1d(item[()] if hasattr(item, "shape") and hasattr(item, "dtype") else item)
    return [v.decode("utf-8") if isinstance(v, bytes) else str(v) for v in values]


def _hdf5_attributes(file: Path, attrs: Any) -> dict[str, Any]:
    """The record attributes of an HDF5 root group, decoded."""
    attributes: dict[str, Any] = {}
    for name in attrs:
        if name not in NOT_RECORD_ATTRIBUTES:
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
            raise InputFileError(
                f"{file}: not an aaria_pin run file (no dataset {name!r})", parameter="file"
            )
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
            tables[name] = numeric(file, name, item[()])
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
