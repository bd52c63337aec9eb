"""Data sets on a Dask cluster: the workers write shards, the client a manifest over them.

The client connects to an existing Dask distributed scheduler, cuts the runs to make into
batches of consecutive runs (:func:`shard_runs`) and submits one task per batch
(:func:`write_shard_task`): the worker makes each run, writes it into the batch's shard beside
the output (:class:`~aaria_pin.files.dataset.manifest.ShardWriter`: temporary name, then renamed)
and returns a small :class:`ShardAck` (the shard's name, each run's row and CRC-32s, the runs
that failed). No run's arrays pass through the client: it writes the output as a manifest of
virtual datasets over the shards (:func:`~aaria_pin.files.dataset.manifest.write_manifest`) once
every task has answered, the empty manifest being laid out first, so ``--resume`` finds the
job's settings and shard prefix.

Faults: a worker that dies mid-task loses that task only; Dask runs it again on another worker
(up to its ``allowed-failures``), which writes the same shard name with the same bytes. A task
that still fails, or a shard that cannot be written (no space, no permission: one
:class:`~aaria_pin.errors.OutputFileError` line naming the shard), fails the runs of that shard
alone. ``resume`` checks every shard of the job on the workers
(:func:`~aaria_pin.files.dataset.manifest.verify_shard`: chunk CRC-32s against the stored ones),
keeps the intact rows and makes the rest. An overwrite writes its manifest beside the old data
set (:func:`~aaria_pin.files.dataset.store.partial_path`) and renames it over the old one once
every task has answered, then deletes the old data set's shards: a killed overwrite leaves the
old data set whole (the next overwrite deletes the killed one's shards and starts anew).
"""

from __future__ import annotations

import os
import time
import uuid
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from aaria_pin.apps.dataset.job import DatasetEstimate, DatasetJob
from aaria_pin.apps.dataset.spec import DatasetJobStoppedError, DatasetSpec, Result, run_result
from aaria_pin.errors import OutputFileError, ParameterError
from aaria_pin.files._stored import first_line
from aaria_pin.files.dataset.manifest import (
    ManifestContents,
    ManifestShards,
    RunLocation,
    ShardContents,
    ShardWriter,
    list_shards,
    read_manifest_shards,
    remove_unused_shards,
    shard_name,
    verify_shard,
    write_manifest,
)
from aaria_pin.files.dataset.store import partial_path

__all__ = [
    "SHARD_SAMPLES",
    "ShardAck",
    "connect",
    "generate_sharded",
    "shard_runs",
    "write_shard_task",
]

SHARD_SAMPLES = 100_000
"""Samples a shard holds at most, in whole runs (100 runs of 10 s at 100 Hz, about 35 MB)."""
TASKS_PER_THREAD = 4
"""Shards per worker thread at least, when the runs allow (to balance the load and lose little
when a worker dies)."""


@dataclass(frozen=True)
class ShardAck:
    """A shard task's answer to the client (a few hundred bytes, whatever the runs' size).

    Attributes:
        shard: the shard's file name
        rows: its number of rows
        stored: ``(run, row, CRC-32 per array)`` of each run written
        errors: ``(run, one-line error)`` of each run that failed
        run_seconds: CPU time of each run written, in its worker thread [s]
        bytes: the shard's size [bytes]
    """

    shard: str
    rows: int
    stored: tuple[tuple[int, int, tuple[int, ...]], ...]
    errors: tuple[tuple[int, str], ...]
    run_seconds: tuple[float, ...]
    bytes: int


