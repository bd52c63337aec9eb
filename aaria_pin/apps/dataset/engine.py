"""Data sets of many runs: deterministic, parallel, streamed to one HDF5 file, resumable.

One engine for every robot. A data set is described by a per-run spec
(:class:`~aaria_pin.apps.dataset.spec.DatasetSpec`; :class:`~.dh.DhDatasetSpec` for Aaria DH
arms, :class:`~.urdf.UrdfDatasetSpec` for a URDF robot) that
knows the data set's fixed layout and makes run k as a :class:`~aaria_pin.core.record.RunRecord`,
a pure function of its seed and k; the runners (local worker processes or a Dask cluster) and
the writer only call it, so the file is the same, array for array, whatever the robot, the
number of workers, the scheduler or the order in which runs finish. With local workers the main
process is the only writer: it writes each run as it arrives, marks it complete and flushes, so
a killed job loses at most the runs in flight, and ``resume`` redoes exactly those. On a Dask
cluster the workers write shards and the client a manifest over them (:mod:`.shards`).
"""

from __future__ import annotations

import itertools
import os
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin._version import __version__
from aaria_pin.apps.dataset.card import store_card
from aaria_pin.apps.dataset.dh import DhDatasetSpec
from aaria_pin.apps.dataset.shards import DatasetEstimate, Estimate, generate_sharded
from aaria_pin.apps.dataset.spec import MAX_RUNS, DatasetSpec, Result, run_result
from aaria_pin.apps.dataset.urdf import UrdfDatasetSpec, UrdfSource
from aaria_pin.core._malloc import tune_malloc
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError
from aaria_pin.files.dataset.shards import read_manifest_shards, remove_unused_shards
from aaria_pin.files.dataset_file import DatasetFile, check_dataset_path, read_dataset_attributes

__all__ = [
    "MAX_RUNS",
    "DatasetEstimate",
    "DatasetReport",
    "DatasetSpec",
    "DhDatasetSpec",
    "UrdfDatasetSpec",
    "UrdfSource",
    "generate_dataset",
    "simulate_dataset_run",
    "software_versions",
]

FLUSH_SECONDS = 0.5
"""How often the writer pushes completed runs to disk [s] (a crash loses at most these)."""

Progress = Callable[[int, int, float], None]


def simulate_dataset_run(spec: DatasetSpec, run: int) -> dict[str, Array]:
    """The stored arrays of run ``run`` (series in the spec's dtype, inputs in float64).

    A pure function of spec and run; :meth:`DatasetSpec.make_run` gives it as a record.
    """
    return spec.arrays(run)


_job = run_result
"""A worker's work on one run (:func:`~.spec.run_result`)."""

TASK_SAMPLES = 4000
"""Samples a local worker's task holds at most, in whole runs (:func:`task_runs`)."""
MAX_TASK_RUNS = 8
"""Most runs in one task."""


