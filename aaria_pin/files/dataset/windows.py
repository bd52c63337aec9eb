"""Fixed-length windows of a data set as a map-style dataset for training, and splits by run.

:meth:`DatasetReader.windows <aaria_pin.files.dataset.reader.DatasetReader.windows>` makes a
:class:`WindowDataset`: ``len(ds)`` windows, ``ds[i]`` one window as a dict of NumPy arrays. It
is what PyTorch's ``DataLoader`` takes as it is, with worker processes (aaria_pin never imports
torch): it pickles as its path and a few numbers, and each process opens the file itself, on
its first read (a forked or unpickled copy notices the new process id and reopens). Windows are
read with plain h5py slices of the stored arrays by name, so a data set whose arrays are HDF5
virtual datasets (a manifest over shard files) reads the same way; a view is put together from
its series' windows (see :class:`WindowDataset`).

Window ``i`` is found by arithmetic: every run has T samples, so every complete run of the split
has ``(T - length) // stride + 1`` windows, and ``i`` is window ``i % W`` of the split's run
``i // W``; nothing per window is kept, whatever their number.

Names may be stored arrays, views or labels (:mod:`.labels`: ``link_types``, ``empty_mask``,
computed from the stored DH table when a run is read). Normalisation is per name
(:mod:`.normalisation`: all but the labels, none, or some names, the others raw; with the
stored training statistics or statistics held in memory). A window may be a whole run
(``length=None`` in the readers). Each process keeps the last few runs it read whole
(:attr:`WindowDataset.cache_runs`), so a shuffled epoch ordered by
:class:`~.sampler.RunBlockSampler` reads each run once.

**Splits by run** (:func:`split_runs`): the runs, complete or not, are ordered by a key drawn
for each run, run k's key being the k-th raw 64-bit output of NumPy's ``PCG64(seed)`` bit
generator (a stream NumPy means to keep fixed across versions; ties, of odds about N² / 2⁶⁵,
keep run order); of that order the first ``round(f_train · N)`` runs are the training split,
the runs up to ``round((f_train + f_validation) · N)`` the validation split, the rest the test
split (``round`` rounds halves up). The assignment is a function of ``(seed, fractions, N)``
alone, so no run is in two splits, the three cover every run, and a run keeps its split when a
resumed data set completes more runs; incomplete runs are then left out of every split.
"""

from __future__ import annotations

import math
import os
from collections import OrderedDict
from collections.abc import Collection, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.record import ColumnView
from aaria_pin.errors import ParameterError
from aaria_pin.files.dataset.labels import LABELS, derive_labels, label_sources
from aaria_pin.files.dataset.normalisation import Statistics, normalised
from aaria_pin.files.dataset.verify import RunCheck

__all__ = [
    "DEFAULT_CACHE_RUNS",
    "DEFAULT_FRACTIONS",
    "SPLITS",
    "WindowCut",
    "WindowDataset",
    "WindowSplit",
    "WindowedRuns",
    "check_cut",
    "check_fractions",
    "cut_windows",
    "run_items",
    "split_runs",
    "view_sources",
]

SPLITS = ("train", "validation", "test")
"""The splits by run, in the order of their fractions."""
DEFAULT_FRACTIONS = (0.8, 0.1, 0.1)
"""Fractions of the runs in the training, validation and test splits."""

DEFAULT_CACHE_RUNS = 8
"""Whole runs a :class:`WindowDataset` keeps read in each process (the latest used)."""


def check_fractions(fractions: Sequence[float]) -> tuple[float, float, float]:
    """Three fractions (train, validation, test), each in [0, 1], summing to 1.

    Raises:
        ParameterError: another count, a negative or non-finite one, or a sum other than 1.
    """
    values = tuple(float(f) for f in fractions)
    if (
        len(values) != len(SPLITS)
        or not all(math.isfinite(f) and 0.0 <= f <= 1.0 for f in values)
        or abs(sum(values) - 1.0) > 1e-9
    ):
        raise ParameterError(
            parameter="fractions",
            value=values,
            allowed="three fractions (train, validation, test) in [0, 1] summing to 1",
        )
    return values[0], values[1], values[2]


