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

import itertools
import os
import time
from collections.abc import Iterator
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Unpack

import numpy as np

from aaria_pin.apps.dataset.card_file import store_card
from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.apps.dataset.job import (
    DatasetEstimate,
    DatasetJob,
    DatasetJobOptions,
    DatasetReport,
    Progress,
    software_versions,
)
from aaria_pin.apps.dataset.runner import LocalRunner
from aaria_pin.apps.dataset.shards import estimate_from_runs, generate_sharded
from aaria_pin.apps.dataset.spec import (
    MAX_RUNS,
    DatasetJobStoppedError,
    DatasetSpec,
    Result,
    check_first_run,
    run_result,
)
from aaria_pin.apps.dataset.urdf_spec import UrdfDatasetSpec, UrdfSource
from aaria_pin.core._malloc import tune_malloc
from aaria_pin.core.arguments import checked
from aaria_pin.core.se3 import Array
from aaria_pin.errors import InputFileError, OutputFileError, ParameterError
from aaria_pin.files._stored import first_line
from aaria_pin.files.dataset.manifest import read_manifest_shards, remove_unused_shards
from aaria_pin.files.dataset.resume import damaged_runs, dataset_progress, read_dataset_attributes
from aaria_pin.files.dataset.store import DatasetFile, check_dataset_path, partial_path
from aaria_pin.files.paths import no_space

__all__ = [
    "MAX_RUNS",
    "DatasetEstimate",
    "DatasetJob",
    "DatasetJobStoppedError",
    "DatasetReport",
    "DatasetSpec",
    "DhDatasetSpec",
    "Progress",
    "UrdfDatasetSpec",
    "UrdfSource",
    "generate_dataset",
    "simulate_dataset_run",
    "software_versions",
]

FLUSH_SECONDS = 0.5
"""How often the writer pushes completed runs to disk [s] (a crash loses at most these)."""


def simulate_dataset_run(spec: DatasetSpec, run: int) -> dict[str, Array]:
    """The stored arrays of run ``run`` (series in the spec's dtype, inputs in float64).

    A pure function of spec and run; :meth:`DatasetSpec.make_run` gives it as a record.
    """
    return spec.arrays(run)


@dataclass(frozen=True)
class _Head:
    """Runs made in the main process before the workers start, and the fastest one's time [s]."""

    results: list[Result]
    run_seconds: float


def _incomplete_runs(complete: np.ndarray, skip: set[int]) -> Iterator[int]:
    """The runs whose flag is 0, in order, but those in ``skip`` (a block of flags at a time)."""
    block = 1 << 16
    for begin in range(0, complete.size, block):
        for offset in np.flatnonzero(complete[begin : begin + block] == 0):
            run = begin + int(offset)
            if run not in skip:
                yield run


@checked
def generate_dataset(
    path: str | os.PathLike[str],
    spec: DatasetSpec,
    job: DatasetJob | None = None,
    **options: Unpack[DatasetJobOptions],
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
    changes nothing when every run's chunks match their checksums (a damaged run is made
    again and listed in :attr:`~.job.DatasetReport.remade`); a manifest's resume always checks
    its shards. An overwrite builds the new data set beside the old one
    (:func:`~aaria_pin.files.dataset.store.partial_path`) and replaces it once complete: a
    killed overwrite leaves the old data set whole, and the same job continues its partial.

    Args:
        path: the ``.h5`` file
        spec: what the data set holds
        job: how the data set is made (:class:`~.job.DatasetJob`: workers or a Dask
            ``scheduler``, ``resume``, ``overwrite``, ``progress``, ``estimate``, ``command``)
        **options: fields of :class:`~.job.DatasetJob` that replace those of ``job``

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
    job = replace(job or DatasetJob(), **options)
    check_dataset_path(file, job.resume, job.overwrite)  # also: its lock held elsewhere
    target = _target(file, spec, job)
    if job.resume and target[0] == file:  # settings read-only first: a mismatch changes nothing
        stored = read_dataset_attributes(file)
        _check_resume(file, spec, job, stored)
        if job.scheduler is None:  # a manifest's resume checks its shards: they may be gone
            complete, total, no_failure = dataset_progress(file)
            if complete == total and no_failure and "card" in stored and not damaged_runs(file):
                return DatasetReport(file, 0, complete, {}, time.perf_counter() - start)
    try:
        return _generate(file, target, spec, job, start)
    except KeyboardInterrupt:
        saved = _saved_runs(target[0])
        shown = "no run" if not saved else f"{saved}/{spec.n_runs} runs"
        raise DatasetJobStoppedError(
            f"interrupted: {shown} saved in {target[0]}; the same command"
            f"{' with --resume' if target[0] == file else ''} goes on",
            saved,
            spec.n_runs,
            exit_status=130,
            parameter="path",
            value=str(file),
        ) from None


def _target(file: Path, spec: DatasetSpec, job: DatasetJob) -> tuple[Path, bool]:
    """The file a local job writes (``file`` or its partial) and whether it continues it.

    The partial is :func:`~aaria_pin.files.dataset.store.partial_path`.

    An overwrite of an existing data set builds the new one beside it, in the partial, and
    replaces it at the end: the old data set stays whole until then. A partial left by a
    killed overwrite is continued by the same command (``overwrite`` or ``resume``) when it
    holds the same settings; else an overwrite starts it anew. A job on a Dask cluster writes
    its manifest in place.
    """
    partial = partial_path(file)
    if job.scheduler is not None:
        return file, job.resume
    if (job.resume or job.overwrite) and partial.is_file():
        try:
            stored = read_dataset_attributes(partial)
        except InputFileError:  # killed while it was laid out: start it anew
            stored = None
        if stored is not None and not spec.mismatches(stored) and "shard_prefix" not in stored:
            return partial, True
    return (partial, False) if job.overwrite and file.exists() else (file, job.resume)


