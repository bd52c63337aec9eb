"""The fixed per-run layout of a data set (format version 2) and the encoding of one run.

Every run of a data set has the same layout: the same joints, IMUs, input tables and column
views, so the file holds each per-run array once with a leading run axis (N × …) and the names,
the URDF text and the views once per file. A :class:`DatasetLayout` is that fixed part; the data
set's spec makes it, the writer lays the file out from it and the reader reads it back.

Chunks: one run per chunk, so a run is written (HDF5's direct chunk write) and read on its own;
a pose series (``base_pose``, ``tool_pose``: T × 4 × 4 per run) is split into one chunk per
matrix entry (chunk 1 × T × 1 × 1): each entry is then a smooth or constant series, which the
shuffle filter and deflate pack about 18 % tighter than the 16 entries interleaved. That keeps a
data set with ``base_pose`` within 3.2 % of the 0.1 layout's size (which had no ``base_pose``
but stored ``q`` twice). Splitting ``imu`` by column too would save another 12 % of its bytes
but costs 84 chunks per run to compress, index, write and read; one chunk per IMU packs worse
than the whole block on a UR5.
"""

from __future__ import annotations

import copy
import itertools
import json
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from aaria_pin.core.record import (
    SERIES,
    ColumnSource,
    ColumnView,
    RunRecord,
    record_shapes,
    signals_view,
)
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError
from aaria_pin.files._stored import NAME_LISTS, STORED_NAMES, require_arrays
from aaria_pin.files.detection import DATASET_FORMAT

__all__ = [
    "DATASET_FORMAT",
    "DATASET_FORMAT_VERSION",
    "NAME_LISTS",
    "SIGNALS_VIEW",
    "STATUS_DATASETS",
    "DatasetLayout",
    "EncodedRun",
    "array_checksum",
    "encode_run",
    "read_layout",
    "read_run_chunks",
    "signals_view",
]

DATASET_FORMAT_VERSION = 2
STATUS_DATASETS = ("checksum", "complete", "failed")
"""The bookkeeping datasets: CRC-32 of each run's arrays, its complete and failed flags."""
SIGNALS_VIEW = "signals"
"""The flat view every data set has: ``time``, ``q:<joint>`` …, ``<imu>_<signal>`` …"""

EncodedRun = dict[str, tuple[list[bytes], int]]
"""A run ready to store: per array, its chunks' bytes (in chunk order) and the CRC-32 of their
uncompressed bytes (see :func:`encode_run`)."""


