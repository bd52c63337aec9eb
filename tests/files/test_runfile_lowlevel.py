"""The run file written through h5py's low-level API is the file h5py's high-level API makes.

``_Hdf5Stream`` creates datasets with ``h5d.create``, attributes with ``h5a.create``
(:func:`aaria_pin.files._stored.write_attributes`) and the ``senSen`` view with
``h5p.set_virtual`` (:func:`aaria_pin.files._stored.create_virtual_view`). Here an independent
writer (h5py's ``create_dataset``, ``attrs[...] = ...``, ``VirtualLayout``: the code these
replaced) writes the same record, and the two files are described object by object (types,
dataspaces, creation properties, virtual mappings, attributes with their HDF5 types, values)
and compared.
"""

from __future__ import annotations

import hashlib
import json
import zlib
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest
from h5py import h5a, h5d, h5o, h5s, h5t

from aaria_pin.core.record import SERIES, VIEW_UNITS, RunRecord
from aaria_pin.files._stored import encode_attributes, units_of, view_blocks, write_attributes
from aaria_pin.files.runfile import write_run
from aaria_pin.files.runfile._attributes import RUN_FORMAT, RUN_FORMAT_VERSION
from tests.files.test_runfile import make_record


def reference_write(path: Path, record: RunRecord) -> None:
    """The run file as h5py's high-level API writes it (uncompressed)."""
    strings = h5py.string_dtype("utf-8")
    arrays = {
        name: np.ascontiguousarray(value, dtype=np.float64)
        for name, value in record.arrays().items()
    }
    arrays = {
        name: value if name in (*SERIES, "imu_mount") else np.atleast_2d(value)
        for name, value in arrays.items()
    }
    with h5py.File(path, "w", track_order=True) as handle:
        handle.attrs["format"] = RUN_FORMAT
        handle.attrs["format_version"] = RUN_FORMAT_VERSION
        for name, data in arrays.items():
            handle.create_dataset(name, data=data)
            handle[name].attrs["units"] = units_of(name)
        for name, view in record.views.items():
            lead = (record.n_samples,)
            layout = h5py.VirtualLayout(shape=(*lead, len(view.columns)), dtype=np.float64)
            for first, count, source in view_blocks(view) if record.n_samples else ():
                vsource = h5py.VirtualSource(
                    ".", source.array, shape=arrays[source.array].shape, dtype=np.float64
                )
                if not source.index:
                    layout[:, first] = vsource[:]
                else:
                    *fixed, last = source.index
                    layout[:, first : first + count] = vsource[
                        (slice(None), *fixed, slice(last, last + count))
                    ]
            dataset = handle.create_virtual_dataset(name, layout, fillvalue=0)
            dataset.attrs.create("columns", list(view.columns), dtype=strings)
            dataset.attrs["units"] = view.units or VIEW_UNITS
        lists = {
            "joint_names": list(record.joint_names),
            "imu_names": list(record.imu_names),
            "imu_parents": [mount.parent for mount in record.imu_mounts],
        }
        for name, values in lists.items():
            handle.create_dataset(name, data=np.array(values, dtype=object), dtype=strings)
        handle.create_dataset("urdf", data=record.urdf, dtype=strings)
        for key, value in encode_attributes(path, record.attributes):
            handle.attrs[key] = value
        sums = {  # CRC-32 of each array's values, little-endian float64 in C order
            name: f"crc32:{zlib.crc32(np.ascontiguousarray(data, '<f8').tobytes()):08x}"
            for name, data in arrays.items()
        }
        handle.attrs["checksums"] = json.dumps(sums, sort_keys=True)


def type_of(tid: Any) -> tuple[Any, ...]:
    """An HDF5 datatype as comparable values."""
    kind = tid.get_class()
    out: tuple[Any, ...] = (kind, tid.get_size())
    if kind == h5t.STRING:
        out += (tid.is_variable_str(), tid.get_cset())
    if kind in (h5t.INTEGER, h5t.FLOAT):
        out += (tid.get_order(),)
    if kind == h5t.ENUM:
        out += tuple(tid.get_member_name(i) for i in range(tid.get_nmembers()))
    return out


