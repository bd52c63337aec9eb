"""Throughput of ``aaria dataset`` with default settings (random DH arms, noise on, gzip).

    python benchmarks/bench_dataset.py          # 100 and 500 runs of 1,000 samples; 1, 2 workers
    python benchmarks/bench_dataset.py --smoke  # CI: 10 and 20 runs of 100 samples, no goal checked
    python benchmarks/bench_dataset.py --cluster  # a sharded job on a loopback Dask cluster
    python benchmarks/bench_dataset.py --cluster --runs 400

``--cluster`` starts ``dask scheduler`` and two ``dask worker`` processes (one thread each) on
loopback and makes a 40-run job of 2 s at 100 Hz in shards: it prints the client's CPU time
against the workers' (``getrusage`` in each process, before and after the job) and the bytes
the client process read and wrote meanwhile (``/proc/self/io``: sockets and the manifest).

The figure of the performance issue is the marginal throughput: the extra samples of the longer
job divided by its extra wall time, ``(500 - 100) × T / (t500 - t100)``, so worker start-up, the
run made before the workers fork and the file's creation cancel out. Whole jobs are timed
(simulation, compression in the workers, HDF5 writing in the main process); each figure is the
median over interleaved repeats (1 worker and 2 workers alternate, so both see the same machine),
and the two-worker ratio is the median of the per-repeat ratios of the marginal throughputs.
"""

from __future__ import annotations

import argparse
import os
import resource
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.apps.dataset.generate import generate_dataset

GOAL_ONE_WORKER = 250_000.0
"""Marginal samples/s on one worker (issue 25's goal; issue 15's was 150,000)."""
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


def _io_bytes() -> int:
    """Bytes this process has read and written so far (Linux; 0 elsewhere)."""
    try:
        fields = dict(line.split(": ") for line in Path("/proc/self/io").read_text().splitlines())
    except OSError:
        return 0
    return int(fields["rchar"]) + int(fields["wchar"])


def _cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def cluster_job(runs: int, duration: float, folder: Path) -> None:
    """A sharded job on a loopback cluster: the client's CPU and bytes against the workers'."""
    from dask.distributed import Client

    dask = [sys.executable, "-m", "dask"]
    file = folder / "scheduler.json"
    quiet = {"start_new_session": True, "stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
    processes = [
        subprocess.Popen(
            [*dask, "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
             "--scheduler-file", str(file)], **quiet,
        )
    ]  # fmt: skip
    try:
        while not file.exists():
            time.sleep(0.05)
        worker = [*dask, "worker", "--scheduler-file", str(file), "--nthreads", "1"]
        worker += ["--host", "127.0.0.1", "--no-dashboard"]
        processes += [subprocess.Popen(worker, **quiet) for _ in range(2)]
        with Client(scheduler_file=str(file), timeout=60) as client:
            client.wait_for_workers(2, timeout=120)
            address = client.scheduler.address
            spec = DhDatasetSpec(n_runs=runs, seed=1, duration=duration)
            generate_dataset(folder / "warm.h5", spec, scheduler=address)  # workers import
            workers_before = sum(client.run(_cpu).values())
            cpu, io, wall = _cpu(), _io_bytes(), time.perf_counter()
            report = generate_dataset(folder / "ds.h5", spec, scheduler=address)
            wall, cpu, io = time.perf_counter() - wall, _cpu() - cpu, _io_bytes() - io
            workers = sum(client.run(_cpu).values()) - workers_before
        shards = sum(path.stat().st_size for path in folder.glob("ds-*.h5"))
        manifest = (folder / "ds.h5").stat().st_size
        print(
            f"cluster job: {runs} runs of {duration:g} s at 100 Hz, 2 workers x 1 thread, "
            f"{report.shards} shards, {wall:.2f} s"
        )
        print(
            f"client CPU {cpu:.2f} s / workers' CPU {workers:.2f} s = {cpu / workers:.1%}; "
            f"client I/O {io:,} bytes (manifest {manifest:,}); shards {shards:,} bytes"
        )
    finally:
        for process in processes:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--smoke", action="store_true", help="tiny sizes, for CI")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--cluster", action="store_true", help="a sharded job on Dask")
    parser.add_argument("--runs", type=int, default=40, help="runs of the --cluster job")
    args = parser.parse_args()
    if args.cluster:
        with tempfile.TemporaryDirectory() as tmp:
            cluster_job(args.runs, 2.0, Path(tmp))
        return
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