@dataclass(frozen=True)
class DatasetLayout:
    """What every run of a data set has in common: names, input tables, views, URDF.

    Attributes:
        joint_names: the n joints of ``q`` … ``tau``
        imu_names: the S IMUs of ``imu``
        imu_parents: each IMU's parent frame (a run whose IMU has a zero mount has none there:
            an empty slot of an Aaria arm)
        tables: shape of each input table of one run, by name, in file order; an extra
            sensor's signals are the table ``sensor_<name>`` (T × columns; its columns and
            units in the file's attribute ``sensors``)
        views: column views of the series (HDF5 virtual datasets in the file); the flat
            ``signals`` view is added to every layout
        urdf: the URDF text shared by every run (``""`` when each run has its own robot, as in
            a data set of random DH arms, whose runs are re-made from their tables)
    """

    joint_names: tuple[str, ...]
    imu_names: tuple[str, ...]
    imu_parents: tuple[str, ...]
    tables: Mapping[str, tuple[int, ...]] = field(default_factory=dict)
    views: Mapping[str, ColumnView] = field(default_factory=dict)
    urdf: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "joint_names", tuple(self.joint_names))
        object.__setattr__(self, "imu_names", tuple(self.imu_names))
        object.__setattr__(self, "imu_parents", tuple(self.imu_parents))
        object.__setattr__(self, "tables", {k: tuple(v) for k, v in self.tables.items()})
        views = dict(self.views)
        views.setdefault(SIGNALS_VIEW, signals_view(self.joint_names, self.imu_names))
        object.__setattr__(self, "views", views)
        if len(self.imu_parents) != len(self.imu_names):
            raise ParameterError(
                f"layout has {len(self.imu_names)} IMU names and {len(self.imu_parents)} "
                "parents; allowed: one parent per IMU",
                parameter="layout",
            )
        clash = [name for name in (*self.tables, *self.views) if name in self.reserved_names()]
        if clash or set(self.tables) & set(self.views):
            bad = clash[0] if clash else sorted(set(self.tables) & set(self.views))[0]
            raise ParameterError(
                f"layout name {bad!r} is taken; allowed: a name not among the series, "
                "imu_mount, the name lists, urdf and the bookkeeping datasets",
                parameter="layout",
            )

    @staticmethod
    def reserved_names() -> tuple[str, ...]:
        """Dataset names a table or view cannot take."""
        return (*STORED_NAMES, *STATUS_DATASETS)

    def shapes(self, samples: int) -> dict[str, tuple[int, ...]]:
        """Shape of each stored array of one run of T = ``samples``, in file order."""
        joints, imus = len(self.joint_names), len(self.imu_names)
        return {**record_shapes(samples, joints, imus), **self.tables}

    @property
    def names(self) -> tuple[str, ...]:
        """Names of the stored per-run arrays, in file order."""
        return tuple(self.shapes(0))

    @property
    def inputs(self) -> tuple[str, ...]:
        """The arrays stored as float64 whatever the data set's dtype: mounts and input tables.

        A sensor's table (``sensor_<name>``) is a series: it takes the data set's dtype.
        """
        from aaria_pin.core.run.sensor import is_sensor_table

        return ("imu_mount", *(name for name in self.tables if not is_sensor_table(name)))

    @staticmethod
    def chunk(name: str, shape: tuple[int, ...]) -> tuple[int, ...]:
        """A run's chunk of an array (no run axis): the whole array, or a pose's one entry.

        A pose series (T × 4 × 4) is chunked per matrix entry (see the module docstring).
        """
        if name in SERIES and shape[1:] == (4, 4):
            return (shape[0], 1, 1)
        return shape

    def check(self, record: RunRecord) -> None:
        """Refuse a run that does not fit the layout (other joints, IMUs or tables).

        Raises:
            ParameterError: naming what differs.
        """
        mine = {
            "joint names": self.joint_names,
            "IMU names": self.imu_names,
            "tables": tuple(sorted(self.tables)),  # the record's order may differ: the file's
        }
        theirs = {
            "joint names": record.joint_names,
            "IMU names": record.imu_names,
            "tables": tuple(sorted(record.tables)),
        }
        for what, expected in mine.items():
            if theirs[what] != expected:
                raise ParameterError(
                    f"run {what} are {list(theirs[what])}; "
                    f"allowed: the data set's {list(expected)}",
                    parameter="record",
                )
        for name, shape in self.tables.items():
            if np.shape(record.tables[name]) != shape:
                raise ParameterError(
                    f"run table {name} has shape {np.shape(record.tables[name])}; allowed: {shape}",
                    parameter="record",
                )

    def to_json(self) -> str:
        """The file's ``layout_json`` attribute: the tables and the views (names apart)."""
        return json.dumps(
            {
                "tables": {name: list(shape) for name, shape in self.tables.items()},
                "views": {
                    name: {
                        "columns": list(view.columns),
                        "sources": [[s.array, list(s.index)] for s in view.sources],
                        "units": view.units,
                    }
                    for name, view in self.views.items()
                },
            }
        )

    @classmethod
    def from_json(
        cls, text: str, names: Mapping[str, tuple[str, ...]], urdf: str = ""
    ) -> DatasetLayout:
        """A layout from a file's ``layout_json`` and its name lists (:data:`NAME_LISTS`)."""
        data = json.loads(text)
        views = {
            name: ColumnView(
                tuple(view["columns"]),
                tuple(ColumnSource(array, tuple(index)) for array, index in view["sources"]),
                view.get("units", ""),
            )
            for name, view in data["views"].items()
        }
        return cls(
            names["joint_names"],
            names["imu_names"],
            names["imu_parents"],
            {name: tuple(shape) for name, shape in data["tables"].items()},
            views,
            urdf,
        )


