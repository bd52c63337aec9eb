"""Mutators of real run files and data sets, for the adversarial tests (issue 28).

Each mutator damages one file in place, the way a disk, a copy or a careless edit would, and
returns a one-line description of what it did (for the failure message and for a repro). The
choices it makes (which array, which byte, which attribute, which value) are drawn through
``draw``, hypothesis's ``data.draw``, so a failing example shrinks and replays.

The mutators are written from the file formats themselves (HDF5 through h5py: an array's data
region from its storage offset, or a chunk's; MATLAB v5 through scipy), not from the library's
reader: the tests check the reader against them.

Formats: ``"h5"`` a run file in HDF5, ``"mat"`` a run file in MATLAB v5, ``"dataset"`` a data
set (HDF5, one row per run, chunked and compressed).
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import numpy as np
from hypothesis import strategies as st

T = TypeVar("T")
Draw = Callable[[st.SearchStrategy[T]], T]
Mutator = Callable[[Path, Any], str]

MAT_HEADER = 128
"""Bytes of a MATLAB v5 file's header (text, subsystem offset, version, endianness)."""

MAT_ATTRIBUTE = "attr_"
"""Prefix of a run attribute stored as a variable of a ``.mat`` file."""

SERIES = ("time", "q", "qd", "qdd", "tau", "imu", "base_pose", "tool_pose", "base_wrench")
"""Arrays with a time axis: the measured and simulated series of a run."""


def invoke_in(folder: Path, argv: list[str]) -> Any:
    """Run ``aaria argv`` in process (click's runner) with ``folder`` as the working folder."""
    import os

    from click.testing import CliRunner

    from aaria_pin.cli import main

    old = Path.cwd()
    os.chdir(folder)
    try:
        return CliRunner().invoke(main, argv)
    finally:
        os.chdir(old)


def _numeric_arrays(handle: Any) -> list[str]:
    """Names of the numeric (float or integer) arrays at the top of an HDF5 file."""
    import h5py

    return sorted(
        name
        for name, item in handle.items()
        if isinstance(item, h5py.Dataset) and item.dtype.kind in "fiu" and item.size
    )


def _flip(path: Path, offset: int, count: int) -> None:
    """Invert ``count`` bytes of ``path`` from ``offset`` (every bit: the bytes surely change)."""
    with path.open("r+b") as stream:
        stream.seek(offset)
        old = stream.read(count)
        stream.seek(offset)
        stream.write(bytes(b ^ 0xFF for b in old))


def truncate(path: Path, draw: Any) -> str:
    """Cut the file short, keeping a drawn share of its bytes (a copy that stopped)."""
    size = path.stat().st_size
    keep = draw(st.integers(min_value=0, max_value=size - 1))
    with path.open("r+b") as stream:
        stream.truncate(keep)
    return f"truncated to {keep} of {size} bytes"


def flip_h5_data(path: Path, draw: Any) -> str:
    """Invert bytes inside one array's stored data (one chunk of it when chunked)."""
    import h5py

    with h5py.File(path, "r") as handle:
        names = [
            name
            for name in _numeric_arrays(handle)
            if handle[name].chunks is not None or handle[name].id.get_offset() is not None
        ]
        name = draw(st.sampled_from(names))
        dset = handle[name]
        if dset.chunks is None:
            start, size, where = dset.id.get_offset(), dset.id.get_storage_size(), "data"
        else:
            index = draw(st.integers(min_value=0, max_value=dset.id.get_num_chunks() - 1))
            info = dset.id.get_chunk_info(index)
            start, size, where = info.byte_offset, info.size, f"chunk {info.chunk_offset}"
    at = draw(st.integers(min_value=0, max_value=size - 1))
    count = draw(st.integers(min_value=1, max_value=min(8, size - at)))
    _flip(path, start + at, count)
    return f"inverted {count} byte(s) at {at} of array {name!r} ({where}, {size} bytes)"


def flip_mat_data(path: Path, draw: Any) -> str:
    """Invert bytes after the header of a ``.mat`` file (its compressed variables)."""
    size = path.stat().st_size
    at = draw(st.integers(min_value=MAT_HEADER, max_value=size - 1))
    count = draw(st.integers(min_value=1, max_value=min(8, size - at)))
    _flip(path, at, count)
    return f"inverted {count} byte(s) at offset {at} of {size}"


def _load_mat(path: Path) -> dict[str, Any]:
    from scipy.io import loadmat

    contents = loadmat(path, appendmat=False, squeeze_me=False, mat_dtype=True)
    return {name: value for name, value in contents.items() if not name.startswith("__")}


def _save_mat(path: Path, contents: dict[str, Any]) -> None:
    """Write ``.mat`` variables as the tool writes them (v5, compressed, 1-D as rows)."""
    from scipy.io import savemat

    savemat(path, contents, appendmat=False, format="5", do_compression=True, oned_as="row")


