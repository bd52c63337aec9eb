"""Joint trajectory files: a user's own motion as time and one column per joint.

Three formats, by suffix:

- **CSV** (``.csv``, ``.txt``): comma separated, ``#`` comment lines; a header line
  ``time,<joint>,...`` and optionally ``qd_<joint>`` and ``qdd_<joint>`` columns (for every
  joint, in any order after time); one row per sample.
- **NPY** (``.npy``): a T × (1 + n) array, time in column 0 and one joint per column.
- **HDF5** (``.h5``, ``.hdf5``): datasets ``time`` (T) and ``q`` (T × n), optionally ``qd``,
  ``qdd`` (T × n) and ``joint_names`` (n strings); a run file is one.

:func:`read_trajectory_file` checks the structure (shapes, names, finite numbers, strictly
increasing times) and refuses a bad file with one line naming the file and what is allowed;
:func:`aaria_pin.core.sampled_motion.trajectory_from_samples` turns what it returns into a
trajectory on a run's time grid.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from aaria_pin.core.se3 import Array
from aaria_pin.errors import InputFileError
from aaria_pin.files._stored import first_line
from aaria_pin.files.io import existing_input, numeric_array, read_csv_table, read_table

__all__ = ["TRAJECTORY_SUFFIXES", "TrajectorySamples", "read_trajectory_file"]

TRAJECTORY_SUFFIXES = (".csv", ".txt", ".npy", ".h5", ".hdf5")
"""Suffixes of the trajectory files read."""

TrajectorySamples = tuple[Array, Array, Array | None, Array | None, tuple[str, ...] | None]
"""``(time, q, qd or None, qdd or None, joint names or None)``: (T,), (T, n) ×3, n names."""


def _fail(file: Path, what: str, allowed: str) -> InputFileError:
    """An error of the trajectory file (``parameter="file"``: an input, see ``existing_input``)."""
    return InputFileError(
        f"{file}: {what}; allowed: {allowed}", parameter="file", allowed=allowed, element=str(file)
    )


def _read_csv(file: Path) -> TrajectorySamples:
    """A CSV trajectory: the table reader's numbers, its columns taken by the header's names."""
    allowed_header = "a header line time,<joint>,... (optionally qd_<joint>, qdd_<joint>)"
    try:
        table, cells = read_csv_table(file)
    except InputFileError:
        raise
    except (OSError, ValueError) as exc:
        raise _fail(file, f"cannot be read ({first_line(exc)})", "a UTF-8 CSV file") from None
    if cells is None:
        raise _fail(file, "has no header line", allowed_header)
    header = [name.strip() for name in cells]
    if header[0] != "time" or len(header) < 2 or any(not name for name in header):
        raise _fail(file, f"header is {','.join(cells)!r}", allowed_header)
    if len(set(header)) != len(header):
        raise _fail(file, "header repeats a column", "each column named once")
    if table.shape[1] != len(header):
        raise _fail(file, f"rows have {table.shape[1]} values", f"{len(header)} per row")
    joints = [n for n in header[1:] if not n.startswith(("qd_", "qdd_"))]
    if not joints:
        raise _fail(file, "header names no joint", allowed_header)
    derivative_columns: dict[str, list[int] | None] = {}
    for prefix in ("qd_", "qdd_"):
        named = [n for n in header[1:] if n.startswith(prefix)]
        if not named:
            derivative_columns[prefix] = None
            continue
        if sorted(named) != sorted(prefix + j for j in joints):
            raise _fail(
                file,
                f"{prefix}<joint> columns are {', '.join(named)}",
                f"none, or one for every joint ({', '.join(prefix + j for j in joints)})",
            )
        derivative_columns[prefix] = [header.index(prefix + j) for j in joints]
    q = table[:, [header.index(j) for j in joints]]
    qd, qdd = (
        None if columns is None else table[:, columns]
        for columns in (derivative_columns["qd_"], derivative_columns["qdd_"])
    )
    return table[:, 0], q, qd, qdd, tuple(joints)


def _read_npy(file: Path) -> TrajectorySamples:
    """An NPY trajectory: the table reader's T × (1 + n) table, time in column 0."""
    array = read_table(file)
    if array.shape[1] < 2:
        raise _fail(
            file, f"holds an array of shape {array.shape}", "a numeric T × (1 + n) array, n >= 1"
        )
    return array[:, 0].copy(), array[:, 1:].copy(), None, None, None