def chunk_origins(shape: tuple[int, ...], chunk: tuple[int, ...]) -> Iterator[tuple[int, ...]]:
    """The first index of each chunk of an array of ``shape`` (one run's), in storage order."""
    return itertools.product(*(range(0, dim, size) for dim, size in zip(shape, chunk, strict=True)))


def codec() -> tuple[Any, Any, Any]:
    """Deflate, inflate and CRC-32: ISA-L's (``isal``), or zlib's where ``isal`` is missing.

    Both make the standard zlib stream and CRC-32; ISA-L deflates about 8 times faster than
    zlib at level 1 for the same size; the CRC-32 is the run files' own
    (:func:`~aaria_pin.files._stored.crc32_function`).
    """
    from aaria_pin.files._stored import crc32_function

    try:
        from isal.isal_zlib import compress, decompress
    except ImportError:  # pragma: no cover - isal is a dependency; zlib makes the same format
        from zlib import compress, decompress
    return compress, decompress, crc32_function()


_CONSTANT_CHUNKS: dict[tuple[str, int, bytes], bytes] = {}
"""Compressed bytes of constant chunks by (dtype, element count, element bytes), per process.

The last row of every pose sample is ``0 0 0 1``: 8 of a run's 32 pose chunks are the same
constant series in every run, so each is compressed once per process.
"""
_MAX_CONSTANT_CHUNKS = 256


def _shuffled_entries(array: Array) -> Array:
    """HDF5's shuffle of each trailing entry's series: ``[entry, byte, t]`` as uint8.

    ``array`` is T × … (one run's series); entry ``i`` (its trailing indices in C order) is the
    series ``array[:, i]``, and row ``[i]`` of the result, read as bytes, is what the shuffle
    filter makes of that series: byte ``j`` of every element together, ``j`` = 0 … itemsize-1.
    One transposing copy for all entries.
    """
    samples, itemsize = array.shape[0], array.itemsize
    flat = np.ascontiguousarray(array).reshape(samples, -1)
    planes = flat.view(np.uint8).reshape(samples, flat.shape[1], itemsize)
    return np.ascontiguousarray(planes.transpose(1, 2, 0))


def _constant_entries(array: Array) -> Array:
    """Which trailing entries of a T × … array hold the same bits at every sample."""
    flat = np.ascontiguousarray(array).reshape(array.shape[0], -1)
    bits = flat.view(np.dtype(f"u{array.itemsize}"))
    return np.asarray((bits == bits[:1]).all(axis=0))


def _per_entry(shape: tuple[int, ...], chunk: tuple[int, ...]) -> bool:
    """Whether a chunking holds one trailing entry's whole series per chunk (T × 1 × … × 1)."""
    return len(shape) > 1 and chunk[0] == shape[0] and all(c == 1 for c in chunk[1:])


def _chunk_blocks(array: Array, chunk: tuple[int, ...]) -> list[Any]:
    """The shuffled bytes of each chunk of one run's array, in storage order (buffers).

    The two chunkings of the layout take one copy each: the whole array (one chunk), or one
    chunk per trailing entry (chunk T × 1 × … × 1, a pose's entries); any other chunking is
    cut chunk by chunk.
    """
    if chunk == array.shape:
        raw = np.ascontiguousarray(array)
        return [np.ascontiguousarray(raw.view(np.uint8).reshape(-1, raw.itemsize).T)]
    if _per_entry(array.shape, chunk):
        return list(_shuffled_entries(array))
    blocks = []
    for origin in chunk_origins(array.shape, chunk):
        block = array[tuple(slice(o, o + c) for o, c in zip(origin, chunk, strict=True))]
        raw = np.ascontiguousarray(block)
        blocks.append(np.ascontiguousarray(raw.view(np.uint8).reshape(-1, raw.itemsize).T))
    return blocks


