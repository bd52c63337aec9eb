"""How a data-set job runs: its settings (:class:`DatasetJob`), its estimate and its report.

A data set's contents are its :class:`~.spec.DatasetSpec`; where and how the runs are made (local
workers or a Dask cluster, resume or overwrite, progress and estimate callbacks) is its
:class:`DatasetJob`. Neither changes a run's arrays.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TypedDict

from aaria_pin.core.arguments import checked
from aaria_pin.errors import ParameterError

__all__ = [
    "DatasetEstimate",
    "DatasetJob",
    "DatasetJobOptions",
    "DatasetReport",
    "Estimate",
    "Progress",
    "software_versions",
]


@dataclass(frozen=True)
class DatasetEstimate:
    """A job's expected cost, from its first runs.

    Attributes:
        runs: runs this job makes
        bytes: data it writes [bytes]
        seconds: wall time [s]
        workers: runs made at once (local workers, or the cluster's threads)
        run_seconds: one run's time in a worker [s]
    """

    runs: int
    bytes: int
    seconds: float
    workers: int
    run_seconds: float


Estimate = Callable[[DatasetEstimate], None]
"""Called once with a job's :class:`DatasetEstimate`, before the bulk of its runs."""
Progress = Callable[[int, int, float], None]
"""Called as ``progress(done, total, seconds)`` after each run (each shard on a cluster)."""


class DatasetJobOptions(TypedDict, total=False):
    """The fields of :class:`DatasetJob` as keywords of :func:`~.engine.generate_dataset`."""

    workers: int | None
    scheduler: str | None
    shards: str | os.PathLike[str] | None
    resume: bool
    overwrite: bool
    progress: Progress | None
    estimate: Estimate | None
    command: str


@checked
@dataclass(frozen=True)
class DatasetJob:
    """How a data set is made (not what it holds): its workers, resume, reports.

    Attributes:
        workers: local worker processes (None: the cores this process may use)
        scheduler: address of a Dask distributed scheduler (instead of local workers)
        shards: the folder of the shards, on storage every Dask worker reaches (with
            ``scheduler`` only; default the output's folder)
        resume: continue an existing file (same spec), redoing the runs that are not complete
        overwrite: replace an existing file (and its shards) once the new one is complete
        progress: called as ``progress(done, total, seconds)`` after each run (each shard on a
            cluster)
        estimate: called once before the bulk of the runs with the job's expected size and
            time (from the first runs)
        command: the command line that asked for the data set (attribute ``command``)

    Raises:
        ParameterError: an empty ``scheduler``, ``shards`` without ``scheduler``, ``workers``
            below 1 or beside a ``scheduler``.
    """

    workers: int | None = None
    scheduler: str | None = None
    shards: str | os.PathLike[str] | None = None
    resume: bool = False
    overwrite: bool = False
    progress: Progress | None = None
    estimate: Estimate | None = None
    command: str = ""

    def __post_init__(self) -> None:
        if self.scheduler is not None and not self.scheduler.strip():
            raise ParameterError(
                parameter="scheduler",
                value=self.scheduler,
                allowed="a Dask scheduler's address, e.g. tcp://host:8786 (without it: local"
                " workers)",
            )
        if self.shards is not None and self.scheduler is None:
            raise ParameterError(
                parameter="shards",
                value=str(self.shards),
                allowed="a folder with a scheduler only (--shards needs --scheduler)",
            )
        if self.workers is not None and self.scheduler is not None:
            raise ParameterError(
                parameter="workers",
                value=self.workers,
                allowed="none with a scheduler (give --workers or --scheduler, not both)",
            )
        if self.workers is not None and self.workers < 1:
            raise ParameterError(parameter="workers", value=self.workers, allowed=">= 1")

    @property
    def local_workers(self) -> int:
        """``workers``, or the cores this process may use."""
        if self.workers is not None:
            return self.workers
        if hasattr(os, "sched_getaffinity"):
            return len(os.sched_getaffinity(0))
        return os.cpu_count() or 1  # pragma: no cover - not Linux


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
        remade: runs flagged complete that a resumed job found damaged and made again
    """

    path: Path
    written: int
    complete: int
    failures: dict[int, str]
    seconds: float
    shards: int = 0
    remade: tuple[int, ...] = ()


def software_versions() -> dict[str, str]:
    """Versions of aaria_pin, Pinocchio, NumPy, h5py, HDF5 and Python, by name.

    The ``versions`` attribute of a data set; Pinocchio's is read from its package metadata,
    without importing it.
    """
    import platform
    from importlib import metadata

    import h5py
    import numpy as np

    from aaria_pin._version import __version__

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