def space_of(space: Any) -> tuple[Any, ...]:
    """A dataspace (and its selection, if a regular hyperslab) as comparable values."""
    kind = space.get_simple_extent_type()
    if kind != h5s.SIMPLE:
        return (kind,)
    selection = space.get_regular_hyperslab() if space.get_select_type() == 2 else None
    return (kind, space.get_simple_extent_dims(), space.get_simple_extent_dims(True), selection)


def value_of(value: Any) -> Any:
    if isinstance(value, np.ndarray) and value.dtype.kind in "biuf":
        return value.shape, value.dtype.str, hashlib.sha256(value.tobytes()).hexdigest()
    if isinstance(value, np.ndarray):
        return value.shape, value.tolist()
    return value


def describe(path: Path) -> list[tuple[Any, ...]]:
    """Every object of an HDF5 file: name, type, dataspace, creation properties, attributes."""
    lines: list[tuple[Any, ...]] = []

    def attributes(name: str, obj: Any) -> None:
        for key in obj.attrs:
            attribute = h5a.open(obj.id, key.encode())
            lines.append(
                (
                    name,
                    key,
                    type_of(attribute.get_type()),
                    space_of(attribute.get_space()),
                    value_of(obj.attrs[key]),
                )
            )

    with h5py.File(path, "r") as handle:
        attributes("/", handle)
        for name in handle:
            item = handle[name]
            dcpl = item.id.get_create_plist()
            properties: list[Any] = [
                dcpl.get_layout(),
                h5o.get_info(item.id).ctime != 0,  # times stored (the dcpl does not say)
                dcpl.get_attr_creation_order(),
                dcpl.get_fill_time(),
                dcpl.get_alloc_time(),
                dcpl.get_nfilters(),
            ]
            if dcpl.get_layout() == h5d.VIRTUAL:
                fill = np.zeros(1)
                dcpl.get_fill_value(fill)
                properties.append(fill.tolist())
                properties += [
                    (
                        dcpl.get_virtual_filename(i),
                        dcpl.get_virtual_dsetname(i),
                        space_of(dcpl.get_virtual_vspace(i)),
                        space_of(dcpl.get_virtual_srcspace(i)),
                    )
                    for i in range(dcpl.get_virtual_count())
                ]
            lines.append(
                (
                    name,
                    type_of(item.id.get_type()),
                    space_of(item.id.get_space()),
                    tuple(properties),
                    value_of(item[()]),
                )
            )
            attributes(name, item)
    return lines


@pytest.mark.parametrize(
    "options",
    [
        {},
        {"imus": 3, "views": False},
        {"samples": 0},
        {"imus": 0, "views": False, "tables": False},
    ],
    ids=["aaria", "three-imus", "no-samples", "no-imu"],
)
def test_low_level_run_file_is_h5py_high_level_file(tmp_path: Path, options: dict) -> None:
    record = make_record(**options)
    written = write_run(tmp_path / "run.h5", record)
    reference_write(tmp_path / "reference.h5", record)
    assert describe(written) == describe(tmp_path / "reference.h5")


def test_write_attributes_makes_h5py_attributes(tmp_path: Path) -> None:
    values: dict[str, Any] = {
        "text": "abc é",
        "flag": True,
        "numpy_flag": np.bool_(False),
        "count": 7,
        "big": np.int64(-(2**62)),
        "real": 2.5,
        "single": np.float32(1.5),
        "ints": np.array([1, 2, 3], dtype=np.int64),
        "reals": np.array([[0.5, 1.0]]),
        "names": np.array(["a", "bé"], dtype=h5py.string_dtype("utf-8")),
        "ascii_dtype_names": np.array(["a", "b"], dtype=h5py.string_dtype("ascii")),
        "empty": np.zeros(0),
        "ümlaut name": "x",
        "a list": [1.0, 2.0],
        "again": 1,
    }
    with h5py.File(tmp_path / "low.h5", "w", track_order=True) as low:
        write_attributes(low, values.items())
        write_attributes(low.id, [("again", "replaced")])
        dataset = low.create_dataset("d", data=np.zeros(2))
        write_attributes(dataset.id, [("units", "m")])
    with h5py.File(tmp_path / "high.h5", "w", track_order=True) as high:
        for key, value in values.items():
            high.attrs[key] = value
        high.attrs["again"] = "replaced"
        high.create_dataset("d", data=np.zeros(2)).attrs["units"] = "m"
    assert describe(tmp_path / "low.h5") == describe(tmp_path / "high.h5")
