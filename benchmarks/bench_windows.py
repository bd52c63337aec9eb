"""Windows/s of a data set's training windows in one process: in order, shuffled, by run blocks.

    python benchmarks/bench_windows.py                 # makes 40 runs of 10 s at 200 Hz (tmp)
    python benchmarks/bench_windows.py --dataset ds.h5 # an existing data set
    python benchmarks/bench_windows.py --smoke         # CI: 4 runs of 1 s, no goal checked

The data set is ``aaria dataset -n 40 --duration 10 --rate 200`` (random DH arms, noise, gzip,
float32). One :class:`~aaria_pin.files.dataset.windows.WindowDataset` of 200-sample windows,
stride 50, names ``senSen`` and ``tau``, is read ``ds[i]`` by ``ds[i]`` in four orders, each
epoch on a fresh copy (an empty cache): in run order; a uniform shuffle (``permutation``);
:class:`~aaria_pin.files.dataset.sampler.RunBlockSampler` (8 runs a block); and the first two
with the read cache off (``cache_runs = 0``, the reading before the cache). Orders alternate
over the repeats, so each sees the same machine; each figure is the median, and the sampler's
ratio is against the in-order figure of the same process. The goal (issue 27): a shuffled epoch
at >= 80 % of in-order speed.
"""

from __future__ import annotations

import argparse
import copy
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from aaria_pin.files.dataset.reader import DatasetReader
from aaria_pin.files.dataset.sampler import RunBlockSampler
from aaria_pin.files.dataset.windows import WindowDataset

GOAL_RATIO = 0.8
"""The sampler's epoch over the in-order one (issue 27)."""


def make_dataset(path: Path, runs: int, duration: float, rate: float) -> None:
    """A data set of random DH arms, as ``aaria dataset -n RUNS --duration D --rate R``."""
    from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
    from aaria_pin.apps.dataset.generate import generate_dataset

    spec = DhDatasetSpec(n_runs=runs, seed=0, duration=duration, rate=rate)
    generate_dataset(path, spec, workers=1)


def epoch_rate(windows: WindowDataset, order: np.ndarray, cache: bool) -> float:
    """Windows/s of one epoch read ``ds[i]`` in an order, on a fresh copy (no cache, no handle)."""
    fresh = copy.copy(windows)
    fresh.__dict__.update(windows.__getstate__())
    fresh.cache_runs = windows.cache_runs if cache else 0
    start = time.perf_counter()
    for index in order.tolist():
        fresh[index]
    elapsed = time.perf_counter() - start
    fresh.close()
    return len(order) / elapsed


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dataset", type=Path, help="an existing data set (else one is made)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--smoke", action="store_true", help="a tiny data set, no goal checked")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        path = args.dataset
        if path is None:
            path = Path(folder) / "ds.h5"
            runs, duration = (4, 1.0) if args.smoke else (40, 10.0)
            make_dataset(path, runs, duration, 200.0)
        with DatasetReader(path) as reader:
            length = min(200, reader.samples)
            windows = reader.windows(length, max(length // 4, 1), names=("senSen", "tau"))
        sampler = RunBlockSampler.for_windows(windows, seed=1)
        rng = np.random.default_rng(0)
        orders: dict[str, Callable[[int], tuple[np.ndarray, bool]]] = {
            "in order": lambda _: (np.arange(len(windows)), True),
            "uniform shuffle": lambda _: (rng.permutation(len(windows)), True),
            f"run blocks ({sampler.runs_per_block} runs)": lambda e: (sampler.order(e), True),
            "in order, no cache": lambda _: (np.arange(len(windows)), False),
            "uniform shuffle, no cache": lambda _: (rng.permutation(len(windows)), False),
        }
        rates: dict[str, list[float]] = {name: [] for name in orders}
        for repeat in range(args.repeats):
            for name, make in orders.items():
                order, cache = make(repeat)
                rates[name].append(epoch_rate(windows, order, cache))
        print(f"{path}: {len(windows)} windows of {length} samples, {len(windows.runs)} runs")
        medians = {name: statistics.median(values) for name, values in rates.items()}
        for name, value in medians.items():
            print(f"  {name:32s} {value:9.0f} windows/s  {value / medians['in order']:6.1%}")
        ratio = (
            medians[next(n for n in medians if n.startswith("run blocks"))] / medians["in order"]
        )
    if not args.smoke and ratio < GOAL_RATIO:
        print(f"run blocks at {ratio:.1%} of in order; goal {GOAL_RATIO:.0%}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
