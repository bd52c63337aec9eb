"""The ``.mat`` layout of a run file as a MATLAB v7.3 MAT-file, written in time pieces (h5py).

A MAT-file v7.3 is an HDF5 file whose first 512 bytes are a user block holding MATLAB's
128-byte header: 116 bytes of text starting ``MATLAB 7.3 MAT-file`` (space padded), an 8-byte
subsystem offset (zeros: none), the version ``0x0200`` and the endian mark ``IM`` (little
endian). Each variable is a dataset at the root with a ``MATLAB_class`` attribute (an ASCII
string). MATLAB is column-major and stores an array of MATLAB size d1 × d2 × … as the HDF5
array of shape (… × d2 × d1): the dims reversed, so a T × n array is an (n, T) dataset and
``time`` (1 × T) a (T, 1) one. Rules followed (as MATLAB, matio and hdf5storage write them):

- numbers: ``double`` (float64), ``int64``; ``logical`` is uint8 with ``MATLAB_int_decode = 1``;
- text: ``char``, UTF-16 code units as uint16 (a 1 × L row: shape (L, 1)) with
  ``MATLAB_int_decode = 2``;
- cell arrays: ``cell``, an array of HDF5 object references to datasets in the group
  ``#refs#``, one per element, each with its own ``MATLAB_class``;
- an empty array (a dim of 0): a uint64 dataset holding its MATLAB size, in MATLAB order, with
  ``MATLAB_empty = 1`` (uint8) beside its ``MATLAB_class``.

The variables are those of the v5 layout (the module docstring of
:mod:`aaria_pin.files.runfile`), with the sizes MATLAB shows for the v5 file: the series
T × … (``time`` 1 × T), each view a real T × C array (materialised piece by piece, not a
virtual dataset: MATLAB's HDF5 library reads virtual datasets only from release R2021b on),
names as 1 × n cell arrays (an empty one 0 × 0, as scipy writes it), ``urdf`` a char row (0 × 0
if empty), ``attr_<name>`` scalars 1 × 1 and vectors 1 × k. The series and views are
preallocated at the run's full length and filled piece by piece (:class:`_Mat73Stream`), so
memory does not grow with the run's length; ``compression="gzip"`` chunks them along time
(deflate level 1 after the shuffle filter; MATLAB reads only deflate, so ``"lzf"`` is refused).

:func:`load_mat73` reads such a file (or one MATLAB saved with ``-v7.3``) into the variables
scipy's ``loadmat`` gives for a v5 file, so the one v5 reader reads both.
"""

from __future__ import annotations

import contextlib
import sys
import time
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.record import SERIES, ColumnView, RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.errors import OutputFileError
from aaria_pin.files._space import close_hdf5
from aaria_pin.files._stored import damaged_errors, read_errors
from aaria_pin.files.runfile._columns import COLUMNS_SUFFIX, RunStream, chunk_rows

USER_BLOCK = 512
"""Bytes of the HDF5 user block that holds the MAT-file header."""

REFS_GROUP = "#refs#"
"""The group of the datasets a cell array's references point to."""

_HEADER_TEXT = 116
_CLASSES = {
    np.dtype(np.float64): "double",
    np.dtype(np.int64): "int64",
    np.dtype(np.uint8): "uint8",
}
_DTYPES = {
    "double": np.float64,
    "single": np.float32,
    "int8": np.int8,
    "uint8": np.uint8,
    "int16": np.int16,
    "uint16": np.uint16,
    "int32": np.int32,
    "uint32": np.uint32,
    "int64": np.int64,
    "uint64": np.uint64,
    "logical": np.bool_,
}


