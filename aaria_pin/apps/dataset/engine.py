"""Data sets of many random runs: deterministic, parallel, streamed to one HDF5 file, resumable.

Run k of a data set with seed S is a pure function of (S, k) and the spec: its inputs come from
:func:`aaria_pin.aaria.randomize.run_streams` and its noise from the fourth stream, so the file is
the
same, array for array, whatever the number of workers, the scheduler (local processes or a Dask
cluster), or the order in which runs finish. The main process is the only writer: it writes each
run as it arrives (one chunk per run), marks it complete and flushes, so a killed job loses at
most the runs in flight, and ``resume`` redoes exactly those.
"""

from __future__ import annotations

import itertools
import os
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin import __version__
from aaria_pin.aaria.randomize import (
    PARTS,
    RandomConfig,
    random_base_table,
    random_dh_table,
    random_joint_table,
    run_streams,
)
from aaria_pin.apps.dataset.urdf_source import URDF_INPUTS, UrdfSource, urdf_layout
from aaria_pin.core._malloc import tune_malloc
from aaria_pin.core.se3 import Array
from aaria_pin.core.seeds import check_seed
from aaria_pin.core.trajectory import DEFAULT_DURATION, DEFAULT_RATE
from aaria_pin.errors import AariaError, ParameterError
from aaria_pin.files.dataset_file import (
    AARIA_LAYOUT,
    INPUT_ARRAYS,
    RUN_ARRAYS,
    DatasetFile,
    RunLayout,
    check_dataset_path,
    encode_run,
    read_dataset_attributes,
)

__all__ = [
    "MAX_RUNS",
    "DatasetReport",
    "DatasetSpec",
    "base_and_noise_inputs",
    "generate_dataset",
    "run_inputs",
    "simulate_dataset_run",
]

MAX_RUNS = 100_000_000
"""Most runs in one data set."""
FLUSH_SECONDS = 0.5
"""How often the writer pushes completed runs to disk [s] (a crash loses at most these)."""

Progress = Callable[[int, int, float], None]