def _read_h5(file: Path) -> TrajectorySamples:
    import h5py

    try:
        handle = h5py.File(file, "r")
    except OSError as exc:
        raise _fail(file, f"cannot be read ({exc})", "an HDF5 file") from None
    with handle:
        arrays: dict[str, Array | None] = {}
        for name in ("time", "q", "qd", "qdd"):
            item = handle.get(name)
            if item is None:
                if name in ("time", "q"):
                    raise _fail(file, f"has no dataset {name!r}", "datasets time and q")
                arrays[name] = None
                continue
            if not isinstance(item, h5py.Dataset):
                raise _fail(file, f"{name!r} is not a numeric dataset", "numeric datasets")
            arrays[name] = numeric_array(file, item[()], name)  # the table reader's rule
        names: tuple[str, ...] | None = None
        if "joint_names" in handle:
            stored = np.asarray(handle["joint_names"][()]).reshape(-1)
            names = tuple(x.decode() if isinstance(x, bytes) else str(x) for x in stored)
    time, q = np.asarray(arrays["time"]), np.asarray(arrays["q"])  # both present: checked
    if q.ndim == 1:
        q = q[:, None]
    time = time.reshape(-1) if time.ndim == 2 and 1 in time.shape else time
    for name in ("qd", "qdd"):
        value = arrays[name]
        if value is not None and value.ndim == 1:
            arrays[name] = value[:, None]
    if names is not None and len(names) != q.shape[-1]:
        raise _fail(file, f"has {len(names)} joint_names", f"{q.shape[-1]}, one per column of q")
    return time, q, arrays["qd"], arrays["qdd"], names


def read_trajectory_file(path: str | os.PathLike[str]) -> TrajectorySamples:
    """Read a joint trajectory from a CSV, NPY or HDF5 file (module docstring: the formats).

    Args:
        path: the file

    Returns:
        ``(time, q, qd, qdd, joint_names)``: time (T,) [s], q (T, n) [rad or m], qd and qdd
        (T, n) or None when the file has none, the joint names or None (NPY).

    Raises:
        InputFileError: an unknown suffix, no such file, or a file that cannot be read or
            holds no valid trajectory (wrong header or shape, fewer than 2 samples, values not
            finite, times not strictly increasing), in one line naming the file.
    """
    file = existing_input(path, TRAJECTORY_SUFFIXES, "trajectory")
    suffix = file.suffix.lower()
    if suffix in (".csv", ".txt"):
        time, q, qd, qdd, names = _read_csv(file)
    elif suffix == ".npy":
        time, q, qd, qdd, names = _read_npy(file)
    else:
        time, q, qd, qdd, names = _read_h5(file)
    n_samples = time.shape[0] if time.ndim == 1 else -1
    if n_samples < 2:
        raise _fail(file, f"time has shape {time.shape}", "(T,) with T >= 2 samples")
    for name, value in (("q", q), ("qd", qd), ("qdd", qdd)):
        if value is None:
            continue
        if value.ndim != 2 or value.shape[0] != n_samples or value.shape[1] < 1:
            raise _fail(file, f"{name} has shape {value.shape}", f"({n_samples}, n), n >= 1")
        if value.shape != q.shape:
            raise _fail(file, f"{name} has shape {value.shape}", f"{q.shape}, as q")
        bad = np.argwhere(~np.isfinite(value))
        if bad.size:
            raise _fail(file, f"{name} row {int(bad[0, 0])} is not finite", "finite numbers")
    if not np.all(np.isfinite(time)):
        raise _fail(file, f"time row {int(np.argmax(~np.isfinite(time)))} is not finite", "finite")
    steps = np.diff(time)
    if not np.all(steps > 0):
        row = int(np.argmax(steps <= 0)) + 1
        raise _fail(file, f"time row {row} is {time[row]:g}", "strictly increasing times")
    return time, q, qd, qdd, names
