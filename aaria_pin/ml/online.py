"""A data set's runs simulated on demand, and their windows split across ``DataLoader`` workers.

:class:`OnlineRuns` holds a data set's spec (:class:`~aaria_pin.apps.dataset.spec.DatasetSpec`,
the one ``aaria dataset`` makes from its flags through
:class:`~aaria_pin.apps.dataset.spec_sources.DatasetSources`) and nothing else: ``runs[k]`` is
:func:`~aaria_pin.apps.dataset.generate.simulate_dataset_run` of the spec and k, the stored
arrays of run k of the file the same settings make (the same numbers and dtypes: run k is a
pure function of the seed and k). It is a map-style dataset (``len``, ``[k]``).

:class:`OnlineWindows` (:meth:`OnlineRuns.windows`) is an iterable dataset of the windows of
some runs, as :meth:`DatasetReader.windows
<aaria_pin.files.dataset.reader.DatasetReader.windows>` cuts them: the same names (arrays,
views, labels), splits by run, window dicts (``run`` and ``start`` beside the names) and
normalisation per name, by the same functions (:func:`~aaria_pin.files.dataset.windows.run_items`,
:func:`~aaria_pin.files.dataset.windows.cut_windows`). Each ``DataLoader`` worker w of W
simulates the runs of its share, the i-th run of the epoch for every i ≡ w (mod W), so no run is
simulated twice in an epoch (:func:`worker_info` reads torch's worker; without torch a process
is worker 0 of 1). :meth:`OnlineWindows.set_epoch` moves an epoch to fresh arms: epoch e takes
the runs ``k + e·N`` (N the spec's runs), those of a data set of ``(e + 1)·N`` runs of the same
seed, so a held-out run of epoch 0's validation or test split is never trained on.

Both pickle as their spec and a few numbers (a ``DataLoader`` worker, forked or spawned,
simulates with its own copy; a URDF robot is loaded once per process).
"""

from __future__ import annotations

import sys
from collections.abc import Collection, Iterator, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin.errors import ParameterError
from aaria_pin.files.dataset.labels import LABELS, available_labels
from aaria_pin.files.dataset.normalisation import (
    GivenStatistics,
    Statistics,
    given_statistics,
    normalised_names,
)
from aaria_pin.files.dataset.windows import (
    DEFAULT_FRACTIONS,
    WindowCut,
    WindowedRuns,
    WindowSplit,
    check_cut,
    check_fractions,
    cut_windows,
    run_items,
    split_runs,
    view_sources,
)

if TYPE_CHECKING:
    from aaria_pin.apps.dataset.spec import DatasetSpec
    from aaria_pin.apps.dataset.spec_sources import DatasetSources
    from aaria_pin.files.dataset.layout import DatasetLayout

__all__ = ["OnlineRuns", "OnlineWindows", "worker_info"]


def worker_info() -> tuple[int, int]:
    """This process's ``DataLoader`` worker and the number of workers, ``(w, W)``.

    Read from ``torch.utils.data.get_worker_info`` when torch is imported (a ``DataLoader``
    imports it), else ``(0, 1)``: the main process, or no torch at all.
    """
    torch = sys.modules.get("torch")
    info = torch.utils.data.get_worker_info() if torch is not None else None
    return (0, 1) if info is None else (int(info.id), int(info.num_workers))