def encode_run(layout: DatasetLayout, record: RunRecord, dtype: str) -> EncodedRun:
    """Each stored array of a run as the bytes of its HDF5 chunks, and their CRC-32.

    The CRC-32 is that of the chunks' bytes before deflate (the shuffled numbers, what HDF5
    gives back when it decodes a chunk's deflate), so it depends on the numbers only: two
    encoders, or two runs of one, that deflate the same numbers to other bytes still record
    the same ``checksum`` row (a resumed data set equals an uninterrupted one array for array,
    ``checksum`` included).

    A chunk is what HDF5's filters make of it: the shuffle filter (byte ``j`` of every element
    together), then deflate at level 1, so h5py, MATLAB and any HDF5 reader decode it. Deflate
    runs through ISA-L (``isal``: a standard zlib stream, about 8 times faster than zlib at the
    same size), or zlib where ``isal`` is missing. Inputs (mounts, tables) stay float64, series
    take ``dtype``.

    Where the time goes (1,000 samples, 14 IMUs, float32; 43 chunks; 2.1 to 3 ms a run as the
    shared machine allows, of which the measures below save 0.1 to 0.4 ms): deflate about
    1.5 ms, of which ``imu`` (336 kB) 0.6 ms and each of the 24 varying pose entries (4 kB)
    about 18 µs, mostly per-stream work (a constant entry takes 4 µs; level 0, which builds no
    Huffman codes of its own, 7 µs but 24 % more bytes, beyond the size budget). A pose's 16
    entries are shuffled by one transposing copy, the 8 constant ones (the last row
    ``0 0 0 1``) are compressed once per process (:data:`_CONSTANT_CHUNKS`: the same bytes as
    compressing them again), and the CRC-32 is ISA-L's.

    Raises:
        ParameterError: the run does not fit the layout.
    """
    layout.check(record)
    compress, _, crc32 = codec()
    encoded: EncodedRun = {}
    for name, array in run_arrays(layout, record, dtype).items():
        chunk = layout.chunk(name, array.shape)
        blocks = _chunk_blocks(array, chunk)
        constant = (
            _constant_entries(array)
            if _per_entry(array.shape, chunk)
            else np.zeros(len(blocks), dtype=bool)
        )
        flat = array.reshape(array.shape[0], -1) if constant.any() else array
        chunks, checksum = [], 0
        for index, block in enumerate(blocks):
            if constant[index]:
                key = (array.dtype.str, array.shape[0], flat[0, index].tobytes())
                data = _CONSTANT_CHUNKS.get(key)
                if data is None:
                    data = compress(block, 1)
                    if len(_CONSTANT_CHUNKS) >= _MAX_CONSTANT_CHUNKS:
                        _CONSTANT_CHUNKS.clear()
                    _CONSTANT_CHUNKS[key] = data
            else:
                data = compress(block, 1)
            checksum = crc32(block, checksum)
            chunks.append(data)
        encoded[name] = (chunks, checksum)
    return encoded


def array_checksum(array: Array, chunk: tuple[int, ...]) -> int:
    """The CRC-32 ``checksum`` records for one run's array: of its chunks before deflate.

    The same number :func:`encode_run` records (its chunks' shuffled bytes, in storage order),
    computed from the numbers, so a reader checks what it read without the stored bytes.

    Args:
        array: one run's array, in its stored dtype
        chunk: its chunk (:meth:`DatasetLayout.chunk`)
    """
    _, _, crc32 = codec()
    checksum = 0
    for block in _chunk_blocks(np.asarray(array), chunk):
        checksum = crc32(block, checksum)
    return int(checksum)


def run_arrays(layout: DatasetLayout, record: RunRecord, dtype: str) -> dict[str, Array]:
    """The stored arrays of a run by name, in file order and in their stored dtypes."""
    arrays = record.arrays()
    return {
        name: np.asarray(arrays[name], dtype="float64" if name in layout.inputs else dtype)
        for name in layout.names
    }


_DATASET_ONLY = (
    "format",
    "format_version",
    "N",
    "samples",
    "dtype",
    "vary",
    "config",
    "fixed_tables",
    "failures",
    "layout",
    "robot_info",
    "noise_stream",
    "command",
    "versions",
    "shard_dir",
    "shard_prefix",
    "card",
    "hardware",
    "hardware_names",
)
"""File attributes that describe the data set, not one of its runs."""