def task_runs(samples: int) -> int:
    """Runs per local worker task: as many as :data:`TASK_SAMPLES` samples hold, 1 to 8.

    Each task costs the parent a submission, wake-ups of its threads and a result message
    whatever its size, about 1 ms of the parent's CPU; with two workers the parent shares their
    two cores. Measured (2 cores, runs of 1,000 samples, two workers): the parent's CPU per run
    fell from 2.1 ms with one run a task to 1.3 ms with four. A long run (4,000 samples or more)
    is a task of its own.
    """
    return max(1, min(MAX_TASK_RUNS, TASK_SAMPLES // max(samples, 1)))


def _jobs(spec: DatasetSpec, runs: tuple[int, ...]) -> list[Result]:
    """A worker's task: :func:`_job` of each run, in order."""
    return [_job(spec, run) for run in runs]


@dataclass(frozen=True)
class DatasetReport:
    """What a job did.

    Attributes:
        path: the data set file
        written: runs written by this job
        complete: runs complete in the file
        failures: failed runs and their errors
        seconds: wall time of this job [s]
        shards: shard files this job wrote (0: one file, local workers)
    """

    path: Path
    written: int
    complete: int
    failures: dict[int, str]
    seconds: float
    shards: int = 0


def software_versions() -> dict[str, str]:
    """Versions of aaria_pin, Pinocchio, NumPy, h5py, HDF5 and Python, by name.

    The ``versions`` attribute of a data set; Pinocchio's is read from its package metadata,
    without importing it.
    """
    import platform
    from importlib import metadata

    import h5py

    def installed(*names: str) -> str:
        for name in names:
            try:
                return metadata.version(name)
            except metadata.PackageNotFoundError:
                continue
        return ""

    return {
        "aaria_pin": __version__,
        "pinocchio": installed("pin", "pinocchio"),
        "numpy": np.__version__,
        "h5py": h5py.__version__,
        "hdf5": h5py.version.hdf5_version,
        "python": platform.python_version(),
    }


def _worker_setup() -> None:
    """In each local worker: leave Ctrl-C to the parent, die with it, keep freed memory."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:  # Linux: the kernel kills the worker when its parent dies (no orphan holds the file)
        import ctypes

        ctypes.CDLL(None).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):  # pragma: no cover - not Linux
        pass
    tune_malloc()


RESULT_PIPE_BYTES = (1 << 20, 1 << 19, 1 << 18)
"""Sizes tried for the workers' result pipe [bytes] (Linux allows 1 MB without privileges)."""


def _widen_result_pipe(pool: Any) -> None:
    """Let a worker hand a whole run to the parent in one write (Linux: a pipe of up to 1 MB).

    A run's result is about 350 kB of compressed chunks (1,000 samples, 14 IMUs) and the
    executor's result pipe holds 64 kB, so the worker waited for the parent to drain it five
    times a run: measured, a worker's idle time between two runs fell from 1.2 ms to 0.55 ms
    (of about 10 ms a run) with a 1 MB pipe. The pipe is the executor's own (a private
    attribute of ``ProcessPoolExecutor``); where it is missing, or the system refuses the size,
    nothing changes.
    """
    try:
        import fcntl

        descriptor = pool._result_queue._reader.fileno()
        resize = fcntl.F_SETPIPE_SZ
    except (AttributeError, ImportError, OSError):  # pragma: no cover - not Linux, or changed
        return
    for size in RESULT_PIPE_BYTES:
        try:
            fcntl.fcntl(descriptor, resize, size)
            return
        except OSError:  # pragma: no cover - above the system's pipe-max-size
            continue


class _LocalRunner:
    """Local worker processes, started before the data set file is opened (none inherits it)."""

    def __init__(self, workers: int) -> None:
        import multiprocessing

        method = "fork" if sys.platform.startswith("linux") else "spawn"
        self._context = multiprocessing.get_context(method)
        self._workers = workers
        self._pool = self._start()

    def _start(self) -> Any:
        from concurrent.futures import ProcessPoolExecutor

        pool = ProcessPoolExecutor(self._workers, self._context, initializer=_worker_setup)
        _widen_result_pipe(pool)
        for future in [pool.submit(int, 0) for _ in range(self._workers)]:
            future.result()  # fork now
        return pool

    def results(self, spec: DatasetSpec, runs: Sequence[int]) -> Iterator[Result]:
        """Results in completion order, a few tasks per worker in flight (:func:`task_runs`).

        A worker that dies breaks the pool, and every task in flight is lost with it: the pool
        is replaced and the lost runs are tried again one at a time, alone in the pool, so only
        the run that kills its worker again fails ("a worker process died during this run");
        the runs that shared its task or the pool with it are kept.
        """
        from collections import deque
        from concurrent.futures import FIRST_COMPLETED, wait
        from concurrent.futures.process import BrokenProcessPool

        size = task_runs(spec.samples)
        pending = (tuple(runs[i : i + size]) for i in range(0, len(runs), size))
        window = self._workers * max(2, 4 // size)
        in_flight: dict[Any, tuple[int, ...]] = {}
        retry: deque[int] = deque()
        alone = False  # the one task in flight is a lost run tried again by itself
        while True:
            if retry:
                if not in_flight:
                    run = retry.popleft()
                    in_flight[self._pool.submit(_jobs, spec, (run,))] = (run,)
                    alone = True
            else:
                alone = False
                for batch in itertools.islice(pending, window - len(in_flight)):
                    in_flight[self._pool.submit(_jobs, spec, batch)] = batch
            if not in_flight:
                return
            done, _ = wait(in_flight, return_when=FIRST_COMPLETED)
            for future in done:
                batch = in_flight.pop(future)
                try:
                    results = future.result()
                except BrokenProcessPool:
                    lost = [*batch, *itertools.chain.from_iterable(in_flight.values())]
                    in_flight.clear()
                    self._pool.shutdown(wait=False, cancel_futures=True)
                    self._pool = self._start()
                    if alone:
                        yield batch[0], None, "a worker process died during this run"
                    else:
                        retry.extend(lost)
                    break
                yield from results

    def close(self) -> None:
        """Stop the workers: queued runs are cancelled, running ones finish."""
        self._pool.shutdown(wait=True, cancel_futures=True)


def generate_dataset(
    path: str | os.PathLike[str],
    spec: DatasetSpec,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    shards: str | os.PathLike[str] | None = None,
    resume: bool = False,
    overwrite: bool = False,
    progress: Progress | None = None,
    estimate: Estimate | None = None,
    command: str = "",
) -> DatasetReport:
    """Simulate the runs of a data set and stream them into one HDF5 file.

    With local workers the file holds every run. With a Dask ``scheduler`` the workers write
    the runs into shard files (in ``shards``, default the output's folder) and the file is a
    manifest of virtual datasets over them that reads as one file (:mod:`.shards`); the arrays
    are the same either way.

    Args:
        path: the ``.h5`` file
        spec: what the data set holds
        workers: local worker processes (default: the number of cores)
        scheduler: address of a Dask distributed scheduler (instead of local workers)
        shards: the folder of the shards, on storage every Dask worker reaches (with
            ``scheduler`` only)
        resume: continue an existing file (same spec), redoing the runs that are not complete
        overwrite: replace an existing file (and its shards)
        progress: called as ``progress(done, total, seconds)`` after each run (each shard on a
            cluster)
        estimate: called once before the bulk of the runs with the job's expected size and time
            (from the first runs)
        command: the command line that asked for the data set (attribute ``command``)

    Returns:
        What the job did; failed runs are listed there and in the file.

    Raises:
        OutputFileError: the file exists without ``resume``/``overwrite``, or cannot be made.
        InputFileError: the file to resume is missing or is not a data set.
        ParameterError: the file to resume holds another spec, or was written the other way
            (in shards, or in one file), or ``shards`` without ``scheduler``.
    """
    start = time.perf_counter()
    file = Path(path)
    check_dataset_path(file, resume, overwrite)
    if workers is None:  # the cores this process may use
        workers = (
            len(os.sched_getaffinity(0))
            if hasattr(os, "sched_getaffinity")
            else (os.cpu_count() or 1)
        )
    if workers < 1:
        raise ParameterError(parameter="workers", value=workers, allowed=">= 1")
    if shards is not None and scheduler is None:
        raise ParameterError(
            parameter="shards", value=str(shards), allowed="a folder with a scheduler only"
        )
    if resume:  # compare settings read-only first: a mismatch changes nothing
        stored = read_dataset_attributes(file)
        different = spec.mismatches(stored)
        if different:
            raise ParameterError(
                f"{file}: was made with other settings ({', '.join(different)}); allowed: the"
                " same settings as the job that made it"
            )
        if scheduler is None and "shard_prefix" in stored:
            raise ParameterError(
                parameter="scheduler",
                value=None,
                allowed=f"a Dask scheduler's address: {file} was written in shards",
            )
    attributes = {**spec.attributes(), "command": command, "versions": software_versions()}
    if scheduler is not None:
        written, complete, failures, count = generate_sharded(
            file,
            spec,
            attributes,
            scheduler=scheduler,
            shards=shards,
            resume=resume,
            progress=progress,
            estimate=estimate,
        )
        store_card(file)
        return DatasetReport(file, written, complete, failures, time.perf_counter() - start, count)
    previous = read_manifest_shards(file) if overwrite and file.is_file() else None
    tune_malloc()
    # One run made here loads Pinocchio and the compiled kernels before the workers fork, so
    # none of them has to load them again; it is kept if the file still needs it. For the
    # estimate, two more are timed (the faster counts: another structure may compile a kernel).
    begin = time.perf_counter()
    head = [_job(spec, 0)]
    run_seconds = time.perf_counter() - begin  # an upper bound: it loads everything
    for run in range(1, min(3, spec.n_runs) if estimate is not None else 1):
        begin = time.perf_counter()
        head.append(_job(spec, run))
        run_seconds = min(run_seconds, time.perf_counter() - begin)
    runner = _LocalRunner(workers)
    written = 0
    try:
        if resume:
            store = DatasetFile.open_for_resume(file)
            store.clear_failures()
        else:
            store = DatasetFile.create(
                file, spec.n_runs, spec.samples, spec.dtype, attributes, spec.layout()
            )
            if previous is not None:  # the shards of the data set this one replaces
                remove_unused_shards(previous.folder, previous.prefix, set())
        with store:
            todo = [int(k) for k in np.flatnonzero(~store.complete_runs())]
            wanted = set(todo)
            kept = [result for result in head if result[0] in wanted]
            if estimate is not None:
                estimate(_local_estimate(head, len(todo), workers, run_seconds))
            rest = [k for k in todo if k not in {result[0] for result in kept}]
            last_flush = time.perf_counter()
            results = itertools.chain(kept, runner.results(spec, rest) if rest else ())
            for done, (run, arrays, error) in enumerate(results, start=1):
                if arrays is None:
                    store.mark_failed(run, error)
                else:
                    store.write_run(run, arrays)
                    written += 1
                if time.perf_counter() - last_flush > FLUSH_SECONDS:
                    store.flush()
                    last_flush = time.perf_counter()
                if progress is not None:
                    progress(done, len(todo), time.perf_counter() - start)
            store.flush()
            complete = int(store.complete_runs().sum())
            failures = store.failures()
    finally:
        runner.close()
    store_card(file)
    return DatasetReport(file, written, complete, failures, time.perf_counter() - start)


def _local_estimate(
    head: Sequence[Result], runs: int, workers: int, run_seconds: float
) -> DatasetEstimate:
    """A local job's cost from the runs made before the workers start (the first one apart)."""
    sizes = [
        sum(len(chunk) for chunks, _ in encoded.values() for chunk in chunks)
        for _, encoded, _ in head
        if encoded is not None
    ]
    per_run = sum(sizes) // len(sizes) if sizes else 0
    return DatasetEstimate(runs, per_run * runs, runs * run_seconds / workers, workers, run_seconds)