@dataclass(frozen=True)
class DatasetSpec:
    """What a data set holds.

    Attributes:
        n_runs: number of runs N
        seed: seed of the whole data set
        duration: run length [s]
        rate: sample rate [Hz]
        noise: add IMU noise
        dtype: ``"float32"`` or ``"float64"`` for the stored arrays
        config: ranges and probabilities of the random parts
        vary: the random parts, a subset of ``("structure", "joints", "base")``
        dh_table: the fixed 8 × 5 table when the structure does not vary
        joint_table: the fixed joint oscillation table when the joints do not vary (default:
            :func:`~aaria_pin.aaria.oscillation.default_joint_table` of the structure)
        base_table: the fixed base oscillation table when the base does not vary (default:
            :func:`~aaria_pin.aaria.oscillation.default_base_table`)
        urdf: a URDF robot instead of DH arms (its structure cannot vary; the joint table has
            one row per actuated joint; see :mod:`aaria_pin.apps.dataset.urdf_source`)
    """

    n_runs: int
    seed: int = 0
    duration: float = DEFAULT_DURATION
    rate: float = DEFAULT_RATE
    noise: bool = True
    dtype: str = "float32"
    config: RandomConfig = field(default_factory=RandomConfig)
    vary: tuple[str, ...] = PARTS
    dh_table: Array | None = None
    joint_table: Array | None = None
    base_table: Array | None = None
    urdf: UrdfSource | None = None

    def __post_init__(self) -> None:
        from aaria_pin.core.trajectory import sample_times

        if not (isinstance(self.n_runs, (int, np.integer)) and 1 <= self.n_runs <= MAX_RUNS):
            raise ParameterError(f"N is {self.n_runs!r}; allowed: 1 to {MAX_RUNS}")
        check_seed(self.seed)
        if self.dtype not in ("float32", "float64"):
            raise ParameterError(f"dtype {self.dtype!r}; allowed: float32, float64")
        unknown = [part for part in self.vary if part not in PARTS]
        if unknown:
            raise ParameterError(f"--vary {unknown[0]!r}; allowed: {', '.join(PARTS)}")
        if self.urdf is not None and ("structure" in self.vary or self.dh_table is not None):
            raise ParameterError(
                "a URDF robot's structure is fixed; allowed: --vary joints,base and no DH table"
            )
        if self.urdf is not None and self.joint_table is not None and "joints" not in self.vary:
            from aaria_pin.core.urdf_robot import validate_urdf_joint_table

            validate_urdf_joint_table(self.joint_table, self.urdf.load())
        if self.urdf is not None and not self.urdf.moving_base and "base" in self.vary:
            raise ParameterError(
                "the robot's base is fixed, so the base cannot vary; allowed: --vary joints"
            )
        if "structure" not in self.vary and self.dh_table is None and self.urdf is None:
            raise ParameterError(
                "the structure does not vary, so a DH table is needed; allowed: --preset or --dh"
            )
        sample_times(self.duration, self.rate)  # checks duration and rate

    @property
    def samples(self) -> int:
        """Samples per run T."""
        from aaria_pin.core.trajectory import sample_times

        return int(sample_times(self.duration, self.rate).size)

    def attributes(self) -> dict[str, Any]:
        """File attributes describing the spec (what :meth:`mismatches` compares on resume)."""
        from aaria_pin.aaria.simulate import UNITS
        from aaria_pin.core.imu_noise import noise_attributes
        from aaria_pin.core.model import GRAVITY

        fixed = {
            name: getattr(self, name).tolist()
            for name in ("dh_table", "joint_table", "base_table")
            if getattr(self, name) is not None
        }
        robot = {} if self.urdf is None else {"robot": self.urdf.attributes()}
        return {
            **robot,
            "seed": int(self.seed),
            "rate": float(self.rate),
            "duration": float(self.duration),
            "noise": bool(self.noise),
            "vary": list(self.vary),
            "config": self.config.as_dict(),
            "fixed_tables": fixed,
            "noise_parameters": noise_attributes(),
            "gravity": GRAVITY.tolist(),
            "units": UNITS,
            "version": __version__,
        }

    def mismatches(self, stored: dict[str, Any]) -> list[str]:
        """Names of the settings that differ from a stored data set's attributes."""
        mine = {**self.attributes(), "N": self.n_runs, "samples": self.samples, "dtype": self.dtype}
        keys = (
            "version",
            "noise_parameters",
            "N",
            "samples",
            "dtype",
            "seed",
            "rate",
            "duration",
            "noise",
            "vary",
            "config",
            "fixed_tables",
            "robot",
        )
        return [key for key in keys if _plain(stored.get(key)) != _plain(mine.get(key))]

    def layout(self) -> RunLayout:
        """The run layout of the data set file (Aaria, or the URDF robot's generic one)."""
        return AARIA_LAYOUT if self.urdf is None else urdf_layout(self.urdf)


