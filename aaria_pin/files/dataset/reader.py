"""Reading a data set without loading it: one run as a record, raw arrays, windows.

Example::

    from aaria_pin.files.dataset.reader import DatasetReader

    with DatasetReader("ds.h5") as ds:
        print(len(ds), ds.samples, ds.attributes["seed"])
        record = ds.record(3)                     # a RunRecord: record.imu, record.view("senSen")
        arrays = ds.run(3, ("senSen", "tau"))     # stored arrays (and views) as stored
        for run_index, start, window in ds.windows(200, stride=100, names=("senSen", "tau")):
            ...                                   # window["senSen"]: (200, 91)
        stats = ds.statistics(("senSen", "tau"), split="train", store=True)  # mean, std
        train = ds.windows(200, names=("senSen", "tau"), split="train", normalise=True)
    train[0]["senSen"]                            # a map-style dataset (any DataLoader)

Both format versions read: 2 (one layout for every robot, views as HDF5 virtual datasets) and
1, of aaria_pin 0.1 (:mod:`.legacy_datasets`). Only complete runs are read, and checked (damage,
checksums, NaN, attributes); a run is one chunk (a few for poses): a window is one run's read.
"""

from __future__ import annotations

import copy
import os
from collections.abc import Collection, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.arguments import checked
from aaria_pin.core.record import SERIES, ColumnView, RunRecord
from aaria_pin.core.record_checks import check_record, record_source
from aaria_pin.core.se3 import Array
from aaria_pin.errors import InputFileError, ParameterError
from aaria_pin.files._stored import decode_attributes, first_line
from aaria_pin.files.dataset.dataset_record import dataset_record
from aaria_pin.files.dataset.header import DatasetHeader
from aaria_pin.files.dataset.labels import available_labels, derive_labels, label_sources
from aaria_pin.files.dataset.layout import (
    DATASET_FORMAT,
    DATASET_FORMAT_VERSION,
    DatasetLayout,
    read_layout,
)
from aaria_pin.files.dataset.legacy_datasets import LEGACY_VERSION, legacy_names, legacy_record
from aaria_pin.files.dataset.manifest import missing_shards
from aaria_pin.files.dataset.normalisation import (
    GivenStatistics,
    given_statistics,
    normalised_names,
)
from aaria_pin.files.dataset.statistics import (
    names_statistics,
    read_statistics,
    store_statistics,
    training_statistics,
)
from aaria_pin.files.dataset.verify import READ_ERRORS, check_arrays, run_check
from aaria_pin.files.dataset.windows import (
    DEFAULT_FRACTIONS,
    WindowCut,
    WindowDataset,
    WindowSplit,
    check_cut,
    check_fractions,
    split_runs,
    view_sources,
)

__all__ = ["DatasetReader"]