def mat73_header(platform: str | None = None, created: str | None = None) -> bytes:
    """The 128-byte MAT-file v7.3 header MATLAB puts in the user block.

    Args:
        platform: the ``Platform:`` field (default ``sys.platform``)
        created: the ``Created on:`` field (default now, as MATLAB writes it)
    """
    text = (
        f"MATLAB 7.3 MAT-file, Platform: {platform or sys.platform}, Created on: "
        f"{created or time.strftime('%a %b %d %H:%M:%S %Y')} HDF5 schema 1.00 ."
    ).encode("ascii")[:_HEADER_TEXT]
    return text.ljust(_HEADER_TEXT, b" ") + bytes(8) + (0x0200).to_bytes(2, "little") + b"IM"


# --- writing -------------------------------------------------------------------------------------


def _matlab_shape(value: Array) -> tuple[int, ...]:
    """The size MATLAB shows for an array scipy writes with ``oned_as="row"``."""
    if value.ndim == 0:
        return (1, 1)
    if value.ndim == 1:
        return (1, value.shape[0])
    return tuple(value.shape)


def _mark(dataset: Any, matlab_class: str, int_decode: int | None = None) -> Any:
    dataset.attrs.create("MATLAB_class", np.bytes_(matlab_class.encode("ascii")))
    if int_decode is not None:
        dataset.attrs.create("MATLAB_int_decode", np.int32(int_decode))
    return dataset


def _put_empty(group: Any, name: str, shape: tuple[int, ...], matlab_class: str) -> Any:
    """An empty MATLAB array: its size (MATLAB order) as uint64, ``MATLAB_empty = 1``."""
    dataset = group.create_dataset(name, data=np.array(shape, dtype=np.uint64))
    _mark(dataset, matlab_class)
    dataset.attrs.create("MATLAB_empty", np.uint8(1))
    return dataset


def _put_text(group: Any, name: str, text: str) -> Any:
    """A MATLAB char row (1 × L UTF-16 code units; 0 × 0 if empty)."""
    units = np.frombuffer(text.encode("utf-16-le"), dtype="<u2")
    if units.size == 0:
        return _put_empty(group, name, (0, 0), "char")
    return _mark(group.create_dataset(name, data=units.reshape(-1, 1)), "char", 2)


def _put_cell(handle: Any, group: Any, name: str, items: Iterable[str]) -> Any:
    """A MATLAB 1 × n cell array of char rows (0 × 0 if empty), elements in ``#refs#``."""
    import h5py

    texts = list(items)
    if not texts:
        return _put_empty(group, name, (0, 0), "cell")
    refs = handle.require_group(REFS_GROUP)
    references = np.empty((len(texts), 1), dtype=h5py.ref_dtype)
    for k, text in enumerate(texts):
        element = _put_text(refs, f"{name}_{k}", text)
        references[k, 0] = element.ref
    return _mark(group.create_dataset(name, data=references), "cell")


def _put_value(handle: Any, name: str, value: Any) -> None:
    """One variable of the v5 layout (as ``_mat_contents`` gives it) as a v7.3 dataset."""
    if isinstance(value, str):
        _put_text(handle, name, value)
        return
    data = np.asarray(value)
    if data.dtype == object:
        _put_cell(handle, handle, name, (str(item) for item in data.ravel()))
        return
    matlab_class = "logical" if data.dtype == np.bool_ else _CLASSES.get(data.dtype)
    if matlab_class is None:
        data = data.astype(np.float64)
        matlab_class = "double"
    shape = _matlab_shape(data)
    if 0 in shape:
        _put_empty(handle, name, shape, matlab_class)
        return
    stored = np.ascontiguousarray(np.reshape(data, shape).T)
    if matlab_class == "logical":
        _mark(handle.create_dataset(name, data=stored.astype(np.uint8)), "logical", 1)
    else:
        _mark(handle.create_dataset(name, data=stored), matlab_class)