def delete_h5_array(path: Path, draw: Any) -> str:
    """Remove one array of the file."""
    import h5py

    with h5py.File(path, "r+") as handle:
        name = draw(st.sampled_from(sorted(handle)))
        del handle[name]
    return f"deleted array {name!r}"


def delete_mat_variable(path: Path, draw: Any) -> str:
    """Remove one array variable (not an ``attr_``) of a ``.mat`` file."""
    contents = _load_mat(path)
    name = draw(st.sampled_from(sorted(n for n in contents if not n.startswith(MAT_ATTRIBUTE))))
    del contents[name]
    _save_mat(path, contents)
    return f"deleted variable {name!r}"


def _other_layout(data: np.ndarray, draw: Any) -> tuple[np.ndarray, str]:
    """``data`` with another shape (a column or a sample short, a transposed table) or of
    another type (booleans, text)."""
    change = draw(st.sampled_from(["last axis short", "first axis short", "bool", "text"]))
    if change == "last axis short" and data.shape and data.shape[-1] > 1:
        return data[..., :-1], change
    if change == "first axis short" and data.shape and data.shape[0] > 1:
        return data[:-1], change
    if change == "bool":
        return data != 0, change
    return data.astype("S24"), "text"


def relayout_h5_array(path: Path, draw: Any) -> str:
    """Store one numeric array again with another shape or type (a layout of another kind)."""
    import h5py

    with h5py.File(path, "r+") as handle:
        name = draw(st.sampled_from(_numeric_arrays(handle)))
        data, change = _other_layout(np.array(handle[name]), draw)
        attributes = dict(handle[name].attrs)
        del handle[name]
        handle[name] = data
        handle[name].attrs.update(attributes)
    return f"array {name!r} stored again as {change} {data.dtype} {data.shape}"


def relayout_mat_variable(path: Path, draw: Any) -> str:
    """Store one numeric variable of a ``.mat`` file again with another shape or type."""
    contents = _load_mat(path)
    names = sorted(
        n
        for n, value in contents.items()
        if not n.startswith(MAT_ATTRIBUTE) and np.asarray(value).dtype.kind in "fiu"
    )
    name = draw(st.sampled_from(names))
    data, change = _other_layout(np.asarray(contents[name]), draw)
    contents[name] = data.astype(str) if change == "text" else data
    _save_mat(path, contents)
    return f"variable {name!r} stored again as {change} {data.dtype} {data.shape}"


def _other_type(value: Any, draw: Any) -> Any:
    """A value of another type than ``value``: text for a number, a number for text."""
    if isinstance(value, (str, bytes)):
        return draw(st.sampled_from([3.5, -1, 0]))
    return draw(st.sampled_from(["fast", "", "[1, 2"]))


def _attribute_names(handle: Any) -> list[str]:
    return sorted(name for name in handle.attrs if name not in ("format",))


def retype_h5_attribute(path: Path, draw: Any) -> str:
    """Store one file attribute as another type (text for a number, a number for text)."""
    import h5py

    with h5py.File(path, "r+") as handle:
        name = draw(st.sampled_from(_attribute_names(handle)))
        value = _other_type(handle.attrs[name], draw)
        handle.attrs[name] = value
    return f"attribute {name!r} set to {value!r}"


def retype_mat_attribute(path: Path, draw: Any) -> str:
    """Store one ``attr_`` variable of a ``.mat`` file as another type."""
    contents = _load_mat(path)
    names = sorted(
        n for n in contents if n.startswith(MAT_ATTRIBUTE) and n != MAT_ATTRIBUTE + "format"
    )
    name = draw(st.sampled_from(names))
    old = contents[name]
    value = _other_type("" if np.asarray(old).dtype.kind == "U" else 0.0, draw)
    contents[name] = value
    _save_mat(path, contents)
    return f"variable {name!r} set to {value!r}"


def _set_attribute(path: Path, name: str, value: Any) -> None:
    """Set one attribute of an HDF5 file or one ``attr_`` variable of a ``.mat`` file."""
    if path.suffix == ".mat":
        contents = _load_mat(path)
        contents[MAT_ATTRIBUTE + name] = value
        _save_mat(path, contents)
        return
    import h5py

    with h5py.File(path, "r+") as handle:
        handle.attrs[name] = value


def _attributes(path: Path) -> dict[str, Any]:
    """The attributes of an HDF5 file, or the ``attr_`` variables of a ``.mat`` file (plain)."""
    if path.suffix == ".mat":
        return {
            name[len(MAT_ATTRIBUTE) :]: str(np.asarray(value).ravel()[0])
            for name, value in _load_mat(path).items()
            if name.startswith(MAT_ATTRIBUTE) and np.asarray(value).dtype.kind == "U"
        }
    import h5py

    with h5py.File(path, "r") as handle:
        return dict(handle.attrs)


