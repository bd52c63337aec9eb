"""Throughput of ``aaria dataset`` with default settings (random DH arms, noise on, gzip).

    python benchmarks/bench_dataset.py          # 100 and 500 runs of 1,000 samples; 1, 2 workers
    python benchmarks/bench_dataset.py --smoke  # CI: 10 and 20 runs of 100 samples, no goal checked

The figure of the performance issue is the marginal throughput: the extra samples of the longer
job divided by its extra wall time, ``(500 - 100) × T / (t500 - t100)``, so worker start-up, the
run made before the workers fork and the file's creation cancel out. Whole jobs are timed
(simulation, compression in the workers, HDF5 writing in the main process); each figure is the
median over interleaved repeats (1 worker and 2 workers alternate, so both see the same machine),
and the two-worker ratio is the median of the per-repeat ratios of the marginal throughputs.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

from aaria_pin.apps.dataset.dh import DhDatasetSpec
from aaria_pin.apps.dataset.engine import generate_dataset

GOAL_ONE_WORKER = 150_000.0
"""Marginal samples/s on one worker (the performance issue's goal)."""
GOAL_RATIO = 1.8
"""Two workers over one (the issue's goal)."""


def job_seconds(runs: int, samples: int, workers: int, folder: Path) -> tuple[float, float]:
    """Wall time of one whole job [s], and the file's bytes per run."""
    rate = 100.0
    spec = DhDatasetSpec(n_runs=runs, seed=1, duration=(samples - 1) / rate, rate=rate)
    path = folder / f"ds{workers}_{runs}.h5"
    start = time.perf_counter()
    generate_dataset(path, spec, workers=workers, overwrite=True)
    seconds = time.perf_counter() - start
    size = path.stat().st_size / runs
    path.unlink()
    return seconds, size


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--smoke", action="store_true", help="tiny sizes, for CI")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    if args.smoke:
        short, long, samples, repeats = 10, 20, 100, 1
    else:
        short, long, samples, repeats = 100, 500, 1000, args.repeats
    extra = (long - short) * samples
    marginal: dict[int, list[float]] = {1: [], 2: []}
    whole: dict[int, list[float]] = {1: [], 2: []}
    ratios: list[float] = []
    size = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        job_seconds(4, samples, 1, folder)  # warm the compiled kernels' cache
        for _ in range(repeats):
            for workers in marginal:
                t_short, _ = job_seconds(short, samples, workers, folder)
                t_long, size = job_seconds(long, samples, workers, folder)
                marginal[workers].append(extra / max(t_long - t_short, 1e-9))
                whole[workers].append(long * samples / t_long)
            ratios.append(marginal[2][-1] / marginal[1][-1])
    rates = {workers: statistics.median(values) for workers, values in marginal.items()}
    wholes = {workers: statistics.median(values) for workers, values in whole.items()}
    ratio = statistics.median(ratios)
    print(
        f"aaria dataset, random DH arms, {samples} samples a run, noise on, gzip, float32;"
        f" median of {repeats}"
    )
    print(f"file size per run: {size:,.0f} bytes (format version 2)")
    print(
        f"{'workers':<8} {f'marginal {short}->{long} runs, samples/s':>38}"
        f" {f'whole {long}-run job, samples/s':>32}"
    )
    for workers in rates:
        print(f"{workers:<8} {rates[workers]:>38,.0f} {wholes[workers]:>32,.0f}")
    print(
        f"one worker, marginal: {rates[1]:,.0f} samples/s ({rates[1] / GOAL_ONE_WORKER:.2f} of the"
        f" goal {GOAL_ONE_WORKER:,.0f}; {1e3 * samples / rates[1]:.2f} ms a run)"
    )
    print(
        f"two workers / one worker, marginal: {ratio:.2f} (goal >= {GOAL_RATIO}; per repeat:"
        f" {', '.join(f'{r:.2f}' for r in ratios)})"
    )


if __name__ == "__main__":
    main()