class _Mat73Stream(RunStream):
    """An open MAT-file v7.3 run file whose series and views are filled piece by piece.

    The interface of :class:`~aaria_pin.files.runfile._hdf5._Hdf5Stream`: ``__init__`` writes
    everything but the series' and views' values and the ``attr_`` variables, :meth:`write`
    fills samples, :meth:`close` writes the ``attr_`` variables (those of the last piece) and
    the MAT-file header into the user block.
    """

    def _open(self, file: Path) -> Any:
        """The open h5py file with room for the MAT-file header."""
        import h5py

        # Links in creation order (as .h5 run files): the variables read back in v5's order.
        return h5py.File(file, "w", userblock_size=USER_BLOCK, track_order=True)

    def _series_dataset(
        self, name: str, shape: tuple[int, ...], time_axis: int, compression: str | None
    ) -> Any:
        """A preallocated double dataset of MATLAB size ``shape`` (None if it is empty)."""
        if 0 in shape:
            _put_empty(self.handle, name, shape, "double")
            return None
        stored = shape[::-1]
        chunks = None
        if compression is not None:
            row_bytes = 8 * int(np.prod(stored)) // shape[time_axis]
            rows = chunk_rows(shape[time_axis], row_bytes)
            chunk = list(stored)
            chunk[len(shape) - 1 - time_axis] = rows
            chunks = tuple(chunk)
        dataset = self.handle.create_dataset(
            name,
            shape=stored,
            dtype=np.float64,
            chunks=chunks,
            compression="gzip" if chunks else None,
            compression_opts=1 if chunks else None,
            shuffle=chunks is not None,
        )
        return _mark(dataset, "double")

    def _lay_out(
        self,
        first: RunRecord,
        arrays: Mapping[str, Array],
        samples: int,
        compression: str | None,
    ) -> None:
        """Create every variable (the rest of ``__init__``)."""
        self.series: dict[str, tuple[Any, int]] = {}
        for name, data in arrays.items():
            if name not in SERIES:
                _put_value(self.handle, name, data)
                continue
            shape = (1, samples) if name == "time" else (samples, *data.shape[1:])
            time_axis = 1 if name == "time" else 0
            dataset = self._series_dataset(name, shape, time_axis, compression)
            if dataset is not None:
                self.series[name] = (dataset, time_axis)
        self.views: dict[str, tuple[Any, ColumnView]] = {}
        for name, view in first.views.items():
            dataset = self._series_dataset(name, (samples, len(view.columns)), 0, compression)
            if dataset is not None:
                self.views[name] = (dataset, view)
            _put_cell(self.handle, self.handle, name + COLUMNS_SUFFIX, view.columns)
        _put_cell(self.handle, self.handle, "joint_names", first.joint_names)
        _put_cell(self.handle, self.handle, "imu_names", first.imu_names)
        _put_cell(self.handle, self.handle, "imu_parents", (m.parent for m in first.imu_mounts))
        _put_text(self.handle, "urdf", first.urdf)

    def write(self, start: int, arrays: Mapping[str, Array]) -> None:
        """Store the series and views of samples ``start`` … (contiguous float64 by name)."""
        n = arrays["time"].shape[0]
        if not n:
            return
        for name, (dataset, time_axis) in self.series.items():
            data = arrays[name]
            selection = [slice(None)] * dataset.ndim
            selection[dataset.ndim - 1 - time_axis] = slice(start, start + n)
            matlab = data.reshape(1, n) if time_axis == 1 else data  # the piece, MATLAB size
            dataset[tuple(selection)] = np.ascontiguousarray(matlab.T)
        for dataset, view in self.views.values():
            dataset[:, start : start + n] = np.ascontiguousarray(view.materialise(arrays).T)

    def close(self, attributes: list[tuple[str, Any]] | None) -> None:
        """Write the ``attr_`` variables (unless None: a failed file), close, write the header.

        Args:
            attributes: the ``.mat`` variables of the attributes by name (``attr_format``,
                ``attr_format_version`` first), as the v5 layout has them
        """
        try:
            if attributes is not None:
                for name, value in attributes:
                    _put_value(self.handle, name, value)
        except BaseException:
            close_hdf5(self.handle, failed=True)
            raise
        close_hdf5(self.handle, failed=attributes is None)
        if attributes is not None:
            with self.file.open("r+b") as stream:
                stream.write(mat73_header())


