"""Throughput of ``aaria dataset`` with default settings (random DH arms, noise on, gzip).

    python benchmarks/bench_dataset.py            # 200 runs of 1,000 samples, 1 and 2 workers
    python benchmarks/bench_dataset.py --smoke    # CI: 10 runs of 100 samples, no timing asserted

Samples per second of wall time, medians of repeats, whole job included (worker start-up, HDF5
writing); and the ratio of two workers to one.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

from aaria_pin.apps.dataset.dh import DhDatasetSpec
from aaria_pin.apps.dataset.engine import generate_dataset


def throughput(runs: int, samples: int, workers: int, folder: Path) -> tuple[float, float]:
    """Samples per second of one job, and the file's bytes per run."""
    rate = 100.0
    spec = DhDatasetSpec(n_runs=runs, seed=1, duration=(samples - 1) / rate, rate=rate)
    path = folder / f"ds{workers}.h5"
    start = time.perf_counter()
    generate_dataset(path, spec, workers=workers, overwrite=True)
    return runs * samples / (time.perf_counter() - start), path.stat().st_size / runs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--smoke", action="store_true", help="tiny sizes, for CI")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    runs, samples, repeats = (10, 100, 1) if args.smoke else (200, 1000, args.repeats)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        throughput(4, samples, 1, folder)  # warm the compiled kernels' cache
        measured: dict[int, list[float]] = {1: [], 2: []}
        size = 0.0
        for _ in range(repeats):  # interleaved, so both see the same machine
            for workers in measured:
                rate, size = throughput(runs, samples, workers, folder)
                measured[workers].append(rate)
        rates = {workers: statistics.median(values) for workers, values in measured.items()}
    print(f"aaria dataset, {runs} runs × {samples} samples, noise on, gzip, median of {repeats}")
    print(f"file size per run: {size:,.0f} bytes (format version 2)")
    print(f"{'workers':<10} {'samples/s':>12}")
    for workers, value in rates.items():
        print(f"{workers:<10} {value:>12,.0f}")
    print(f"two workers / one worker (floor: the per-run throughput): {rates[2] / rates[1]:.2f}")


if __name__ == "__main__":
    main()