def check_cut(length: int | None, stride: int | None, samples: int) -> tuple[int, int]:
    """Check a window length and stride against the samples per run: ``(length, stride)``.

    Args:
        length: samples per window, or None: the whole run (one window a run)
        stride: samples between window starts (None: the length)
        samples: samples per run T

    Raises:
        ParameterError: a length outside [1, samples], a stride below 1.
    """
    length = samples if length is None else length
    stride = length if stride is None else stride
    if not 1 <= length <= samples:
        raise ParameterError(
            parameter="length",
            value=length,
            allowed=f"1 to {samples} (samples per run), or None (whole runs)",
        )
    if stride < 1:
        raise ParameterError(parameter="stride", value=stride, allowed="an integer >= 1")
    return length, stride


def split_runs(
    n_runs: int, split: str, seed: int = 0, fractions: Sequence[float] = DEFAULT_FRACTIONS
) -> np.ndarray:
    """The runs of one split, complete or not, in increasing order (see the module docstring).

    Args:
        n_runs: runs in the data set N
        split: ``"train"``, ``"validation"`` or ``"test"``
        seed: the split's seed (a non-negative integer; not the data set's seed)
        fractions: of the N runs in the training, validation and test splits

    Returns:
        The run indices (int64).

    Raises:
        ParameterError: an unknown split, a negative seed, or bad fractions.
    """
    if split not in SPLITS:
        raise ParameterError(parameter="split", value=split, allowed=", ".join(SPLITS) + ", None")
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise ParameterError(parameter="seed", value=seed, allowed="an integer >= 0")
    train, validation, _ = check_fractions(fractions)
    keys = np.random.PCG64(int(seed)).random_raw(n_runs)
    order = np.argsort(keys, kind="stable")
    cuts = [0, math.floor(train * n_runs + 0.5), math.floor((train + validation) * n_runs + 0.5)]
    cuts.append(n_runs)
    at = SPLITS.index(split)
    return np.sort(order[cuts[at] : cuts[at + 1]]).astype(np.int64)


def view_sources(names: Sequence[str], views: Mapping[str, ColumnView]) -> tuple[str, ...]:
    """The stored arrays to read for some names: a view's series (``time`` first), else the name.

    Args:
        names: arrays or views
        views: the views among them, by name
    """
    needed: dict[str, None] = {}
    for name in names:
        if name in views:
            needed.update({"time": None})
            needed.update({source.array: None for source in views[name].sources})
        else:
            needed[name] = None
    return tuple(needed)


def run_items(
    names: Sequence[str],
    views: Mapping[str, ColumnView],
    stored: Mapping[str, np.ndarray],
    statistics: Statistics | None = None,
) -> dict[str, np.ndarray]:
    """The names' arrays of one run from its stored arrays: labels, views, normalisation.

    Args:
        names: arrays, views or labels
        views: the views among the names, by name (put together from their series)
        stored: the run's stored arrays by name (over some samples; constants whole), the
            names' sources among them (:func:`view_sources` of :func:`~.labels.label_sources`)
        statistics: per-channel ``(mean, std)`` of the names to normalise, or None
    """
    labels = derive_labels(names, stored)
    items = {
        name: labels[name]
        if name in labels
        else views[name].materialise(stored)
        if name in views
        else stored[name]
        for name in names
    }
    for name, (mean, std) in (statistics or {}).items():
        items[name] = normalised(items[name], mean, std)
    return items


