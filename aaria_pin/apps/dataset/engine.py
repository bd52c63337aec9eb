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
cluster the workers write shards and the client a manifest over them (:mod:`.manifest`).

Faults: the output's lock is held for the whole job (a second job on it is refused at once);
run 0 is made before the output is touched, so a fixed input no run can use is refused in one
line and an existing data set stays as it was; Ctrl-C, a full disk and a lost Dask scheduler
stop the job with :class:`~.spec.DatasetJobStoppedError` (one line: the runs saved, ``resume``
goes on); a killed local worker loses its own tasks only, which are made again.
"""

from __future__ import annotations

import contextlib
import itertools
import os
import sys
import time
from collections import deque
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin._version import __version__
from aaria_pin.apps.dataset.card_file import store_card
from aaria_pin.apps.dataset.dh import DhDatasetSpec
from aaria_pin.apps.dataset.shards import (
    DatasetEstimate,
    Estimate,
    estimate_from_runs,
    generate_sharded,
)
from aaria_pin.apps.dataset.spec import (
    MAX_RUNS,
    DatasetJobStoppedError,
    DatasetSpec,
    Result,
    check_first_run,
    run_result,
)
from aaria_pin.apps.dataset.urdf import UrdfDatasetSpec, UrdfSource
from aaria_pin.core._malloc import tune_malloc
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError
from aaria_pin.files.dataset.manifest import read_manifest_shards, remove_unused_shards
from aaria_pin.files.dataset.resume import dataset_progress, read_dataset_attributes
from aaria_pin.files.dataset.store import DatasetFile, check_dataset_path
from aaria_pin.files.paths import no_space

__all__ = [
    "MAX_RUNS",
    "DatasetEstimate",
    "DatasetJobStoppedError",
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


SOCKET_BYTES = 1 << 20
"""Buffer asked for each worker's result socket [bytes] (the system may grant less)."""


def _widen(connection: Any) -> None:
    """Let a worker hand a run to the parent in fewer writes (a larger socket buffer).

    A run's result is about 350 kB of compressed chunks (1,000 samples, 14 IMUs); with a
    64 kB pipe the worker waited for the parent to drain it five times a run (measured with
    the earlier process pool: a worker's idle time between two runs fell from 1.2 ms to
    0.55 ms, of about 10 ms a run, with a 1 MB pipe). Where the system refuses, nothing
    changes.
    """
    import socket

    try:
        sock = socket.socket(fileno=os.dup(connection.fileno()))
    except OSError:  # pragma: no cover - not a socket (another platform's pipe)
        return
    try:
        for option in (socket.SO_SNDBUF, socket.SO_RCVBUF):
            sock.setsockopt(socket.SOL_SOCKET, option, SOCKET_BYTES)
    except OSError:  # pragma: no cover - refused
        pass
    finally:
        sock.close()


def _worker_main(connection: Any, inherited: Sequence[Any]) -> None:
    """A local worker: take the spec, then tasks (run tuples) until None; answer each task.

    The parent's ends of the other workers' connections, inherited through ``fork``, are
    closed first. A worker that loses its parent (pipe closed) ends quietly.
    """
    for other in inherited:
        other.close()
    _worker_setup()
    spec: DatasetSpec | None = None
    try:
        while True:
            message = connection.recv()
            if message is None:
                return
            if isinstance(message, DatasetSpec):
                spec = message
                continue
            assert spec is not None
            connection.send(_jobs(spec, message))
    except (EOFError, OSError):
        return


@dataclass
class _Worker:
    """One local worker process, its connection and the tasks it holds, oldest first."""

    process: Any
    connection: Any
    tasks: deque[tuple[int, ...]] = field(default_factory=deque)
    retrying: bool = False  # its one task is a lost run tried again by itself

    def send(self, message: Any) -> None:
        """Send the spec, a task or None; a worker that died meanwhile is found by the reader.

        Its connection then reads as ended, and its tasks, this one included, are lost runs.
        """
        with contextlib.suppress(OSError):
            self.connection.send(message)


ALONE_DEATHS = 2
"""Deaths of a worker running a lost run alone after which that run is failed."""