def shard_runs(samples: int, runs: int, threads: int) -> int:
    """Runs per shard: enough shards for every thread, none too big, at least one run.

    At least :data:`TASKS_PER_THREAD` shards per thread when the runs allow, at most
    :data:`SHARD_SAMPLES` samples a shard.

    More, smaller shards balance the load and lose less when a worker dies; fewer keep the
    file count and the manifest's mappings (one per array and shard) small.
    """
    per_thread = -(-max(runs, 1) // (TASKS_PER_THREAD * max(threads, 1)))
    return max(1, min(per_thread, SHARD_SAMPLES // max(samples, 1)))


def write_shard_task(spec: DatasetSpec, runs: Sequence[int], folder: str, prefix: str) -> ShardAck:
    """A worker's task: make ``runs`` and write them into their shard in ``folder``.

    A run that raises is reported and leaves its row empty; a shard that cannot be written
    fails all its runs with the one-line reason (and leaves no file under the shard's name).
    """
    import time as clock

    name = shard_name(prefix, runs)
    stored: list[tuple[int, int, tuple[int, ...]]] = []
    errors: list[tuple[int, str]] = []
    seconds: list[float] = []
    size = 0
    try:
        with ShardWriter(
            Path(folder), prefix, runs, spec.samples, spec.dtype, spec.layout()
        ) as writer:
            for row, run in enumerate(runs):
                begin = clock.thread_time()
                _, encoded, error = run_result(spec, int(run))
                if encoded is None:
                    errors.append((int(run), error))
                    continue
                stored.append((int(run), row, writer.write_run(row, encoded)))
                seconds.append(clock.thread_time() - begin)
        size = writer.path.stat().st_size
    except OutputFileError as exc:
        failed = {run for run, _ in errors}
        errors += [(int(run), str(exc)) for run in runs if int(run) not in failed]
        stored, seconds = [], []
    return ShardAck(name, len(runs), tuple(stored), tuple(errors), tuple(seconds), size)


def connect(address: str) -> Any:
    """A Dask client of the scheduler at ``address``.

    Raises:
        ParameterError: Dask is missing, or no scheduler answers at ``address``.
    """
    try:
        from dask.distributed import Client
    except ImportError:
        raise ParameterError(
            parameter="scheduler",
            value=address,
            allowed="an address, with Dask installed (pip install 'aaria-pin[distributed]')",
        ) from None
    try:
        return Client(address, timeout=30)
    except (OSError, TimeoutError, ValueError) as exc:
        raise ParameterError(
            parameter="scheduler",
            value=address,
            allowed=f"the address of a running Dask scheduler (this one: {exc})",
        ) from None


class _QuietClientLog:
    """Dask's client log held to CRITICAL for a job (its reconnection errors are tracebacks)."""

    def __init__(self) -> None:
        import logging

        self._logger = logging.getLogger("distributed.client")
        self._level = self._logger.level
        self._logger.setLevel(logging.CRITICAL)

    def restore(self) -> None:
        """Put the log's level back."""
        self._logger.setLevel(self._level)


def _scheduler_lost(client: Any) -> bool:
    """Whether a Dask client has lost its scheduler (closed after failing to reconnect)."""
    return str(getattr(client, "status", "running")) not in ("running", "newly-created")


@dataclass
class _Job:
    """The client's view of a sharded job: where each run is, and what failed."""

    locations: dict[int, RunLocation]
    checksums: dict[int, tuple[int, ...]]
    failures: dict[int, str]

    def keep(self, contents: Sequence[ShardContents], n_runs: int) -> None:
        """Take the intact rows of verified shards (the first shard by name holding a run)."""
        for shard in sorted(contents, key=lambda c: c.name):
            for run, (row, checksums) in sorted(shard.intact.items()):
                if 0 <= run < n_runs and run not in self.locations:
                    self.locations[run] = RunLocation(shard.name, row, shard.rows)
                    self.checksums[run] = checksums

    def take(self, ack: ShardAck) -> None:
        """Record a shard's answer."""
        for run, row, checksums in ack.stored:
            self.locations[run] = RunLocation(ack.shard, row, ack.rows)
            self.checksums[run] = checksums
            self.failures.pop(run, None)
        for run, message in ack.errors:
            if run not in self.locations:  # a duplicate task's failure does not undo a run
                self.failures[run] = message


def estimate_from_runs(
    head: Sequence[Result], runs: int, workers: int, run_seconds: float
) -> DatasetEstimate:
    """A job's cost from runs made in this process before the workers start.

    Args:
        head: those runs' results (their encoded sizes give the bytes per run)
        runs: runs the job still makes
        workers: worker threads or processes that make them at once
        run_seconds: the fastest of those runs [s] (the first loads everything)
    """
    sizes = [
        sum(len(chunk) for chunks, _ in encoded.values() for chunk in chunks)
        for _, encoded, _ in head
        if encoded is not None
    ]
    per_run = sum(sizes) // len(sizes) if sizes else 0
    return DatasetEstimate(runs, per_run * runs, runs * run_seconds / workers, workers, run_seconds)


def _estimate(ack: ShardAck, runs: int, threads: int) -> DatasetEstimate | None:
    """The job's cost from its first shard.

    A shard's median run: a worker's first run (imports, compiled kernels) is left out when the
    shard has three runs or more.
    """
    if not ack.stored:
        return None
    ordered = sorted(ack.run_seconds)
    run_seconds = ordered[len(ordered) // 2]
    per_run = ack.bytes / len(ack.stored)
    return DatasetEstimate(
        runs, int(per_run * runs), runs * run_seconds / max(threads, 1), threads, run_seconds
    )


def generate_sharded(
    file: Path,
    spec: DatasetSpec,
    attributes: dict[str, Any],
    settings: DatasetJob,
    head: tuple[Sequence[Result], float] | None = None,
) -> tuple[int, int, dict[int, str], int]:
    """Make a data set on a Dask cluster as shards and a manifest (see the module docstring).

    The caller has checked the output path and, on resume, the settings.

    Args:
        file: the manifest (the output)
        spec: what the data set holds
        attributes: file attributes of a new data set
        settings: its ``scheduler`` (the Dask scheduler's address), ``shards`` (the shard folder;
            default: the output's folder; on resume, the job's), ``resume`` (continue the
            manifest at ``file``), ``progress`` (called as ``progress(done, total, seconds)``
            after each shard) and ``estimate`` (called once with the job's expected cost:
            before the shards are sent when ``head`` is given, else after the first shard)
        head: runs made in this process before the job (the caller's input check) and the
            fastest one's time [s], for the estimate before starting

    Returns:
        Runs written by this job, runs complete, failures, shards this job wrote.

    Raises:
        ParameterError: no scheduler at the address, a missing shard folder, or (resume) a file
            that was not written in shards.
        OutputFileError: the manifest cannot be written.
    """
    from dask.distributed import as_completed

    start = time.perf_counter()
    scheduler, shards, resume = settings.scheduler, settings.shards, settings.resume
    progress, estimate = settings.progress, settings.estimate
    if scheduler is None:
        raise ParameterError(
            parameter="scheduler", value=None, allowed="a Dask scheduler's address"
        )
    previous = read_manifest_shards(file) if file.is_file() else None  # the caller checked
    # An overwrite writes its manifest beside the old data set and replaces it at the end.
    manifest = partial_path(file) if file.is_file() and not resume else file
    folder = Path(shards) if shards is not None else None
    if folder is None:
        folder = previous.folder if resume and previous is not None else file.parent
    if not folder.is_dir():
        raise ParameterError(
            parameter="shards", value=str(folder), allowed="an existing folder for the shards"
        )
    # Absolute for the workers, whose working folder is their own (the manifest still maps
    # its shards by paths relative to itself).
    folder = folder.resolve()
    client = connect(scheduler)
    quiet = _QuietClientLog()  # a lost scheduler is told in one line, not the client's trace
    try:
        layout = spec.layout()
        job = _Job({}, {}, {})
        raw: dict[str, Any] | None = None
        if resume:
            assert previous is not None
            prefix, raw = previous.prefix, previous.raw_attributes
            paths = [str(path) for path in list_shards(folder, prefix)]
            futures = client.map(verify_shard, paths, prefix=prefix, names=layout.names, pure=False)
            job.keep(client.gather(futures), spec.n_runs)
        else:
            prefix = f"{file.stem}-{uuid.uuid4().hex[:8]}"
            stale = read_manifest_shards(manifest) if manifest != file else None
            if stale is not None:  # a killed overwrite's shards
                remove_unused_shards(stale.folder, stale.prefix, set())
            kept = ManifestShards(folder, prefix, {})
            new = ManifestContents(kept, spec.n_runs, spec.samples, spec.dtype, attributes, layout)
            write_manifest(manifest, new)
        todo = [k for k in range(spec.n_runs) if k not in job.locations]
        threads = max(1, sum(client.nthreads().values()))
        size = shard_runs(spec.samples, len(todo), threads)
        batches = [todo[i : i + size] for i in range(0, len(todo), size)]
        told = estimate is None
        if estimate is not None and head is not None and head[0]:
            estimate(estimate_from_runs(head[0], len(todo), threads, head[1]))
            told = True
        batch_of = {
            client.submit(write_shard_task, spec, batch, str(folder), prefix, pure=False): batch
            for batch in batches
        }
        done = 0
        lost: BaseException | None = None
        for future in as_completed(list(batch_of)):
            batch = batch_of.pop(future)
            try:
                ack = future.result()
            except Exception as exc:  # the cluster gave up on the task (its workers died)
                if _scheduler_lost(client):
                    lost = exc
                    break
                message = f"the cluster could not run it ({type(exc).__name__}: {first_line(exc)})"
                ack = ShardAck("", 0, (), tuple((run, message) for run in batch), (), 0)
            job.take(ack)
            done += len(batch)
            if not told and estimate is not None:
                cost = _estimate(ack, len(todo), threads)
                if cost is not None:
                    estimate(cost)
                    told = True
            if progress is not None:
                progress(done, len(todo), time.perf_counter() - start)
        contents = ManifestContents(
            ManifestShards(folder, prefix, raw or {}), spec.n_runs, spec.samples, spec.dtype,
            {} if resume else attributes, layout, job.locations, job.checksums, job.failures,
        )  # fmt: skip
        write_manifest(manifest, contents)
        if lost is not None:  # the runs so far are in the manifest; their shards are kept
            raise DatasetJobStoppedError(
                f"lost the Dask scheduler at {scheduler} ({type(lost).__name__}:"
                f" {first_line(lost) or 'closed'}): {len(job.locations)}/{spec.n_runs} runs saved"
                f" in {manifest}; the same command with --resume goes on once a scheduler is"
                " there",
                len(job.locations),
                spec.n_runs,
                parameter="path",
                value=str(file),
            )
        used = {location.shard for location in job.locations.values()}
        remove_unused_shards(folder, prefix, used)
        if manifest != file:  # the new data set is whole: it replaces the old one
            os.replace(manifest, file)
            if previous is not None:  # the overwritten data set's shards
                remove_unused_shards(previous.folder, previous.prefix, set())
    finally:
        client.close()
        quiet.restore()
    written = sum(1 for run in todo if run in job.locations)
    return written, len(job.locations), job.failures, len(batches)