def _plain(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    return value


def run_inputs(spec: DatasetSpec, run: int) -> tuple[Array, Array, Array, np.random.SeedSequence]:
    """Inputs of run ``run``: DH table, joint table, base table (6 × 4) and its noise seed."""
    from aaria_pin.aaria.dh import chain_from_aaria
    from aaria_pin.aaria.oscillation import default_joint_table

    structure, joints, base, _ = run_streams(spec.seed, run)
    if "structure" in spec.vary:
        dh = random_dh_table(spec.config, structure)
    else:
        assert spec.dh_table is not None
        dh = np.asarray(spec.dh_table, dtype=float)
    if "joints" in spec.vary:
        joint_table = random_joint_table(spec.config, dh, joints)
    elif spec.joint_table is not None:
        joint_table = np.asarray(spec.joint_table, dtype=float)
    else:
        joint_table = default_joint_table(chain_from_aaria(dh))
    base_table, noise_seed = base_and_noise_inputs(spec, run, base)
    return dh, joint_table, base_table, noise_seed


def base_and_noise_inputs(
    spec: DatasetSpec, run: int, base: np.random.Generator
) -> tuple[Array, np.random.SeedSequence]:
    """Base table (6 × 4) and noise seed of run ``run`` (DH arms and URDF robots alike).

    Args:
        spec: the data set
        run: the run index
        base: the run's base stream (the third of :func:`~aaria_pin.aaria.randomize.run_streams`)
    """
    from aaria_pin.aaria.oscillation import default_base_table

    if "base" in spec.vary:
        base_table = random_base_table(spec.config, base)
    else:
        base_table = np.asarray(
            spec.base_table if spec.base_table is not None else default_base_table(), dtype=float
        )
    if base_table.shape == (2, 4):
        base_table = np.repeat(base_table, 3, axis=0)
    return base_table, np.random.SeedSequence(spec.seed, spawn_key=(run, len(PARTS)))


def simulate_dataset_run(spec: DatasetSpec, run: int) -> dict[str, Array]:
    """The arrays of run ``run``, a pure function of spec and run.

    Time series are in the spec's dtype, inputs (tables, mounts) in float64.
    """
    from aaria_pin.aaria.simulate import simulate_run

    if spec.urdf is not None:
        from aaria_pin.apps.dataset.urdf_source import urdf_run_arrays

        return urdf_run_arrays(spec, run)
    dh, joint_table, base_table, noise_seed = run_inputs(spec, run)
    record = simulate_run(
        dh,
        joint_table,
        base_table,
        duration=spec.duration,
        rate=spec.rate,
        seed=noise_seed,
        noise=spec.noise,
    )
    return {
        name: np.asarray(getattr(record, name), dtype=float if name in INPUT_ARRAYS else spec.dtype)
        for name in RUN_ARRAYS
    }


Encoded = dict[str, tuple[bytes, int]]


def _job(spec: DatasetSpec, run: int) -> tuple[int, Encoded | None, str]:
    """A worker's task: run ``run`` as compressed chunks, or its one-line error and inputs."""
    try:
        names = INPUT_ARRAYS if spec.urdf is None else URDF_INPUTS
        return run, encode_run(simulate_dataset_run(spec, run), spec.dtype, names), ""
    except Exception as exc:  # any failure of one run is reported, and the others go on
        message = str(exc) if isinstance(exc, AariaError) else f"{type(exc).__name__}: {exc}"
        return run, None, f"{message} ({_describe_inputs(spec, run)})"


def _describe_inputs(spec: DatasetSpec, run: int) -> str:
    """The inputs of a failed run, for its error message."""
    try:
        if spec.urdf is not None:
            from aaria_pin.apps.dataset.urdf_source import urdf_run_inputs

            joint_table, base_table, _ = urdf_run_inputs(spec, run, spec.urdf.load())
            return f"joint_table={joint_table.tolist()} base_table={base_table.tolist()}"
        dh, joint_table, base_table, _ = run_inputs(spec, run)
        return (
            f"senSenDH={dh.tolist()} senSenJ={joint_table.tolist()} senSenB={base_table.tolist()}"
        )
    except Exception:
        return "inputs could not be drawn"


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


Result = tuple[int, Encoded | None, str]


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
        for future in [pool.submit(int, 0) for _ in range(self._workers)]:
            future.result()  # fork now
        return pool

    def results(self, spec: DatasetSpec, runs: Sequence[int]) -> Iterator[Result]:
        """Results in completion order, at most four runs per worker in flight.

        A worker that dies fails the runs it had in flight and is replaced.
        """
        from concurrent.futures import FIRST_COMPLETED, wait
        from concurrent.futures.process import BrokenProcessPool

        pending = iter(runs)
        in_flight: dict[Any, int] = {}
        while True:
            for run in itertools.islice(pending, 4 * self._workers - len(in_flight)):
                in_flight[self._pool.submit(_job, spec, run)] = run
            if not in_flight:
                return
            done, _ = wait(in_flight, return_when=FIRST_COMPLETED)
            for future in done:
                run = in_flight.pop(future)
                try:
                    yield future.result()
                except BrokenProcessPool:
                    for lost in [run, *in_flight.values()]:
                        yield lost, None, "a worker process died during this run"
                    in_flight.clear()
                    self._pool.shutdown(wait=False, cancel_futures=True)
                    self._pool = self._start()
                    break

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
                "--scheduler needs Dask; allowed: pip install 'aaria-pin[distributed]'"
            ) from None
        try:
            self._client = Client(address, timeout=30)
        except (OSError, TimeoutError, ValueError) as exc:
            raise ParameterError(f"scheduler {address!r} cannot be reached ({exc})") from None

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
        raise ParameterError(f"--workers {workers}; allowed: >= 1")
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
