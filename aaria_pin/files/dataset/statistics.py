"""Per-channel normalisation statistics of a data set's arrays: computed in one pass, stored in it.

:func:`channel_statistics` reads the chosen runs a block at a time (about
:data:`BLOCK_BYTES` of float64 per array per block) and merges each block's count, mean and
sum of squared deviations into the running ones (Chan, Golub and LeVeque's pairwise update), in
float64: one pass over the data, memory bounded by the block, and no cancellation of the naive
``E[x²] - E[x]²``. The std is the population one (``ddof=0``, as ``numpy.std``). A time series
is reduced over its runs and samples (channel shape: one sample's, e.g. ``(91,)`` for
``senSen``, ``(S, 6)`` for ``imu``); a per-run constant array (a table, the IMU mounts) over its
runs (channel shape: the array's). A view (``senSen``, ``signals``) is not read: its statistics
are gathered from those of its series (:func:`view_statistics`), the same numbers.

Stored (:func:`store_statistics`) in the data set as ``statistics/<split>/<name>/mean`` and
``.../std`` (float64) with attributes ``split``, ``seed``, ``fractions`` and ``runs`` (the
number of runs) on the split's group, ``count`` (samples per channel) on each name's group. The
new group is written under a temporary name and then moved over the old one, so a reader sees
either the old statistics or the new, and the file's other objects are not rewritten (HDF5 adds
the new objects and updates the ``statistics`` group's index).
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.record import ColumnView
from aaria_pin.errors import InputFileError, OutputFileError
from aaria_pin.files._space import (
    METADATA_BYTES,
    check_space,
    close_hdf5,
    no_space,
    no_space_error,
    spare_room,
)
from aaria_pin.files.dataset.verify import RunCheck
from aaria_pin.files.dataset.windows import WindowCut, check_fractions, view_sources
from aaria_pin.files.paths import write_failure

__all__ = [
    "BLOCK_BYTES",
    "STATISTICS_GROUP",
    "channel_statistics",
    "names_statistics",
    "read_statistics",
    "store_statistics",
    "training_statistics",
    "view_statistics",
]

STATISTICS_GROUP = "statistics"
"""The group of a data set file holding the stored statistics, one subgroup per split."""
BLOCK_BYTES = 64 * 2**20
"""About how many float64 bytes of one array a block of runs holds while it is reduced."""

_ALL_RUNS = "all"

_ENTRY_BYTES = 8192
"""The HDF5 metadata of one array's stored statistics, at most [bytes] (a group, two datasets,
an attribute)."""
"""The subgroup of statistics over every complete run (no split)."""


def _merge(
    total: tuple[int, np.ndarray, np.ndarray], part: tuple[int, np.ndarray, np.ndarray]
) -> tuple[int, np.ndarray, np.ndarray]:
    """Count, mean and sum of squared deviations of two parts together (Chan et al. 1979)."""
    n_a, mean_a, m2_a = total
    n_b, mean_b, m2_b = part
    if n_a == 0:
        return part
    n = n_a + n_b
    delta = mean_b - mean_a
    return n, mean_a + delta * (n_b / n), m2_a + m2_b + delta**2 * (n_a * n_b / n)


def channel_statistics(
    handle: Any,
    names: Sequence[str],
    series: Sequence[bool],
    runs: np.ndarray,
    check: RunCheck | None = None,
    block_bytes: int = BLOCK_BYTES,
) -> dict[str, tuple[np.ndarray, np.ndarray, int]]:
    """Per-channel mean, std and count of arrays over some runs, in one streaming pass.

    Args:
        handle: the open h5py file of the data set
        names: arrays or views (N × … each)
        series: for each name, whether axis 1 is time (reduced too) or part of the channel
        runs: the runs, increasing (complete ones)
        check: how each run's array is read and checked (:class:`~.verify.RunCheck`: damaged
            runs and NaN refused); None reads them as stored
        block_bytes: float64 bytes of one array a block of runs may hold

    Returns:
        ``{name: (mean, std, count)}``, mean and std float64 of the channel shape, count the
        values per channel.

    Raises:
        InputFileError: with ``check``, a damaged run or one holding a NaN or an infinity.
    """
    result: dict[str, tuple[np.ndarray, np.ndarray, int]] = {}
    runs = np.asarray(runs, dtype=np.int64)
    for name, is_series in zip(names, series, strict=True):
        dataset = handle[name]
        channel = dataset.shape[2:] if is_series else dataset.shape[1:]
        run_values = int(np.prod(dataset.shape[1:], dtype=np.int64)) * 8
        per_block = max(1, block_bytes // max(run_values, 1))
        total: tuple[int, np.ndarray, np.ndarray] = (0, np.zeros(channel), np.zeros(channel))
        for first in range(0, len(runs), per_block):
            block = runs[first : first + per_block]
            stored = np.empty((len(block), *dataset.shape[1:]), dtype=dataset.dtype)
            for row, run in enumerate(block):  # a run a read: h5py's list index took 3x longer
                stored[row] = (
                    dataset[int(run)] if check is None else check.checked(handle, name, int(run))
                )
            values = stored.astype(np.float64).reshape(-1, *channel)
            mean = values.mean(axis=0)
            m2 = ((values - mean) ** 2).sum(axis=0)
            total = _merge(total, (values.shape[0], mean, m2))
        count, mean, m2 = total
        std = np.sqrt(m2 / count) if count else np.full(channel, np.nan)
        result[name] = (mean if count else np.full(channel, np.nan), std, count)
    return result


def view_statistics(
    view: ColumnView, statistics: Mapping[str, tuple[np.ndarray, np.ndarray, int]]
) -> tuple[np.ndarray, np.ndarray, int]:
    """A view's statistics gathered from those of its series (its columns are their columns).

    Args:
        view: the view
        statistics: ``{series: (mean, std, count)}`` of every series the view refers to

    Returns:
        ``(mean, std, count)``, mean and std of shape ``(C,)``.
    """
    mean = np.array([statistics[s.array][0][s.index] for s in view.sources], dtype=np.float64)
    std = np.array([statistics[s.array][1][s.index] for s in view.sources], dtype=np.float64)
    return mean, std, statistics[view.sources[0].array][2]


def names_statistics(
    handle: Any, cut: WindowCut, runs: np.ndarray, check: RunCheck | None = None
) -> dict[str, tuple[np.ndarray, np.ndarray, int]]:
    """Per-channel mean, std and count of arrays and views over some runs (see the module).

    Args:
        handle: the open h5py file of the data set
        cut: the names, the file's views and its per-run constants (length, stride and samples
            unused)
        runs: the runs, increasing (complete ones)
        check: how each run's array is read and checked (see :func:`channel_statistics`)
    """
    views = {name: cut.views[name] for name in cut.names if name in cut.views}
    sources = view_sources(cut.names, views)
    series = [name not in cut.constants for name in sources]
    stored = channel_statistics(handle, sources, series, runs, check)
    return {
        name: view_statistics(views[name], stored) if name in views else stored[name]
        for name in cut.names
    }


def _split_group(split: str | None) -> str:
    return f"{STATISTICS_GROUP}/{split or _ALL_RUNS}"


def store_statistics(
    path: str | os.PathLike[str],
    statistics: Mapping[str, tuple[np.ndarray, np.ndarray, int]],
    split: str | None,
    seed: int,
    fractions: Sequence[float],
    runs: int,
) -> None:
    """Store statistics in the data set file (replacing those of the same split).

    Args:
        path: the data set file (opened for writing: no other handle on it may be open)
        statistics: ``{name: (mean, std, count)}``, as :func:`channel_statistics` gives
        split: the split they are of (None: every complete run, stored as ``all``)
        seed: the split's seed
        fractions: the split's fractions
        runs: how many runs they are over

    The statistics are written in place, holding a reserve of the device meanwhile
    (:func:`~aaria_pin.files._space.spare_room`): on a full device the reserve is freed, the
    file closed cleanly (HDF5 left to meet a full device here crashed the process) and the
    stored statistics of the split are kept.

    Raises:
        OutputFileError: the file cannot be opened for writing (read-only, or open elsewhere).
        NoSpaceError: no room on the device (checked first: twice the statistics' bytes and
            their metadata).
    """
    import h5py

    file = Path(path)
    size = sum(2 * np.asarray(mean).nbytes + _ENTRY_BYTES for mean, _, _ in statistics.values())
    with spare_room(file, size + METADATA_BYTES) as free_spare:
        check_space(file, size)
        try:
            handle = h5py.File(file, "r+")
        except OSError as exc:
            raise OutputFileError(
                f"{path}: cannot store statistics in it ({exc}); allowed: a writable data set "
                "that no other handle in this process has open",
                parameter="file",
            ) from None
        try:
            shares = np.asarray(fractions, float)
            _store(
                handle,
                statistics,
                split,
                {"seed": int(seed), "fractions": shares, "runs": int(runs)},
            )
        except BaseException as exc:
            close_hdf5(handle, failed=True, make_room=free_spare)
            if no_space(exc):
                raise no_space_error(file) from None
            raise
        try:
            close_hdf5(handle, failed=False, make_room=free_spare)
        except (OSError, RuntimeError) as exc:
            raise write_failure(file, exc) from None


def _store(
    handle: Any,
    statistics: Mapping[str, tuple[np.ndarray, np.ndarray, int]],
    split: str | None,
    marks: Mapping[str, Any],
) -> None:
    """Write the statistics into the open file (as :func:`store_statistics`), flushed.

    ``marks`` are the split's attributes beside its name (seed, fractions, runs).
    """
    group_name = _split_group(split)
    partial = f"{STATISTICS_GROUP}/.{split or _ALL_RUNS}.partial"
    if partial in handle:
        del handle[partial]
    group = handle.require_group(STATISTICS_GROUP).create_group(partial.split("/")[1])
    group.attrs.update(split=split or _ALL_RUNS, **marks)
    opened = [group]  # closed with the file, not one by one (see store_statistics)
    for name, (mean, std, count) in statistics.items():
        entry = group.create_group(name)
        entry.attrs["count"] = int(count)
        opened.append(entry)
        opened.append(entry.create_dataset("mean", data=np.asarray(mean, np.float64)))
        opened.append(entry.create_dataset("std", data=np.asarray(std, np.float64)))
    handle.flush()
    if group_name in handle:
        del handle[group_name]
    handle.move(partial, group_name)


def read_statistics(
    handle: Any, split: str | None, path: str | os.PathLike[str] = ""
) -> tuple[dict[str, tuple[np.ndarray, np.ndarray]], dict[str, Any]]:
    """Statistics stored in an open data set file for one split.

    Args:
        handle: the open h5py file
        split: the split (None: every complete run)
        path: the file, for messages

    Returns:
        ``({name: (mean, std)}, attributes)``; the attributes are ``split``, ``seed``,
        ``fractions`` (a tuple) and ``runs``.

    Raises:
        InputFileError: no statistics stored for that split.
    """
    group_name = _split_group(split)
    if group_name not in handle:
        raise InputFileError(
            f"{path}: no statistics stored for split {split or _ALL_RUNS!r}; allowed: a split "
            "whose statistics were stored (DatasetReader.statistics(..., store=True))",
            parameter="split",
        )
    group = handle[group_name]
    attributes = {
        "split": str(group.attrs["split"]),
        "seed": int(group.attrs["seed"]),
        "fractions": tuple(float(f) for f in group.attrs["fractions"]),
        "runs": int(group.attrs["runs"]),
    }
    values = {name: (entry["mean"][()], entry["std"][()]) for name, entry in group.items()}
    return values, attributes


def training_statistics(
    handle: Any,
    path: str | os.PathLike[str],
    names: Sequence[str],
    seed: int,
    fractions: Sequence[float],
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Stored training statistics of some names, checked to be of the windows' split.

    Args:
        handle: the open h5py file of the data set
        path: the file, for messages
        names: the names to normalise (only these need stored statistics)
        seed: the windows' split seed
        fractions: the windows' split fractions

    Returns:
        ``{name: (mean, std)}`` of the names (none: ``{}``, nothing read).

    Raises:
        InputFileError: no training statistics stored, stored for another seed or fractions,
            or none stored for one of the names (named).
    """
    if not names:
        return {}
    values, attributes = read_statistics(handle, "train", path)
    wanted = (int(seed), tuple(float(f) for f in check_fractions(fractions)))
    if (attributes["seed"], attributes["fractions"]) != wanted:
        raise InputFileError(
            f"{path}: statistics stored for split seed {attributes['seed']}, fractions "
            f"{attributes['fractions']}; allowed: those of the windows (seed {wanted[0]}, "
            f"fractions {wanted[1]}): store them again with these",
            parameter="normalise",
        )
    missing = [name for name in names if name not in values]
    if missing:
        raise InputFileError(
            f"{path}: no training statistics stored for {missing[0]!r}; allowed: "
            f"{', '.join(values)} (store them with DatasetReader.statistics)",
            parameter="normalise",
        )
    return {name: values[name] for name in names}
