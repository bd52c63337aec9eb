"""Windows/s and runs/s of runs generated inside the training loop, against reading a file.

    python benchmarks/bench_online.py                  # 16 random DH arms, 10 s at 200 Hz
    python benchmarks/bench_online.py --runs 32 --repeats 3
    python benchmarks/bench_online.py --smoke          # CI: 4 runs of 1 s, one repeat

The data set is ``aaria dataset -n RUNS --duration 10 --rate 200`` (random DH arms, noise,
float32): made once into a temporary file by one worker (its runs/s printed), then read as
200-sample windows, stride 50, names ``senSen``, ``tau`` and ``link_types``, in one epoch each
way: the file-backed windows in order (:class:`~aaria_pin.files.dataset.windows.WindowDataset`
iterated, each run read once); the online windows in this process
(:class:`~aaria_pin.ml.online.OnlineWindows` iterated, each run simulated once); and, with
torch installed, a ``DataLoader`` over the online windows (batches of 64, collated into tensors)
in this process (0 workers) and with 1 and 2 worker processes (their start-up counted: a fresh
loader per epoch, as without ``persistent_workers``), and with 1 and 2 persistent workers
(``persistent_workers=True``, ``torch(advance_epochs=True)``: fresh arms each epoch, the
workers started once, before the timing). Modes alternate over the repeats; each
figure is the median, and the ratio is against the file-backed figure of the same process.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.apps.dataset.generate import generate_dataset
from aaria_pin.files.dataset.reader import DatasetReader
from aaria_pin.ml.online import OnlineRuns, OnlineWindows

NAMES = ("senSen", "tau", "link_types")


def file_epoch(path: Path, length: int, stride: int) -> int:
    """Windows of one in-order epoch of the file-backed windows (a fresh reader)."""
    with DatasetReader(path) as reader:
        windows = reader.windows(length, stride, names=NAMES)
        count = sum(1 for _ in windows)
        windows.close()
    return count


def online_epoch(windows: OnlineWindows) -> int:
    """Windows of one epoch of the online windows in this process."""
    return sum(1 for _ in windows)


def loader_epoch(windows: OnlineWindows, workers: int) -> int:
    """Windows of one epoch through a torch ``DataLoader`` with some worker processes."""
    import torch

    loader = torch.utils.data.DataLoader(windows.torch(), batch_size=64, num_workers=workers)
    return sum(len(batch["run"]) for batch in loader)


def persistent_loader(windows: OnlineWindows, workers: int) -> Callable[[], int]:
    """An epoch of a ``DataLoader`` whose workers persist (fresh arms each epoch), warmed up."""
    import torch

    loader = torch.utils.data.DataLoader(
        windows.torch(advance_epochs=True),
        batch_size=64,
        num_workers=workers,
        persistent_workers=True,
    )

    def epoch() -> int:
        return sum(len(batch["run"]) for batch in loader)

    epoch()  # the workers started and their first epoch run, outside the timing
    return epoch


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=16)
    parser.add_argument("--duration", type=float, default=10.0)
    parser.add_argument("--rate", type=float, default=200.0)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--smoke", action="store_true", help="4 runs of 1 s, one repeat")
    args = parser.parse_args()
    runs, duration, repeats = args.runs, args.duration, args.repeats
    if args.smoke:
        runs, duration, repeats = 4, 1.0, 1
    spec = DhDatasetSpec(n_runs=runs, seed=0, duration=duration, rate=args.rate)
    online = OnlineRuns(spec)
    online[0]  # the compiled kernels loaded, as a training job's first run would
    length = min(200, online.samples)
    stride = max(length // 4, 1)
    windows = online.windows(length, stride, names=NAMES)
    modes: dict[str, Callable[[], int]] = {
        "file-backed, in order": lambda: file_epoch(path, length, stride),
        "online, this process": lambda: online_epoch(windows),
    }
    try:
        import torch  # noqa: F401

        for workers in (0, 1, 2):
            name = f"online, DataLoader {workers} worker{'s' * (workers != 1)}"
            modes[name] = lambda w=workers: loader_epoch(windows, w)
        for workers in (1, 2):
            name = f"online, persistent {workers} worker{'s' * (workers != 1)}"
            modes[name] = persistent_loader(windows, workers)
    except ModuleNotFoundError:
        print("torch not installed: no DataLoader figures (pip install aaria-pin[ml])")
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "ds.h5"
        start = time.perf_counter()
        generate_dataset(path, spec, workers=1)
        made = runs / (time.perf_counter() - start)
        rates: dict[str, list[float]] = {name: [] for name in modes}
        for _ in range(repeats):
            for name, epoch in modes.items():
                start = time.perf_counter()
                count = epoch()
                rates[name].append(count / (time.perf_counter() - start))
                assert count == len(windows), (name, count)
    per_run = windows.windows_per_run
    print(
        f"{runs} runs of {duration:g} s at {args.rate:g} Hz, {len(windows)} windows of {length}"
        f" samples (stride {stride}), names {', '.join(NAMES)}; aaria dataset with 1 worker:"
        f" {made:.2f} runs/s"
    )
    reference = statistics.median(rates["file-backed, in order"])
    for name, values in rates.items():
        value = statistics.median(values)
        print(
            f"  {name:34s} {value:9.0f} windows/s {value / per_run:8.2f} runs/s"
            f"  {value / reference:7.1%} of the file"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