@checked
class DatasetReader:
    """A data set file opened for reading.

    Args:
        path: the data set's ``.h5`` file (format version 1 or 2)

    Attributes:
        path: the file
        version: its format version
        header: its attributes, read once (:class:`~aaria_pin.files.dataset.header.DatasetHeader`)
        complete: which runs are complete (N booleans)
        names: what :meth:`run` reads, in file order: the stored per-run arrays, then (version
            2) the views
        layout: the fixed per-run layout (version 2; None for version 1)

    Raises:
        InputFileError: missing, unreadable, not a data set, of an unknown version, or
            damaged: an attribute of the wrong type, an array missing or of the wrong shape
            (``parameter="file"``). A run's own damage is found when it is read (see
            :mod:`.verify`).
    """

    def __init__(self, path: str | os.PathLike[str]) -> None:
        import h5py

        self.path = Path(path)
        try:
            self._handle = h5py.File(self.path, "r")
        except READ_ERRORS as exc:
            raise InputFileError(
                f"{self.path}: cannot be read as a data set ({first_line(exc)})", parameter="file"
            ) from None
        try:
            self._open()
        except InputFileError:
            self._handle.close()
            raise
        except READ_ERRORS as exc:  # a damaged header, layout or bookkeeping array
            self._handle.close()
            raise InputFileError(
                f"{self.path}: a damaged data set ({first_line(exc)}); allowed: a complete "
                "aaria_pin data set (make it again)",
                parameter="file",
            ) from None

    def _open(self) -> None:
        """Read and check the header, the layout and the flags (see the class)."""
        attrs = self._handle.attrs
        if attrs.get("format") != DATASET_FORMAT:
            raise InputFileError(f"{self.path}: not an aaria_pin data set", parameter="file")
        self.version = int(attrs.get("format_version", LEGACY_VERSION))
        if self.version not in (LEGACY_VERSION, DATASET_FORMAT_VERSION):
            raise InputFileError(
                f"{self.path}: data set format version is {self.version}; allowed: "
                f"{LEGACY_VERSION}, {DATASET_FORMAT_VERSION} (a newer aaria_pin wrote it)",
                parameter="file",
            )
        if self.version == DATASET_FORMAT_VERSION:
            missing = missing_shards(self._handle, self.path)
            if missing:
                raise InputFileError(
                    f"{self.path}: its shard {missing[0]} is missing ({len(missing)} missing); "
                    "allowed: the data set's folder with all its shards",
                    parameter="file",
                )
        self.header = DatasetHeader.from_attributes(
            decode_attributes(attrs, self.path), self.version, self.path
        )
        self.layout: DatasetLayout | None = None
        if self.version == LEGACY_VERSION:
            self.names: tuple[str, ...] = legacy_names(self._handle)
            shapes: dict[str, tuple[int, ...] | None] = dict.fromkeys(self.names)
        else:
            self.layout = read_layout(self._handle)
            self.names = (*self.layout.names, *self.layout.views)
            shapes = {
                **self.layout.shapes(self.samples),
                **dict.fromkeys(self.layout.views),
                "checksum": (len(self.layout.names),),
            }
        n_runs = self.header.n_runs
        check_arrays(self._handle, self.path, n_runs, shapes)
        self.complete = self._handle["complete"][()].astype(bool)
        self._check = run_check(self._handle, self.path, n_runs, self.layout)

    def __len__(self) -> int:
        return self.header.n_runs

    @property
    def handle(self) -> Any:
        """The open ``h5py.File`` (read-only), for what the reader's methods do not cover."""
        return self._handle

    @property
    def samples(self) -> int:
        """Samples per run T."""
        return self.header.samples

    @property
    def attributes(self) -> dict[str, Any]:
        """File attributes, JSON ones decoded (keys without the ``_json`` suffix); a copy."""
        return copy.deepcopy(self.header.attributes)

    @property
    def stored_names(self) -> tuple[str, ...]:
        """The arrays stored per run (the views apart), in file order."""
        return self.layout.names if self.layout is not None else self.names

    def _check_run(self, index: int) -> None:
        if not 0 <= index < len(self):
            raise ParameterError(
                f"run {index}; allowed: 0 to {len(self) - 1}",
                parameter="run",
                value=index,
                allowed=f"0 to {len(self) - 1}",
            )
        if not self.complete[index]:
            raise ParameterError(
                f"run {index} is not complete in {self.path}",
                parameter="run",
                value=index,
                allowed=f"a complete run of {self.path}",
            )

    def run(self, index: int, names: Sequence[str] | None = None) -> dict[str, Array]:
        """Arrays of one complete run as stored (by default every stored array, in file order).

        Args:
            index: the run
            names: arrays or views to read (see :attr:`names`)

        Raises:
            ParameterError: index out of range, a run that is not complete, or an unknown name.
            InputFileError: the run is damaged (unreadable, or other numbers than its
                checksum's) or holds a NaN or an infinity (see :mod:`.verify`).
        """
        self._check_run(index)
        names = self.stored_names if names is None else names
        unknown = [name for name in names if name not in self.names]
        if unknown:
            raise ParameterError(
                f"array {unknown[0]!r}; allowed: {', '.join(self.names)}", parameter="names"
            )
        views = self._views
        arrays = {}
        for name in names:
            if name in views:  # a view's numbers are its series': those are verified
                self._check.verify_run(self._handle, index, view_sources([name], views))
                arrays[name] = self._check.read(self._handle, name, index)
                self._check.finite(name, index, arrays[name])
            else:
                arrays[name] = self._check.checked(self._handle, name, index)
        return arrays

    def record(self, index: int) -> RunRecord:
        """Run ``index`` as a run record (arrays in float64), whatever the format version.

        Its attributes are those of a single run: ``kind``, ``robot``, rate, duration, noise
        settings, the run's noise seed (``seed`` and ``noise_spawn_key``) and ``run``.

        Raises:
            ParameterError: index out of range, or a run that is not complete.
            InputFileError: the run is damaged or not finite (see :meth:`run`).
        """
        record = self._record(index)
        check_record(record, record_source(self.path, index), finite=False)  # read: checked
        return record

    def _record(self, index: int) -> RunRecord:
        """Run ``index`` as read (:meth:`record` before its attributes are checked)."""
        self._check_run(index)
        if self.layout is None:
            self._check.verify_run(self._handle, index, self.names)  # readable and finite
            return legacy_record(self._handle, index, self.header)
        return dataset_record(self._handle, self._check, self.header, self.layout, index)

    @property
    def verifiable(self) -> bool:
        """Whether the file records checksums of its runs' numbers (format version 2)."""
        return self._check.verifiable

    def check_run(self, index: int) -> None:
        """Read every stored array of a complete run whole, check it finite and verify it.

        Raises:
            ParameterError: index out of range, or a run that is not complete.
            InputFileError: the run is damaged or holds a NaN or an infinity (see :meth:`run`).
        """
        self._check_run(index)
        self._check.verify_run(self._handle, index, self.stored_names)

    @property
    def series_names(self) -> tuple[str, ...]:
        """The names of :attr:`names` with a time axis (axis 1), the per-run constants apart.

        Series, views and sensor tables (``q_measured``) have one; the layout's inputs do not.
        """
        if self.layout is not None:
            return tuple(name for name in self.names if name not in self.layout.inputs)
        return tuple(name for name in self.names if name in SERIES or name in ("senSen", "signals"))

    @property
    def _views(self) -> dict[str, ColumnView]:
        """The views put together from their series (version 2; version 1 stores its view)."""
        return dict(self.layout.views) if self.layout is not None else {}

    @property
    def _constants(self) -> frozenset[str]:
        """The stored per-run arrays without a time axis."""
        return frozenset(self.names) - set(self.series_names)

    @property
    def label_names(self) -> tuple[str, ...]:
        """The labels this file's stored arrays give (:mod:`.labels`: ``link_types``, …)."""
        return available_labels(self.stored_names)

    def labels(self, index: int, names: Sequence[str] | None = None) -> dict[str, Array]:
        """Labels of one complete run (by default every one of :attr:`label_names`).

        Raises:
            ParameterError: index out of range, a run that is not complete, or an unknown label.
            InputFileError: the run's source arrays are damaged or not finite (see :meth:`run`).
        """
        chosen = self.label_names if names is None else tuple(names)
        unknown = [name for name in chosen if name not in self.label_names]
        if unknown:
            raise ParameterError(
                parameter="names", value=unknown[0], allowed=", ".join(self.label_names)
            )
        return derive_labels(chosen, self.run(index, label_sources(chosen)))

    def _chosen_names(self, names: Sequence[str] | None, labels: bool = False) -> tuple[str, ...]:
        """Names to read, checked (default: the first view, ``senSen`` or ``signals``)."""
        if names is None:
            first = next(iter(self.layout.views)) if self.layout is not None else self.names[0]
            return (first,)
        if isinstance(names, str):
            names = (names,)
        known = (*self.names, *self.label_names) if labels else self.names
        unknown = [name for name in names if name not in known]
        if unknown or not names:
            raise ParameterError(
                parameter="names",
                value=unknown[0] if unknown else ",".join(names),
                allowed=", ".join(known),
            )
        return tuple(names)

    def split_runs(
        self,
        split: str | None = None,
        seed: int = 0,
        fractions: Sequence[float] = DEFAULT_FRACTIONS,
    ) -> np.ndarray:
        """The complete runs of one split by run (None: every complete run), increasing.

        See :func:`~aaria_pin.files.dataset.windows.split_runs`: the split of run k depends on
        ``(seed, fractions, N)`` alone; incomplete runs are in none.

        Raises:
            ParameterError: an unknown split, a negative seed, or bad fractions.
        """
        if split is None:
            check_fractions(fractions)
            return np.flatnonzero(self.complete).astype(np.int64)
        runs = split_runs(len(self), split, seed, fractions)
        return runs[self.complete[runs]]

    def windows(
        self,
        length: int | None,
        stride: int | None = None,
        *,
        names: Sequence[str] | None = None,
        split: str | None = None,
        seed: int = 0,
        fractions: Sequence[float] = DEFAULT_FRACTIONS,
        normalise: bool | Collection[str] = False,
        statistics: GivenStatistics | None = None,
    ) -> WindowDataset:
        """Fixed-length windows over the complete runs (of one split), as a map-style dataset.

        ``len(ds)`` windows; ``ds[i]`` is ``{name: window, "run": k, "start": s}`` (NumPy
        arrays); PyTorch's ``DataLoader(ds, batch_size=64, shuffle=True, num_workers=2)``
        takes it as it is (see :mod:`aaria_pin.files.dataset.windows`). Iterating gives
        ``(run, start, {name: window})`` run by run, each run read once.

        Args:
            length: samples per window; None: each run whole (one window a run, the run's
                arrays normalised as asked)
            stride: samples between window starts (default ``length``: no overlap)
            names: arrays, views or labels (``senSen``, ``signals``, ``imu``, ``q``, ``tau``,
                ``base_wrench``, ``link_types``, …; default the first view, ``senSen`` or
                ``signals``); a series is cut along time, a per-run constant (``senSenDH``,
                ``imu_mount``, a label of :attr:`label_names`) comes whole
            split: ``"train"``, ``"validation"``, ``"test"``, or None for every complete run
            seed: the split's seed
            fractions: of the runs in the training, validation and test splits
            normalise: which names to normalise, the others raw: True (every name but the
                labels), False, or some of the names (``("imu",)``); each is centred on the
                mean and divided by the std (a channel of std 0 only centred) of
                ``statistics``, else stored for the training split of the same seed and
                fractions (see :meth:`statistics`)
            statistics: ``{name: (mean, std)}`` to normalise with instead of the stored ones
                (another data set's :meth:`statistics`, ``OnlineRuns.statistics``, a window
                dataset's ``statistics``; :func:`~.normalisation.given_statistics`)

        Raises:
            ParameterError: a length outside [1, T], a stride below 1, an unknown name or
                split, a negative seed, bad fractions, a name to normalise not among the
                names (or a label), or not in ``statistics``.
            InputFileError: no such stored statistics for a name to normalise (named).
        """
        length, stride = check_cut(length, stride, self.samples)
        chosen = self._chosen_names(names, labels=True)
        runs = self.split_runs(split, seed, fractions)
        scaled = normalised_names(normalise, chosen)
        if statistics is not None:
            given = given_statistics(scaled, statistics)
        else:
            given = training_statistics(self._handle, self.path, scaled, seed, fractions)
        cut = WindowCut(length, stride, chosen, self._views, self._constants, self.samples)
        return WindowDataset(
            self.path,
            cut,
            WindowSplit(runs, split, seed, tuple(fractions)),
            given or None,
            copy.deepcopy(self._check),
        )

    def statistics(
        self,
        names: Sequence[str] | None = None,
        *,
        split: str | None = "train",
        seed: int = 0,
        fractions: Sequence[float] = DEFAULT_FRACTIONS,
        store: bool = False,
    ) -> dict[str, tuple[Array, Array]]:
        """Per-channel mean and std of arrays over every sample of a split's complete runs.

        One streaming pass in float64 (:func:`~aaria_pin.files.dataset.statistics.
        channel_statistics`); a series is reduced over runs and time (channel shape: one
        sample's), a per-run constant over runs.

        Args:
            names: arrays or views (default: the first view)
            split: ``"train"`` (default), ``"validation"``, ``"test"``, or None: every
                complete run
            seed: the split's seed
            fractions: of the runs in the training, validation and test splits
            store: also store them in the file (``statistics/<split>/<name>/mean|std``,
                replacing those of the same split; the file is opened for writing, so no other
                handle on it may be open in this process)

        Returns:
            ``{name: (mean, std)}``, float64 arrays of the channel shape (NaN over no runs).

        Raises:
            ParameterError: an unknown name or split, a negative seed or bad fractions.
            OutputFileError: ``store`` on a file that cannot be written.
        """
        chosen = self._chosen_names(names)
        runs = self.split_runs(split, seed, fractions)
        if len(runs) == 0:  # statistics of nothing: NaN, useless to normalise with
            raise ParameterError(
                parameter="split",
                value=split,
                allowed=f"a split holding a complete run (this one holds none of {len(self)}"
                " with these fractions and seed)",
            )
        computed = names_statistics(
            self._handle,
            WindowCut(1, 1, chosen, self._views, self._constants, 1),
            runs,
            self._check,
        )
        if store:
            import h5py

            self._handle.close()
            try:
                store_statistics(self.path, computed, split, seed, fractions, len(runs))
            finally:
                self._handle = h5py.File(self.path, "r")
        return {name: (mean, std) for name, (mean, std, _) in computed.items()}

    def stored_statistics(self, split: str | None = "train") -> dict[str, tuple[Array, Array]]:
        """Statistics stored in the file for one split (see :meth:`statistics`).

        Raises:
            InputFileError: none stored for that split.
        """
        return read_statistics(self._handle, split, self.path)[0]

    def close(self) -> None:
        """Close the file."""
        self._handle.close()

    def __enter__(self) -> DatasetReader:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