def bogus_kind(path: Path, draw: Any) -> str:
    """Set the file's ``kind`` to a kind no reader knows."""
    value = draw(st.sampled_from(["bogus", "", "DH"]))
    _set_attribute(path, "kind", value)
    return f"kind set to {value!r}"


def break_json(path: Path, draw: Any) -> str:
    """Cut one ``*_json`` attribute short, so that it no longer parses."""
    attributes = _attributes(path)
    name = draw(st.sampled_from(sorted(n for n in attributes if n.endswith("_json"))))
    text = str(attributes[name])
    cut = draw(st.integers(min_value=1, max_value=max(1, len(text) - 1)))
    broken = text[:cut]
    try:
        json.loads(broken)
    except ValueError:
        pass
    else:  # a cut that still parses ("{}" has none that do; "[1, 2]" -> "[1" does not)
        broken = text + "}"
    _set_attribute(path, name, broken)
    return f"attribute {name!r} cut to {broken!r}"


def negative_count(path: Path, draw: Any) -> str:
    """Set a data set's run count ``N`` to a negative number."""
    value = draw(st.sampled_from([-3, -1]))
    _set_attribute(path, "N", np.int64(value))
    return f"N set to {value}"


def _bad_number(draw: Any) -> float:
    return float(draw(st.sampled_from([np.nan, np.inf, -np.inf])))


def inject_h5_nonfinite(path: Path, draw: Any) -> str:
    """Write a NaN or an infinity into one sample of a series (one run's, in a data set)."""
    import h5py

    value = _bad_number(draw)
    with h5py.File(path, "r+") as handle:
        names = [name for name in SERIES if name in handle]
        name = draw(st.sampled_from(names))
        dset = handle[name]
        run = ()
        if "N" in handle.attrs:  # a data set: one row per run
            run = (draw(st.integers(min_value=0, max_value=dset.shape[0] - 1)),)
        data = np.array(dset[run])
        index = draw(st.integers(min_value=0, max_value=data.size - 1))
        data.flat[index] = value
        dset[run] = data
    where = f"run {run[0]} " if run else ""
    return f"{value} written into {where}{name!r} at flat index {index}"


def inject_mat_nonfinite(path: Path, draw: Any) -> str:
    """Write a NaN or an infinity into one sample of a series of a ``.mat`` file."""
    value = _bad_number(draw)
    contents = _load_mat(path)
    name = draw(st.sampled_from([n for n in SERIES if n in contents]))
    data = np.array(contents[name], dtype=float)
    index = draw(st.integers(min_value=0, max_value=data.size - 1))
    data.flat[index] = value
    contents[name] = data
    _save_mat(path, contents)
    return f"{value} written into {name!r} at flat index {index}"


def damage_chunk(path: Path, array: str, run: int) -> None:
    """Invert 16 bytes in the middle of run ``run``'s chunk of a data set's ``array`` (its
    compressed data no longer inflates)."""
    import h5py

    with h5py.File(path, "r") as handle:
        dset = handle[array]
        info = dset.id.get_chunk_info_by_coord((run,) + (0,) * (dset.ndim - 1))
    _flip(path, info.byte_offset + info.size // 2, min(16, info.size // 2))


def damage_run(path: Path, draw: Any) -> tuple[int, str]:
    """Damage one drawn run of a data set: inverted bytes in its chunk of a series, or a NaN
    or infinity written into it. Returns the run and what was done."""
    import h5py

    with h5py.File(path, "r") as handle:
        runs = handle["tau"].shape[0]
    run = draw(st.integers(0, runs - 1))
    array = draw(st.sampled_from(SERIES))
    if draw(st.booleans()):
        damage_chunk(path, array, run)
        return run, f"inverted bytes in run {run}'s chunk of {array!r}"
    value = _bad_number(draw)
    with h5py.File(path, "r+") as handle:
        rows = np.array(handle[array][run])
        index = draw(st.integers(0, rows.size - 1))
        rows.flat[index] = value
        handle[array][run] = rows
    return run, f"{value} written into run {run}'s {array!r} at flat index {index}"


H5_MUTATORS: dict[str, Mutator] = {
    "truncate": truncate,
    "flip_bytes": flip_h5_data,
    "delete_array": delete_h5_array,
    "array_layout": relayout_h5_array,
    "attribute_type": retype_h5_attribute,
    "bogus_kind": bogus_kind,
    "broken_json": break_json,
    "nonfinite": inject_h5_nonfinite,
}

MUTATORS: dict[str, dict[str, Mutator]] = {
    "h5": H5_MUTATORS,
    "mat": {
        "truncate": truncate,
        "flip_bytes": flip_mat_data,
        "delete_array": delete_mat_variable,
        "array_layout": relayout_mat_variable,
        "attribute_type": retype_mat_attribute,
        "bogus_kind": bogus_kind,
        "broken_json": break_json,
        "nonfinite": inject_mat_nonfinite,
    },
    "dataset": {**H5_MUTATORS, "negative_count": negative_count},
}
"""The mutators that apply to each file format, by name."""