def record_attributes(
    file_attributes: Mapping[str, Any], run: int, noise_stream: int, drawn: Array | None = None
) -> dict[str, Any]:
    """The attributes of run ``run``'s record: the data set's, its noise seed, its index.

    The record gets what a single run records: ``kind``, ``robot`` (a name), rate, duration,
    noise settings, gravity, units, version, the robot's frames, its hardware models; ``seed``
    with ``noise_spawn_key`` ``[run, noise_stream]`` (the run's noise stream, so
    :func:`~aaria_pin.core.seeds.stored_seed` gives it back) and ``run``. A data set whose
    hardware has ranges gives each run its own values: ``drawn`` (its table
    ``hardware_values``) at the attribute paths of ``hardware_names`` (``encoder/noise/0``;
    NaN: a key the run leaves out).
    """
    attributes = {k: v for k, v in file_attributes.items() if k not in _DATASET_ONLY}
    names = file_attributes.get("hardware_names") or []
    if drawn is not None and len(names) == np.size(drawn):
        attributes.update(copy.deepcopy({name.split("/")[0]: attributes[name.split("/")[0]]
                                         for name in names}))  # fmt: skip
        for name, value in zip(names, np.asarray(drawn, dtype=float).ravel(), strict=True):
            *parents, last = name.split("/")
            target: Any = attributes
            for key in parents:
                target = target[int(key)] if isinstance(target, list) else target[key]
            if isinstance(target, list):
                target[int(last)] = float(value)
            elif np.isnan(value):
                target.pop(last, None)  # a term the run does not record (off)
            else:
                target[last] = float(value)
    info = file_attributes.get("robot_info") or {}
    for key in ("source", "moving_base", "base_frame", "tool_frame"):
        if key in info:
            attributes.setdefault(key, info[key])
    attributes["noise_spawn_key"] = [int(run), int(noise_stream)]
    attributes["run"] = int(run)
    return attributes


def read_layout(handle: Any) -> DatasetLayout:
    """The layout of an open version 2 data set file.

    Raises:
        InputFileError: a name list, ``urdf``, a per-run array, a view or a status array
            that is not an array (an HDF5 group).
    """
    require_arrays(handle, handle.filename, (*NAME_LISTS, "urdf", *STATUS_DATASETS))
    names = {name: tuple(handle[name].asstr()[()]) for name in NAME_LISTS}
    urdf = handle["urdf"].asstr()[()] if "urdf" in handle else ""
    layout = DatasetLayout.from_json(handle.attrs["layout_json"], names, urdf)
    require_arrays(handle, handle.filename, (*layout.names, *layout.views))
    return layout


def read_run_chunks(
    handle: Any, names: Sequence[str], row: int
) -> tuple[list[tuple[str, tuple[int, ...], bytes]], list[int], list[int]]:
    """The stored chunk bytes of one run (row ``row`` of each array) and each array's CRC-32s.

    Returns:
        ``(name, chunk origin with the row, bytes)`` of every chunk in storage order; the
        CRC-32 of each array's chunks once inflated, in ``names`` order (what ``checksum``
        records, :func:`~.layout.encode_run`); and the CRC-32 of their stored (deflated) bytes
        (what files written before the checksums were of uncompressed bytes recorded).

    Raises:
        OSError, KeyError, RuntimeError, zlib.error: a chunk or an array cannot be read or
            inflated.
    """
    _, decompress, crc32 = codec()  # ISA-L's CRC-32: 4 µs a 200 kB chunk against zlib's 49
    chunks, plain, stored = [], [], []
    for name in names:
        dataset = handle[name]
        plain_crc = stored_crc = 0
        for origin in chunk_origins(dataset.shape[1:], dataset.chunks[1:]):
            where = (row, *origin)
            _, data = dataset.id.read_direct_chunk(where)
            stored_crc = crc32(data, stored_crc)
            try:
                plain_crc = crc32(decompress(data), plain_crc)
            except Exception as exc:  # isal's and zlib's own error classes
                raise OSError(f"chunk {where} of {name} cannot be inflated ({exc})") from None
            chunks.append((name, where, data))
        plain.append(plain_crc)
        stored.append(stored_crc)
    return chunks, plain, stored