class _LocalRunner:
    """Local worker processes, each with a connection of its own to the parent.

    Started before the data set file is opened (a replacement started later inherits it but
    never touches it). A worker that dies closes its connection: the parent reads the end of
    it at once (never a hang on a half-written answer, which a pool's shared result pipe
    allows), and only that worker's tasks are lost; they are tried again one at a time, each
    alone on a worker, so only a run whose worker dies :data:`ALONE_DEATHS` times while it runs
    alone fails ("a worker process died during this run"): a run that kills its worker, not
    one whose worker was killed from outside (the OOM killer, a user) once.

    Why not ``concurrent.futures.ProcessPoolExecutor``: its workers share one result pipe, and a
    worker killed while writing its answer left the pool's manager blocked on that pipe for
    good (2 of 12 trials in issue 18, Ctrl-C ignored); a dead worker also broke the whole pool,
    losing every task in flight. Measured here: 8 workers killed at random points of 4 jobs
    (``tests/apps/test_dataset_faults.py``), no hang, the arrays identical; a 300-run job of
    1,000 samples on two workers takes 0.97 of the pool's time (median of 3, a loaded machine).
    """

    def __init__(self, workers: int) -> None:
        import multiprocessing

        method = "fork" if sys.platform.startswith("linux") else "spawn"
        self._context: Any = multiprocessing.get_context(method)
        self._fork = method == "fork"
        self._workers = [self._start() for _ in range(workers)]

    def _start(self) -> _Worker:
        parent, child = self._context.Pipe(duplex=True)
        inherited = [worker.connection for worker in getattr(self, "_workers", ())]
        process = self._context.Process(
            target=_worker_main,
            args=(child, inherited if self._fork else []),
            daemon=True,
        )
        process.start()
        child.close()  # the worker's end lives in the worker only: its death is our EOF
        _widen(parent)
        return _Worker(process, parent)

    def _replace(self, worker: _Worker, spec: DatasetSpec) -> None:
        """Start a fresh worker in a dead one's place."""
        worker.connection.close()
        worker.process.join(timeout=5)
        fresh = self._start()
        fresh.send(spec)
        self._workers[self._workers.index(worker)] = fresh

    def results(self, spec: DatasetSpec, runs: Iterable[int]) -> Iterator[Result]:
        """Results in completion order, a few tasks per worker in flight (:func:`task_runs`)."""
        from multiprocessing.connection import wait

        size = task_runs(spec.samples)
        iterator = iter(runs)
        pending = iter(lambda: tuple(itertools.islice(iterator, size)), ())
        depth = max(2, 4 // size)
        retry: deque[int] = deque()
        deaths: dict[int, int] = {}  # lost runs' workers that died while they ran alone
        for worker in self._workers:
            worker.send(spec)
        while True:
            for worker in self._workers:
                if worker.retrying:
                    continue
                if retry:  # lost runs first, each alone on an idle worker
                    if not worker.tasks:
                        run = retry.popleft()
                        worker.tasks.append((run,))
                        worker.retrying = True
                        worker.send((run,))
                    continue
                while len(worker.tasks) < depth:
                    batch = next(pending, None)
                    if batch is None:
                        break
                    worker.tasks.append(batch)
                    worker.send(batch)
            busy = {worker.connection: worker for worker in self._workers if worker.tasks}
            if not busy:
                return
            for ready in wait(list(busy)):
                worker = busy[ready]
                try:
                    results: list[Result] = worker.connection.recv()
                except (EOFError, OSError):
                    lost = list(itertools.chain.from_iterable(worker.tasks))
                    if worker.retrying:
                        run = lost[0]
                        deaths[run] = deaths.get(run, 0) + 1
                        if deaths[run] >= ALONE_DEATHS:
                            yield run, None, "a worker process died during this run"
                        else:
                            retry.append(run)
                    else:
                        retry.extend(lost)
                    self._replace(worker, spec)
                    continue
                worker.tasks.popleft()
                worker.retrying = False
                yield from results

    def close(self) -> None:
        """Stop the workers: idle ones are told to end, busy ones (a job stopped) are killed.

        Closing again does nothing.
        """
        workers, self._workers = self._workers, []
        for worker in workers:
            if worker.tasks:
                worker.process.kill()
            else:
                worker.send(None)
        for worker in workers:
            worker.process.join(timeout=5)
            if worker.process.is_alive():  # pragma: no cover - a worker stuck in a run
                worker.process.kill()
                worker.process.join()
            worker.connection.close()


def _incomplete_runs(complete: np.ndarray, skip: set[int]) -> Iterator[int]:
    """The runs whose flag is 0, in order, but those in ``skip`` (a block of flags at a time)."""
    block = 1 << 16
    for begin in range(0, complete.size, block):
        for offset in np.flatnonzero(complete[begin : begin + block] == 0):
            run = begin + int(offset)
            if run not in skip:
                yield run


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
    manifest of virtual datasets over them that reads as one file (:mod:`.manifest`); the arrays
    are the same either way.

    The output's lock (:func:`~aaria_pin.files.io.output_lock`) is held for the whole job: a
    second job on the same output is refused at once, whatever its flags. Run 0's inputs (every
    fixed input and one draw of the random ones) are checked, and run 0 made, before the output
    is touched (:func:`~.spec.check_first_run`). Resuming a one-file data set that is complete
    (every run flagged, no failure, and its card, which a job stores after its last flush)
    returns at once without reading its runs; a manifest's resume always checks its shards.

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
        OutputFileError: the file exists without ``resume``/``overwrite``, cannot be made, or
            another process is writing it.
        InputFileError: the file to resume is missing or is not a data set.
        ParameterError: the file to resume holds another spec, or was written the other way
            (in shards, or in one file); ``shards`` without ``scheduler``; an empty
            ``scheduler``; run 0's inputs refused.
        DatasetJobStoppedError: Ctrl-C, no space left on the device, or the Dask scheduler lost:
            the runs saved so far are kept (``resume`` goes on).
    """
    start = time.perf_counter()
    file = Path(path)
    if scheduler is not None and not scheduler.strip():
        raise ParameterError(
            parameter="scheduler",
            value=scheduler,
            allowed="a Dask scheduler's address, e.g. tcp://host:8786 (without it: local workers)",
        )
    if shards is not None and scheduler is None:
        raise ParameterError(
            parameter="shards", value=str(shards), allowed="a folder with a scheduler only"
        )
    if workers is None:  # the cores this process may use
        workers = (
            len(os.sched_getaffinity(0))
            if hasattr(os, "sched_getaffinity")
            else (os.cpu_count() or 1)
        )
    if workers < 1:
        raise ParameterError(parameter="workers", value=workers, allowed=">= 1")
    check_dataset_path(file, resume, overwrite)  # also: its lock held elsewhere
    if resume:  # compare settings read-only first: a mismatch changes nothing
        stored = read_dataset_attributes(file)
        different = spec.mismatches(stored)
        if different:
            raise ParameterError(
                f"{file}: was made with other settings ({', '.join(different)}); allowed:"
                " the same settings as the job that made it"
            )
        if scheduler is None and "shard_prefix" in stored:
            raise ParameterError(
                parameter="scheduler",
                value=None,
                allowed=f"a Dask scheduler's address: {file} was written in shards",
            )
        if scheduler is not None and "shard_prefix" not in stored:
            raise ParameterError(
                parameter="scheduler",
                value=scheduler,
                allowed=f"none: {file} was written by local workers in one file (resume it with "
                "--workers)",
            )
        if scheduler is None:  # a manifest's resume checks its shards: they may be gone
            complete, total, no_failure = dataset_progress(file)
            if complete == total and no_failure and "card" in stored:  # its job ended
                return DatasetReport(file, 0, complete, {}, time.perf_counter() - start)
    try:
        return _generate(
            file, spec, workers, scheduler, shards, resume, overwrite, progress, estimate,
            command, start,
        )  # fmt: skip
    except KeyboardInterrupt:
        saved = _saved_runs(file)
        shown = "no run" if not saved else f"{saved}/{spec.n_runs} runs"
        raise DatasetJobStoppedError(
            f"interrupted: {shown} saved in {file}; the same command with --resume goes on",
            saved,
            spec.n_runs,
            exit_status=130,
        ) from None


def _saved_runs(file: Path) -> int | None:
    """Runs complete in a data set file after a stopped job (None: it cannot be read)."""
    if not file.is_file():
        return 0
    try:
        return dataset_progress(file)[0]
    except Exception:  # a file left unreadable by the failure itself
        return None


def _generate(
    file: Path,
    spec: DatasetSpec,
    workers: int,
    scheduler: str | None,
    shards: str | os.PathLike[str] | None,
    resume: bool,
    overwrite: bool,
    progress: Progress | None,
    estimate: Estimate | None,
    command: str,
    start: float,
) -> DatasetReport:
    """:func:`generate_dataset` after its read-only checks.

    Run 0 is made (its inputs checked) and the local workers are started before the output's
    lock is taken, so no worker inherits the lock (a killed job's lock goes with its main
    process); the lock is then held until the file is complete.
    """
    from aaria_pin.files.io import output_lock

    tune_malloc()
    # Run 0 checks the inputs before the output is touched; it loads Pinocchio and the compiled
    # kernels before the workers fork, so none of them has to load them again, and it is kept
    # if the file still needs it. For the estimate, two more are timed (the faster counts:
    # another structure may compile a kernel).
    begin = time.perf_counter()
    head = [check_first_run(spec)]
    run_seconds = time.perf_counter() - begin  # an upper bound: it loads everything
    attributes = {**spec.attributes(), "command": command, "versions": software_versions()}
    for run in range(1, min(3, spec.n_runs) if estimate is not None else 1):
        begin = time.perf_counter()
        head.append(_job(spec, run))
        run_seconds = min(run_seconds, time.perf_counter() - begin)
    if scheduler is not None:
        with output_lock(file):
            check_dataset_path(file, resume, overwrite)
            written, complete, failures, count = generate_sharded(
                file,
                spec,
                attributes,
                scheduler=scheduler,
                shards=shards,
                resume=resume,
                progress=progress,
                estimate=estimate,
                head=(head, run_seconds),
            )
            store_card(file)
        return DatasetReport(file, written, complete, failures, time.perf_counter() - start, count)
    runner = _LocalRunner(workers)
    try:
        with output_lock(file):
            try:
                check_dataset_path(file, resume, overwrite)
                written, complete, failures = _write_local(
                    file, spec, attributes, runner, head, resume, overwrite, progress, estimate,
                    workers, run_seconds, start,
                )  # fmt: skip
            finally:
                runner.close()  # a worker started after the file was opened holds it open
            store_card(file)
    finally:
        runner.close()
    return DatasetReport(file, written, complete, failures, time.perf_counter() - start)


def _write_local(
    file: Path,
    spec: DatasetSpec,
    attributes: dict[str, Any],
    runner: _LocalRunner,
    head: list[Result],
    resume: bool,
    overwrite: bool,
    progress: Progress | None,
    estimate: Estimate | None,
    workers: int,
    run_seconds: float,
    start: float,
) -> tuple[int, int, dict[int, str]]:
    """Make (or reopen) the file and write every run it still needs; written, complete, failed.

    Raises:
        DatasetJobStoppedError: no space left on the device (the runs flagged so far kept).
    """
    previous = read_manifest_shards(file) if overwrite and file.is_file() else None
    written = 0
    if resume:
        store = DatasetFile.open_for_resume(file)
        store.clear_failures()
    else:
        store = DatasetFile.create(
            file, spec.n_runs, spec.samples, spec.dtype, attributes, spec.layout()
        )
        if previous is not None:  # the shards of the data set this one replaces
            remove_unused_shards(previous.folder, previous.prefix, set())
    try:
        complete_flags = store.complete_runs()
        todo = int(complete_flags.size - np.count_nonzero(complete_flags))
        kept = [result for result in head if not complete_flags[result[0]]]
        if estimate is not None:
            estimate(estimate_from_runs(head, todo, workers, run_seconds))
        rest = _incomplete_runs(complete_flags, {result[0] for result in kept})
        last_flush = time.perf_counter()
        results = itertools.chain(kept, runner.results(spec, rest))
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
                progress(done, todo, time.perf_counter() - start)
        store.flush()
        complete = int(np.count_nonzero(store.complete_runs()))
        failures = store.failures()
    except KeyboardInterrupt:
        store.close()  # the runs received so far are flagged and kept
        raise
    except BaseException as exc:
        store.abandon()
        if no_space(exc):
            saved = _saved_runs(file)
            shown = "no run" if not saved else f"{saved}/{spec.n_runs} runs"
            raise DatasetJobStoppedError(
                f"no space left on device writing {file}: {shown} saved; free some space"
                " and run the same command with --resume to go on",
                saved,
                spec.n_runs,
            ) from None
        raise
    store.close()
    return written, complete, failures