def cut_windows(
    items: Mapping[str, np.ndarray],
    constant: Collection[str],
    length: int,
    stride: int,
    samples: int,
) -> Iterator[tuple[int, dict[str, np.ndarray]]]:
    """The windows of one whole run, in order: ``(start, {name: window})``.

    Args:
        items: the run's arrays by name (:func:`run_items` of the whole run)
        constant: the names without a time axis (per-run constants, labels): given whole
        length: samples per window
        stride: samples between window starts
        samples: samples of the run T (``(T - length) // stride + 1`` windows)
    """
    for start in range(0, (samples - length) // stride * stride + 1, stride):
        window = slice(start, start + length)
        yield (
            start,
            {name: array if name in constant else array[window] for name, array in items.items()},
        )


@dataclass(frozen=True)
class WindowCut:
    """How a data set's runs are cut into windows.

    Attributes:
        length: samples per window
        stride: samples between window starts
        names: arrays or views to give
        views: the file's views, by name (those among the names are assembled from their series)
        constants: the stored arrays without a time axis (per-run constants)
        samples: samples per run T
    """

    length: int
    stride: int
    names: Sequence[str]
    views: Mapping[str, ColumnView]
    constants: Collection[str]
    samples: int


@dataclass(frozen=True)
class WindowSplit:
    """The runs a window dataset cuts, and the split they are.

    Attributes:
        runs: the runs to cut (complete, increasing)
        split: the split they are (None: every complete run)
        seed: the split's seed
        fractions: the split's fractions
    """

    runs: np.ndarray
    split: str | None = None
    seed: int = 0
    fractions: Sequence[float] = DEFAULT_FRACTIONS


class WindowedRuns:
    """What a window dataset cuts: the runs, their windows, the names and their normalisation.

    The part :class:`WindowDataset` (over a file) and ``aaria_pin.ml.OnlineWindows`` (over runs
    simulated on demand) have in common, made from the same three values.

    Args:
        cut: how the runs are cut (window length, stride, names; the views, constants and
            samples per run)
        split: the runs to cut and the split they are
        statistics: per-channel ``(mean, std)`` of the names to normalise (the others raw), or
            None

    Attributes:
        length, stride, names, samples, runs, split, seed, fractions, statistics: as given
        windows_per_run: windows of one run W
    """

    def __init__(
        self, cut: WindowCut, split: WindowSplit, statistics: Statistics | None = None
    ) -> None:
        self.length = int(cut.length)
        self.stride = int(cut.stride)
        self.names = tuple(cut.names)
        self._views = {name: cut.views[name] for name in self.names if name in cut.views}
        self._sources = view_sources(label_sources(self.names), self._views)
        self._whole = frozenset(cut.constants) | frozenset(LABELS)  # no time axis: given whole
        self.samples = int(cut.samples)
        self.runs = np.asarray(split.runs, dtype=np.int64)
        self.split = split.split
        self.seed = int(split.seed)
        self.fractions = tuple(float(f) for f in split.fractions)
        self.statistics = dict(statistics) if statistics is not None else None
        self.windows_per_run = (self.samples - self.length) // self.stride + 1

    def __len__(self) -> int:
        return len(self.runs) * self.windows_per_run


class WindowDataset(WindowedRuns):
    """Fixed-length windows over the complete runs of a data set (or of one split of its runs).

    Made by :meth:`DatasetReader.windows
    <aaria_pin.files.dataset.reader.DatasetReader.windows>`, which checks the arguments.

    ``ds[i]`` is a dict: each name's window (``length × …`` of a time series, the whole per-run
    array of a constant one such as ``senSenDH`` or ``imu_mount``, or of a label such as
    ``link_types``, see :mod:`.labels`), plus ``run`` and ``start`` (0-d int64 arrays: the run
    and the window's first sample). Iterating gives the same windows in the same order as
    ``(run, start, {name: window})``, reading each run once.

    **Read cache**: each process keeps the stored arrays of the last :attr:`cache_runs` runs it
    read, whole (a run is one HDF5 chunk: reading one window decompresses the whole run anyway),
    and cuts windows from them in memory; ``ds.cache_runs = 0`` reads each window from the file.
    A shuffled epoch reads each run once when consecutive windows come from a few runs at a
    time: :class:`~.sampler.RunBlockSampler` orders them so (its docstring has the figures).

    A view of a version 2 file (``senSen``, ``signals``) is put together from its series'
    windows (:meth:`ColumnView.materialise <aaria_pin.core.record.ColumnView.materialise>`),
    the same numbers as the file's virtual dataset gives: reading ``time``, ``q`` and ``imu``
    and copying columns took 1.0 ms a random 200-sample ``senSen`` window where h5py's read of
    the virtual dataset took 2.2 ms (0.38 against 1.41 ms in run order; 200 runs of 1,001
    samples, one core).

    Args:
        path: the data set file
        cut: how the runs are cut (window length, stride, names; the file's views, constants
            and samples per run)
        split: the runs to cut and the split they are
        statistics: per-channel ``(mean, std)`` of the names to normalise (the others raw), or
            None
        check: how runs are checked as they are read (:class:`~.verify.RunCheck`: each run's
            arrays read whole, finite and verified against their checksums once per process);
            None reads them as stored, errors made one line

    Attributes:
        path, length, stride, names, runs, split, seed, fractions, statistics: as given
        windows_per_run: windows of one run W
        cache_runs: whole runs kept read in each process (default :data:`DEFAULT_CACHE_RUNS`)
    """

    def __init__(
        self,
        path: str | os.PathLike[str],
        cut: WindowCut,
        split: WindowSplit,
        statistics: Statistics | None = None,
        check: RunCheck | None = None,
    ) -> None:
        super().__init__(cut, split, statistics)
        self.path = Path(path).resolve()  # a pickled copy may run in another folder
        self._constant = tuple(name in self._whole for name in self._sources)
        self._check = check if check is not None else RunCheck(self.path, 0)
        self._handle: Any = None
        self._datasets: list[Any] = []
        self._pid = -1
        self.cache_runs = DEFAULT_CACHE_RUNS
        self._cache: OrderedDict[int, dict[str, np.ndarray]] = OrderedDict()

    def _arrays(self) -> list[Any]:
        """The stored h5py datasets to read, opened in this process (again after a fork)."""
        if self._handle is None or self._pid != os.getpid():
            import h5py

            self._handle = h5py.File(self.path, "r")
            self._datasets = [self._handle[name] for name in self._sources]
            self._pid = os.getpid()
        return self._datasets

    def locate(self, index: int) -> tuple[int, int]:
        """Run and first sample of window ``index`` (negative counts from the end).

        Raises:
            IndexError: ``index`` outside ``[-len, len)``.
        """
        count = len(self)
        if not -count <= index < count:
            raise IndexError(f"window {index} of {count}")
        index %= count
        run, window = divmod(index, self.windows_per_run)
        return int(self.runs[run]), window * self.stride

    def _read(self, run: int, samples: slice) -> dict[str, np.ndarray]:
        """The names' arrays of one run over some samples (constants whole), normalised."""
        return run_items(self.names, self._views, self._run_arrays(run, samples), self.statistics)

    def _run_arrays(self, run: int, samples: slice) -> dict[str, np.ndarray]:
        """The stored arrays of one run over some samples (constants whole), from the cache."""
        sources = zip(self._sources, self._constant, self._arrays(), strict=True)
        if self.cache_runs < 1:
            return {
                name: self._stored(dataset, name, run, slice(None) if constant else samples)
                for name, constant, dataset in sources
            }
        whole = self._cache.get(run)
        if whole is None:
            whole = {
                name: self._stored(dataset, name, run, slice(None)) for name, _, dataset in sources
            }
            self._cache[run] = whole
            while len(self._cache) > self.cache_runs:
                self._cache.popitem(last=False)
        else:
            self._cache.move_to_end(run)
        # copies: a caller changing a window in place must not change the cached run
        return {
            name: whole[name].copy() if constant else whole[name][samples].copy()
            for name, constant in zip(self._sources, self._constant, strict=True)
        }

    def _stored(self, dataset: Any, name: str, run: int, samples: slice) -> np.ndarray:
        """A stored array of a run over some samples; the run's whole array checked once.

        The first read of an array of a run in this process reads it whole, checks that it is
        finite and verifies it against its checksum (:class:`~.verify.RunCheck`); later reads
        read only the samples asked for (their errors still ours).
        """
        check = self._check
        if check.n_runs and not check.is_checked(name, run):
            return check.checked(self._handle, name, run, dataset)[samples]
        return check.read(dataset, name, run, None if samples == slice(None) else samples)

    def __getitem__(self, index: int) -> dict[str, np.ndarray]:
        run, start = self.locate(int(index))
        items = self._read(run, slice(start, start + self.length))
        items["run"] = np.asarray(run, dtype=np.int64)
        items["start"] = np.asarray(start, dtype=np.int64)
        return items

    def __iter__(self) -> Iterator[tuple[int, int, dict[str, np.ndarray]]]:
        for run in self.runs:
            arrays = self._read(int(run), slice(None))
            cut = cut_windows(arrays, self._whole, self.length, self.stride, self.samples)
            for start, window in cut:
                yield int(run), start, window

    def close(self) -> None:
        """Close this process's handle on the file (the next read reopens it)."""
        if self._handle is not None and self._pid == os.getpid():
            self._handle.close()
        self._handle, self._datasets, self._pid = None, [], -1
        self._cache.clear()

    def __getstate__(self) -> dict[str, Any]:
        state = dict(self.__dict__)
        state.update(_handle=None, _datasets=[], _pid=-1, _cache=OrderedDict())
        return state

    def __repr__(self) -> str:
        return (
            f"WindowDataset({str(self.path)!r}, length={self.length}, stride={self.stride}, "
            f"names={self.names}, split={self.split!r}, runs={len(self.runs)}, "
            f"windows={len(self)}, normalised={tuple(self.statistics or ())})"
        )