def _check_resume(file: Path, spec: DatasetSpec, job: DatasetJob, stored: dict[str, Any]) -> None:
    """Refuse to resume a file of other settings, or written the other way (shards, one file).

    Raises:
        ParameterError: naming the first setting that differs, or ``scheduler``.
    """
    different = spec.mismatches(stored)
    if different:
        raise ParameterError(
            f"{file}: was made with other settings ({', '.join(different)}); allowed:"
            " the same settings as the job that made it",
            parameter=different[0],
            value=str(file),
        )
    if job.scheduler is None and "shard_prefix" in stored:
        raise ParameterError(
            parameter="scheduler",
            value=None,
            allowed=f"a Dask scheduler's address: {file} was written in shards",
        )
    if job.scheduler is not None and "shard_prefix" not in stored:
        raise ParameterError(
            parameter="scheduler",
            value=job.scheduler,
            allowed=f"none: {file} was written by local workers in one file (resume it with "
            "--workers)",
        )


def _saved_runs(file: Path) -> int | None:
    """Runs complete in a data set file after a stopped job (None: it cannot be read)."""
    if not file.is_file():
        return 0
    try:
        return dataset_progress(file)[0]
    except Exception:  # a file left unreadable by the failure itself
        return None


def _generate(
    file: Path, building: tuple[Path, bool], spec: DatasetSpec, job: DatasetJob, start: float
) -> DatasetReport:
    """:func:`generate_dataset` after its read-only checks; local workers write ``building``.

    Run 0 is made (its inputs checked) and the local workers are started before the output's
    lock is taken, so no worker inherits the lock (a killed job's lock goes with its main
    process); the lock is then held until the file is complete. ``building`` is the file the
    local workers write and whether to continue it (:func:`_target`); one other than ``file``
    (an overwrite's partial) replaces ``file`` once complete, card included.
    """
    from aaria_pin.files.io import output_lock

    target, resume = building

    tune_malloc()
    # Run 0 checks the inputs before the output is touched; it loads Pinocchio and the compiled
    # kernels before the workers fork, so none of them has to load them again, and it is kept
    # if the file still needs it. For the estimate, two more are timed (the faster counts:
    # another structure may compile a kernel).
    begin = time.perf_counter()
    results = [check_first_run(spec)]
    run_seconds = time.perf_counter() - begin  # an upper bound: it loads everything
    attributes = {**spec.attributes(), "command": job.command, "versions": software_versions()}
    for run in range(1, min(3, spec.n_runs) if job.estimate is not None else 1):
        begin = time.perf_counter()
        results.append(run_result(spec, run))
        run_seconds = min(run_seconds, time.perf_counter() - begin)
    head = _Head(results, run_seconds)
    if job.scheduler is not None:
        with output_lock(file):
            check_dataset_path(file, job.resume, job.overwrite)
            written, complete, failures, count = generate_sharded(
                file, spec, attributes, job, head=(head.results, head.run_seconds)
            )
            store_card(file)
        return DatasetReport(file, written, complete, failures, time.perf_counter() - start, count)
    runner = LocalRunner(job.local_workers)
    try:
        with output_lock(file):
            try:
                check_dataset_path(file, job.resume, job.overwrite)
                written, complete, failures, remade = _write_local(
                    target, spec, job, attributes, runner, head, start, resume
                )
            finally:
                runner.close()  # a worker started after the file was opened holds it open
            store_card(target)
            if target != file:
                _replace(target, file)
    finally:
        runner.close()
    seconds = time.perf_counter() - start
    return DatasetReport(file, written, complete, failures, seconds, remade=tuple(remade))


def _replace(partial: Path, file: Path) -> None:
    """Put a complete overwrite's data set in place of the old one, then drop the old shards."""
    previous = read_manifest_shards(file) if file.is_file() else None
    try:
        os.replace(partial, file)
    except OSError as exc:
        raise OutputFileError(
            f"{file}: cannot be replaced by the new data set ({first_line(exc)}); allowed: a "
            f"writable folder (the new data set is complete in {partial})",
            parameter="path",
            value=str(file),
        ) from None
    if previous is not None:  # the shards of the data set this one replaced
        remove_unused_shards(previous.folder, previous.prefix, set())


def _write_local(
    file: Path,
    spec: DatasetSpec,
    job: DatasetJob,
    attributes: dict[str, Any],
    runner: LocalRunner,
    head: _Head,
    start: float,
    resume: bool,
) -> tuple[int, int, dict[int, str], list[int]]:
    """Make (or reopen) the file and write every run it still needs.

    ``file`` is the output, or an overwrite's partial; ``resume``: continue it.

    Returns:
        Runs written, runs complete, failures, and the runs flagged complete that were found
        damaged and made again.

    Raises:
        DatasetJobStoppedError: no space left on the device (the runs flagged so far kept).
    """
    written = 0
    if resume:
        store = DatasetFile.open_for_resume(file)
        store.clear_failures()
    else:
        store = DatasetFile.create(
            file, spec.n_runs, spec.samples, spec.dtype, attributes, spec.layout()
        )
    try:
        complete_flags = store.complete_runs()
        todo = int(complete_flags.size - np.count_nonzero(complete_flags))
        kept = [result for result in head.results if not complete_flags[result[0]]]
        if job.estimate is not None:
            job.estimate(
                estimate_from_runs(head.results, todo, job.local_workers, head.run_seconds)
            )
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
            if job.progress is not None:
                job.progress(done, todo, time.perf_counter() - start)
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
                parameter="path",
                value=str(file),
            ) from None
        raise
    store.close()
    return written, complete, failures, store.damaged