# --- reading -------------------------------------------------------------------------------------


def _mat73_errors(file: Path) -> contextlib.AbstractContextManager[None]:
    """Turn h5py's errors on reading ``file`` into one-line :class:`InputFileError`."""
    return read_errors(file, "a .mat v7.3 run file")


def _class_of(dataset: Any) -> str:
    value = dataset.attrs.get("MATLAB_class", b"double")
    return value.decode("ascii") if isinstance(value, bytes) else str(value)


def _is_empty(dataset: Any) -> bool:
    return bool(np.asarray(dataset.attrs.get("MATLAB_empty", 0)).any())


def _shape_of(dataset: Any) -> tuple[int, ...]:
    """The MATLAB size of a variable, without reading it (an empty one's size is read)."""
    if _is_empty(dataset):
        return tuple(int(dim) for dim in np.ravel(dataset[()]))
    shape = tuple(int(dim) for dim in dataset.shape[::-1])
    return shape if len(shape) >= 2 else (*shape, 1)[:2]


def _text(data: Array) -> Array:
    """A MATLAB char array (MATLAB order) as scipy gives it: one string per row."""
    rows = np.atleast_2d(data)
    return np.array(
        [row.astype("<u2").tobytes().decode("utf-16-le", errors="replace") for row in rows]
    )


def _read_value(handle: Any, dataset: Any) -> Any:
    """A variable as scipy's ``loadmat(squeeze_me=False, mat_dtype=True)`` gives it."""
    matlab_class = _class_of(dataset)
    if _is_empty(dataset):
        shape = _shape_of(dataset)
        if matlab_class == "char":
            return np.array([], dtype="<U1")
        if matlab_class == "cell":
            return np.empty(shape, dtype=object)
        return np.zeros(shape, dtype=_DTYPES.get(matlab_class, np.float64))
    data = np.asarray(dataset[()])
    matlab = data.T if data.ndim >= 2 else data.reshape(-1, 1)  # MATLAB order
    if matlab_class == "char":
        return _text(matlab)
    if matlab_class == "cell":
        cell = np.empty(matlab.shape, dtype=object)
        for index, reference in np.ndenumerate(matlab):
            cell[index] = _read_value(handle, handle[reference])
        return cell
    if matlab_class == "logical":
        return matlab.astype(bool)
    return matlab.astype(_DTYPES.get(matlab_class, np.float64), copy=False)


def _variables(handle: Any) -> dict[str, Any]:
    """The variables (root datasets, not the ``#…#`` groups) of an open v7.3 file."""
    import h5py

    return {
        name: item
        for name, item in handle.items()
        if isinstance(item, h5py.Dataset) and not name.startswith("#")
    }


def load_mat73(file: Path, names: list[str] | None = None) -> dict[str, Any]:
    """Variables of a MAT-file v7.3, as scipy's ``loadmat`` gives a v5 file's.

    Args:
        file: the file
        names: the variables to read (default all)
    """
    import h5py

    with _mat73_errors(file), h5py.File(file, "r") as handle, damaged_errors(file):
        return {
            name: _read_value(handle, item)
            for name, item in _variables(handle).items()
            if names is None or name in names
        }


def mat73_variables(file: Path) -> dict[str, tuple[int, ...]]:
    """The names and MATLAB sizes of a MAT-file v7.3's variables, without reading them."""
    import h5py

    with _mat73_errors(file), h5py.File(file, "r") as handle:
        return {name: _shape_of(item) for name, item in _variables(handle).items()}


def check_mat73_compression(final: Path, compression: str | None) -> None:
    """Refuse a filter MATLAB cannot read (it reads deflate, ``"gzip"``, only)."""
    if compression not in (None, "gzip"):
        raise OutputFileError(
            f"{final}: compression {compression!r} cannot be read by MATLAB; allowed for a "
            ".mat v7.3 file: None, 'gzip'",
            parameter="compression",
            value=compression,
            allowed="None, 'gzip'",
        )
