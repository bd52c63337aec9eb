"""A shuffled order of a data set's windows that reads each run once an epoch: blocks of runs.

A uniformly shuffled epoch takes windows of random runs one after the other: each window
decompresses its run's chunk again (a run is one HDF5 chunk), so it read about 8 % as many
windows a second as reading in run order (figures below).
:class:`RunBlockSampler` shuffles at the run level and within blocks: each epoch it puts the
runs in a random order, cuts that order into blocks of ``runs_per_block`` runs, and gives the
windows of each block in a random order, block after block. With a
:class:`~.windows.WindowDataset` keeping at least that many runs read (its ``cache_runs``,
default 8, the sampler's default block too), every run is read from the file once an epoch per
process.

**How far from uniform**: every window comes once an epoch, and every order of the runs and of
the windows within a block is equally likely; but the windows of one block come together. Two
consecutive windows come from the same run with probability ``(W - 1) / (G·W - 1)`` (about
``1/G``: 1/8 by default) against ``(W - 1) / (R·W - 1)`` (about ``1/R``) for a uniform shuffle
(G runs a block, R runs, W windows a run), and a batch of B windows holds windows of at most G
runs (of about ``min(B, R)`` when uniform). A larger block is closer to uniform and needs a
larger cache (G whole runs in memory per process).

Measured (``aaria dataset -n 40 --duration 10 --rate 200 -o ds40.h5``, then ``python
benchmarks/bench_windows.py --dataset ds40.h5 --repeats 5``: 1,480 windows of 200 samples,
stride 50, ``senSen`` and ``tau``, one process on 2 cores shared with other jobs, medians):
in run order 5,500 windows/s, uniform shuffle 470/s (8.6 %), this sampler (8 runs a block)
6,600/s (121 % of in order); with the read cache off, as before it existed, in order 5,200/s
and uniform 470/s. A quieter run (3 repeats) gave 9,400, 770 and 9,500/s (101 %).

It is an iterable of indices with a length, as PyTorch's ``DataLoader(ds, sampler=...)`` takes
it (aaria_pin imports no torch); the order of an epoch is a function of ``(seed, epoch)`` alone:
call :meth:`RunBlockSampler.set_epoch` before each epoch for a new order (as PyTorch's
``DistributedSampler``). With ``num_workers``, the ``DataLoader`` hands batches of the sampler's
indices to the workers in turn, so every worker reads the runs of the current block (a run is
then read once an epoch per worker).
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from aaria_pin.errors import ParameterError
from aaria_pin.files.dataset.windows import DEFAULT_CACHE_RUNS, WindowDataset

__all__ = ["RunBlockSampler"]


def _count(value: int, parameter: str, low: int) -> int:
    """An integer of at least ``low``."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < low:
        raise ParameterError(parameter=parameter, value=value, allowed=f"an integer >= {low}")
    return int(value)


class RunBlockSampler:
    """Window indices of a window dataset, shuffled by blocks of runs (see the module docstring).

    Args:
        n_runs: runs R of the window dataset (``len(ds.runs)``)
        windows_per_run: windows W of a run (``ds.windows_per_run``); window ``i`` is window
            ``i % W`` of run ``i // W``, as :class:`~.windows.WindowDataset` counts them
        runs_per_block: runs G whose windows are shuffled together (at most the dataset's
            ``cache_runs`` for each run to be read once)
        seed: the order's seed (with the epoch)

    Attributes:
        n_runs, windows_per_run, runs_per_block, seed: as given
        epoch: the epoch whose order iterating gives (0 at first; :meth:`set_epoch`)

    Raises:
        ParameterError: a negative count or seed, or a block of no runs.
    """

    def __init__(
        self,
        n_runs: int,
        windows_per_run: int,
        runs_per_block: int = DEFAULT_CACHE_RUNS,
        seed: int = 0,
    ) -> None:
        self.n_runs = _count(n_runs, "n_runs", 0)
        self.windows_per_run = _count(windows_per_run, "windows_per_run", 0)
        self.runs_per_block = _count(runs_per_block, "runs_per_block", 1)
        self.seed = _count(seed, "seed", 0)
        self.epoch = 0

    @classmethod
    def for_windows(
        cls, windows: WindowDataset, runs_per_block: int | None = None, seed: int = 0
    ) -> RunBlockSampler:
        """The sampler of a window dataset (blocks of its ``cache_runs`` runs by default).

        Raises:
            ParameterError: a block of no runs, or a negative seed.
        """
        block = max(windows.cache_runs, 1) if runs_per_block is None else runs_per_block
        return cls(len(windows.runs), windows.windows_per_run, block, seed)

    def set_epoch(self, epoch: int) -> None:
        """Choose the epoch whose order the next iteration gives.

        Raises:
            ParameterError: a negative epoch.
        """
        self.epoch = _count(epoch, "epoch", 0)

    def __len__(self) -> int:
        return self.n_runs * self.windows_per_run

    def order(self, epoch: int | None = None) -> np.ndarray:
        """The window indices of an epoch (default :attr:`epoch`), int64, each once.

        Raises:
            ParameterError: a negative epoch.
        """
        epoch = self.epoch if epoch is None else _count(epoch, "epoch", 0)
        rng = np.random.default_rng([self.seed, epoch])
        runs = rng.permutation(self.n_runs).astype(np.int64)
        within = np.arange(self.windows_per_run, dtype=np.int64)
        blocks = []
        for first in range(0, self.n_runs, self.runs_per_block):
            block = runs[first : first + self.runs_per_block, None] * self.windows_per_run + within
            indices = block.ravel()
            rng.shuffle(indices)
            blocks.append(indices)
        return np.concatenate(blocks) if blocks else np.zeros(0, dtype=np.int64)

    def __iter__(self) -> Iterator[int]:
        return iter(self.order().tolist())

    def __repr__(self) -> str:
        return (
            f"RunBlockSampler(n_runs={self.n_runs}, windows_per_run={self.windows_per_run}, "
            f"runs_per_block={self.runs_per_block}, seed={self.seed}, epoch={self.epoch})"
        )
