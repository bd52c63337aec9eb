"""Local worker processes of a data-set job: each makes runs and answers with their results.

The main process of a job (:func:`~.engine.generate_dataset`) is the only writer of the file;
the workers of a :class:`LocalRunner` make the runs (:func:`~.spec.run_result`, a few runs a
task: :func:`task_runs`) and send back their compressed chunks over a connection of their own,
so a worker that dies loses its own tasks only, which are made again.
"""

from __future__ import annotations

import contextlib
import itertools
import os
import sys
from collections import deque
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any

from aaria_pin.apps.dataset.spec import DatasetSpec, Result, run_result
from aaria_pin.core._malloc import tune_malloc

__all__ = [
    "ALONE_DEATHS",
    "MAX_TASK_RUNS",
    "SOCKET_BYTES",
    "TASK_SAMPLES",
    "LocalRunner",
    "task_runs",
]

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
    """A worker's task: :func:`~.spec.run_result` of each run, in order."""
    return [run_result(spec, run) for run in runs]


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


class LocalRunner:
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