class OnlineRuns:
    """A data set's runs, each simulated when asked: ``runs[k]``, the stored arrays of run k.

    Args:
        spec: the data set's spec, or its sources (the settings ``aaria dataset`` takes, as
            :class:`~aaria_pin.apps.dataset.spec_sources.DatasetSources`; resolved and checked
            here)

    Attributes:
        spec: the spec
        layout: what every run holds (names, views, per-run tables)
        samples: samples per run T
    """

    def __init__(self, spec: DatasetSpec | DatasetSources) -> None:
        from aaria_pin.apps.dataset.spec_sources import DatasetSources

        self.spec: DatasetSpec = spec.spec() if isinstance(spec, DatasetSources) else spec
        self.layout: DatasetLayout = self.spec.layout()
        self.samples = int(self.spec.samples)

    @classmethod
    def defaults(cls, n_runs: int, seed: int = 0, **sources: Any) -> OnlineRuns:
        """The runs of ``aaria dataset -n N --seed S`` (random DH arms), other flags as keywords.

        Args:
            n_runs: runs N
            seed: the data set's seed
            **sources: other fields of :class:`~aaria_pin.apps.dataset.spec_sources.DatasetSources`
                (``duration=0.2``, ``rate=100.0``, ``robot="ur5"``, …)

        Raises:
            ParameterError: settings ``aaria dataset`` refuses (its flag named as a parameter).
        """
        from aaria_pin.apps.dataset.spec_sources import DatasetSources

        return cls(DatasetSources(n_runs=n_runs, seed=seed, **sources))

    def __len__(self) -> int:
        return int(self.spec.n_runs)

    def __getitem__(self, run: int) -> dict[str, np.ndarray]:
        """Run ``run``'s stored arrays by name, in file order and stored dtypes (simulated now).

        Raises:
            IndexError: ``run`` outside ``[-N, N)``.
        """
        count = len(self)
        if not -count <= int(run) < count:
            raise IndexError(f"run {run} of {count}")
        return self.simulate(int(run) % count)

    def simulate(self, run: int) -> dict[str, np.ndarray]:
        """Run ``run``'s stored arrays (any run ≥ 0: beyond N, those of a larger data set)."""
        from aaria_pin.apps.dataset.generate import simulate_dataset_run

        return simulate_dataset_run(self.spec, int(run))

    @property
    def names(self) -> tuple[str, ...]:
        """The names windows take: the stored arrays, the views and the labels."""
        stored = self.layout.names
        return (*stored, *self.layout.views, *available_labels(stored))

    def _chosen(self, names: Sequence[str] | None, labels: bool) -> tuple[str, ...]:
        """Names checked against :attr:`names` (default: the first view, as the reader's)."""
        if names is None:
            return (next(iter(self.layout.views)),)
        chosen = (names,) if isinstance(names, str) else tuple(names)
        known = self.names if labels else tuple(n for n in self.names if n not in LABELS)
        unknown = [name for name in chosen if name not in known]
        if unknown or not chosen:
            shown = unknown[0] if unknown else ""
            raise ParameterError(parameter="names", value=shown, allowed=", ".join(known))
        return chosen

    def _cut(self, length: int, stride: int, names: Sequence[str]) -> WindowCut:
        """How the runs are cut, as a file of this layout's :class:`WindowCut` (the reader's)."""
        constants = frozenset(self.layout.inputs)
        return WindowCut(length, stride, names, dict(self.layout.views), constants, self.samples)

    def statistics(
        self, names: Sequence[str] | None = None, runs: Sequence[int] | np.ndarray | None = None
    ) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Per-channel mean and std of arrays or views over some runs, simulated now.

        The numbers :meth:`DatasetReader.statistics
        <aaria_pin.files.dataset.reader.DatasetReader.statistics>` gives on the file of the
        same settings (the same function over the same arrays); the runs are held in memory
        together, so a few hundred runs of a long data set are enough.

        Args:
            names: arrays or views (default: the first view)
            runs: the runs (default: the training split of seed 0 and the default fractions,
                the split ``windows(normalise=True)`` reads a file's statistics of)

        Raises:
            ParameterError: an unknown name, or no runs.
        """
        from aaria_pin.files.dataset.statistics import names_statistics

        chosen = self._chosen(names, labels=False)
        chosen_runs = (
            split_runs(len(self), "train") if runs is None else np.asarray(runs, dtype=np.int64)
        )
        if chosen_runs.size == 0:
            raise ParameterError(parameter="runs", value="[]", allowed="at least one run")
        cut = self._cut(1, 1, chosen)
        sources = view_sources(chosen, {n: cut.views[n] for n in chosen if n in cut.views})
        simulated = [self.simulate(int(run)) for run in chosen_runs]
        stacked = {name: np.stack([arrays[name] for arrays in simulated]) for name in sources}
        computed = names_statistics(stacked, cut, np.arange(chosen_runs.size))
        return {name: (mean, std) for name, (mean, std, _) in computed.items()}

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
    ) -> OnlineWindows:
        """Fixed-length windows of the runs (of one split), simulated as they are iterated.

        The arguments are those of :meth:`DatasetReader.windows
        <aaria_pin.files.dataset.reader.DatasetReader.windows>`, but ``statistics`` is needed
        to normalise: a file stores its own, these runs none.

        Args:
            length: samples per window; None: each run whole (one window a run)
            stride: samples between window starts (default ``length``)
            names: arrays, views or labels (default the first view)
            split: ``"train"``, ``"validation"``, ``"test"``, or None for every run
            seed: the split's seed
            fractions: of the runs in the training, validation and test splits
            normalise: which names to normalise: True (every name but the labels), False, or
                some of the names
            statistics: ``{name: (mean, std)}`` of (at least) the names to normalise:
                :meth:`statistics`, or a file's :meth:`DatasetReader.statistics
                <aaria_pin.files.dataset.reader.DatasetReader.statistics>`
                (:func:`~aaria_pin.files.dataset.normalisation.given_statistics`)

        Raises:
            ParameterError: a length outside [1, T], a stride below 1, an unknown name or
                split, a negative seed, bad fractions, a name to normalise not among the names
                (or a label), or without statistics.
        """
        length, stride = check_cut(length, stride, self.samples)
        chosen = self._chosen(names, labels=True)
        if split is None:
            check_fractions(fractions)
            runs = np.arange(len(self), dtype=np.int64)
        else:
            runs = split_runs(len(self), split, seed, fractions)
        given = given_statistics(normalised_names(normalise, chosen), statistics or {})
        return OnlineWindows(
            self,
            self._cut(length, stride, chosen),
            WindowSplit(runs, split, seed, tuple(fractions)),
            given or None,
        )


class OnlineWindows(WindowedRuns):
    """The windows of some runs, simulated run by run as they are iterated.

    Made by :meth:`OnlineRuns.windows`. Iterating gives each window as a dict: each name's
    window, plus ``run`` and ``start`` (0-d int64), as ``WindowDataset[i]`` does, run by run in
    increasing order; in a ``DataLoader`` worker, only that worker's share of the runs
    (:meth:`worker_runs`). ``len`` is the windows of every worker together.

    Args:
        runs: the runs' source
        cut: how the runs are cut (length, stride, names; the layout's views and constants)
        split: the runs to cut and the split they are
        statistics: ``(mean, std)`` of the names to normalise, or None

    Attributes:
        length, stride, names, runs, split, seed, fractions, statistics: as given
        windows_per_run: windows of one run
        epoch: the epoch (:meth:`set_epoch`; 0: the runs as given)
    """

    def __init__(
        self,
        runs: OnlineRuns,
        cut: WindowCut,
        split: WindowSplit,
        statistics: Statistics | None = None,
    ) -> None:
        super().__init__(cut, split, statistics)
        self.source = runs
        self.epoch = 0

    def set_epoch(self, epoch: int) -> None:
        """Take the runs of an epoch: run ``k + epoch·N`` for each run k given (fresh arms).

        Call it before each epoch's iteration; a ``DataLoader`` without
        ``persistent_workers`` gives each epoch's workers a copy made then.

        Raises:
            ParameterError: a negative epoch.
        """
        if isinstance(epoch, bool) or not isinstance(epoch, int | np.integer) or epoch < 0:
            raise ParameterError(parameter="epoch", value=epoch, allowed="an integer >= 0")
        self.epoch = int(epoch)

    def epoch_runs(self) -> np.ndarray:
        """The runs of the current epoch, increasing."""
        return self.runs + self.epoch * len(self.source)

    def worker_runs(self, worker: int = 0, workers: int = 1) -> np.ndarray:
        """Worker ``worker`` of ``workers``'s runs of the epoch: every ``workers``-th from its own.

        Raises:
            ParameterError: ``workers`` below 1, or ``worker`` outside ``[0, workers)``.
        """
        if workers < 1:
            raise ParameterError(parameter="workers", value=workers, allowed="an integer >= 1")
        if not 0 <= worker < workers:
            raise ParameterError(parameter="worker", value=worker, allowed=f"0 to {workers - 1}")
        return self.epoch_runs()[worker::workers]

    def iterate(self, worker: int = 0, workers: int = 1) -> Iterator[dict[str, np.ndarray]]:
        """The windows of worker ``worker`` of ``workers``'s runs, each run simulated once."""
        for run in self.worker_runs(worker, workers).tolist():
            stored = self.source.simulate(run)
            needed = {name: stored[name] for name in self._sources}
            items = run_items(self.names, self._views, needed, self.statistics)
            for start, window in cut_windows(
                items, self._whole, self.length, self.stride, self.samples
            ):
                window["run"] = np.asarray(run, dtype=np.int64)
                window["start"] = np.asarray(start, dtype=np.int64)
                yield window

    def __iter__(self) -> Iterator[dict[str, np.ndarray]]:
        return self.iterate(*worker_info())

    def torch(self, advance_epochs: bool = False) -> Any:
        """These windows as a ``torch.utils.data.IterableDataset`` (for a ``DataLoader``).

        Args:
            advance_epochs: each iteration after the first in a worker takes its next epoch (for a
                ``DataLoader`` with ``persistent_workers=True``, whose workers never see a
                later :meth:`set_epoch`; :class:`~aaria_pin.ml._torch.TorchWindows`)

        Raises:
            ModuleNotFoundError: torch is not installed (``pip install aaria-pin[ml]``).
        """
        from aaria_pin.ml._torch import TorchWindows

        return TorchWindows(self, advance_epochs)

    def __repr__(self) -> str:
        return (
            f"OnlineWindows(length={self.length}, stride={self.stride}, names={self.names}, "
            f"split={self.split!r}, runs={len(self.runs)}, epoch={self.epoch}, "
            f"windows={len(self)}, normalised={tuple(self.statistics or ())})"
        )
