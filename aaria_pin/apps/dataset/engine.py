"""Data sets of many runs: deterministic, parallel, streamed to one HDF5 file, resumable.

One engine for every robot. A data set is described by a per-run spec
(:class:`~aaria_pin.apps.dataset.spec.DatasetSpec`; :class:`~.dh.DhDatasetSpec` for Aaria DH
arms, :class:`~.urdf.UrdfDatasetSpec` for a URDF robot) that
knows the data set's fixed layout and makes run k as a :class:`~aaria_pin.core.record.RunRecord`,
a pure function of its seed and k; the runners (local worker processes or a Dask cluster) and
the writer only call it, so the file is the same, array for array, whatever the robot, the
number of workers, the scheduler or the order in which runs finish. The main process is the only
writer: it writes each run as it arrives, marks it complete and flushes, so a killed job loses at
most the runs in flight, and ``resume`` redoes exactly those.
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

from aaria_pin.apps.dataset.dh import DhDatasetSpec
from aaria_pin.apps.dataset.spec import MAX_RUNS, DatasetSpec
from aaria_pin.apps.dataset.urdf import UrdfDatasetSpec, UrdfSource
from aaria_pin.core._malloc import tune_malloc
from aaria_pin.core.se3 import Array
from aaria_pin.errors import AariaError, ParameterError
from aaria_pin.files.dataset_file import (
    DatasetFile,
    EncodedRun,
    check_dataset_path,
    encode_run,
    read_dataset_attributes,
)

__all__ = [
    "MAX_RUNS",
    "DatasetReport",
    "DatasetSpec",
    "DhDatasetSpec",
    "UrdfDatasetSpec",
    "UrdfSource",
    "generate_dataset",
    "simulate_dataset_run",
]

FLUSH_SECONDS = 0.5
"""How often the writer pushes completed runs to disk [s] (a crash loses at most these)."""

Progress = Callable[[int, int, float], None]


def simulate_dataset_run(spec: DatasetSpec, run: int) -> dict[str, Array]:
    """The stored arrays of run ``run`` (series in the spec's dtype, inputs in float64).

    A pure function of spec and run; :meth:`DatasetSpec.make_run` gives it as a record.
    """
    return spec.arrays(run)


def _job(spec: DatasetSpec, run: int) -> tuple[int, EncodedRun | None, str]:
    """A worker's task: run ``run`` as compressed chunks, or its one-line error and inputs."""
    try:
        return run, encode_run(spec.layout(), spec.make_run(run), spec.dtype), ""
    except Exception as exc:  # any failure of one run is reported, and the others go on
        message = str(exc) if isinstance(exc, AariaError) else f"{type(exc).__name__}: {exc}"
        return run, None, f"{message} ({spec.describe_inputs(run)})"


Result = tuple[int, EncodedRun | None, str]
"""A run's outcome: its index, its encoded chunks (None if it failed), its error message."""

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
    """

    path: Path
    written: int
    complete: int
    failures: dict[int, str]
    seconds: float


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


class _DaskRunner:
    """An existing Dask distributed cluster, connected before the file is touched."""

    def __init__(self, address: str) -> None:
        try:
            from dask.distributed import Client
        except ImportError:
            raise ParameterError(
                parameter="scheduler",
                value=address,
                allowed="an address, with Dask installed (pip install 'aaria-pin[distributed]')",
            ) from None
        try:
            self._client = Client(address, timeout=30)
        except (OSError, TimeoutError, ValueError) as exc:
            raise ParameterError(
                parameter="scheduler",
                value=address,
                allowed=f"the address of a running Dask scheduler (this one: {exc})",
            ) from None

    def results(self, spec: DatasetSpec, runs: Sequence[int]) -> Iterator[Result]:
        """Results in completion order, at most four runs per worker thread in flight."""
        from dask.distributed import as_completed

        window = 4 * max(1, sum(self._client.nthreads().values()))
        pending = iter(runs)
        run_of: dict[Any, int] = {}

        def submit(run: int) -> Any:
            future = self._client.submit(_job, spec, run, pure=False)
            run_of[future] = run
            return future

        futures = as_completed([submit(k) for k in itertools.islice(pending, window)])
        for future in futures:
            run = run_of.pop(future)
            try:
                yield future.result()
            except Exception as exc:  # the cluster lost the worker: this run fails
                yield run, None, f"the cluster could not run it ({type(exc).__name__}: {exc})"
            for k in itertools.islice(pending, 1):
                futures.add(submit(k))

    def close(self) -> None:
        """Disconnect from the cluster."""
        self._client.close()


def generate_dataset(
    path: str | os.PathLike[str],
    spec: DatasetSpec,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    resume: bool = False,
    overwrite: bool = False,
    progress: Progress | None = None,
) -> DatasetReport:
    """Simulate the runs of a data set and stream them into one HDF5 file.

    Args:
        path: the ``.h5`` file
        spec: what the data set holds
        workers: local worker processes (default: the number of cores)
        scheduler: address of a Dask distributed scheduler (instead of local workers)
        resume: continue an existing file (same spec), redoing the runs that are not complete
        overwrite: replace an existing file
        progress: called as ``progress(done, total, seconds)`` after each run

    Returns:
        What the job did; failed runs are listed there and in the file.

    Raises:
        OutputFileError: the file exists without ``resume``/``overwrite``, or cannot be made.
        InputFileError: the file to resume is missing or is not a data set.
        ParameterError: the file to resume holds another spec.
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
    if resume:  # compare settings read-only first: a mismatch changes nothing
        different = spec.mismatches(read_dataset_attributes(file))
        if different:
            raise ParameterError(
                f"{file}: was made with other settings ({', '.join(different)}); allowed: the"
                " same settings as the job that made it"
            )
    if scheduler is None:
        tune_malloc()
        # One run made here loads Pinocchio and the compiled kernels before the workers fork,
        # so none of them has to load them again; it is kept if the file still needs it.
        warm = _job(spec, 0)
    runner: _LocalRunner | _DaskRunner = (
        _DaskRunner(scheduler) if scheduler else _LocalRunner(workers)
    )
    written = 0
    try:
        if resume:
            store = DatasetFile.open_for_resume(file)
            store.clear_failures()
        else:
            store = DatasetFile.create(
                file, spec.n_runs, spec.samples, spec.dtype, spec.attributes(), spec.layout()
            )
        with store:
            todo = [int(k) for k in np.flatnonzero(~store.complete_runs())]
            head = [warm] if scheduler is None and todo and todo[0] == 0 else []
            rest = todo[len(head) :]
            last_flush = time.perf_counter()
            results = itertools.chain(head, runner.results(spec, rest) if rest else ())
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
    return DatasetReport(file, written, complete, failures, time.perf_counter() - start)
