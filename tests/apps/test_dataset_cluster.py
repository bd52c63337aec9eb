"""Data sets on a real Dask cluster: ``dask scheduler`` and two ``dask worker`` processes on
loopback. Workers write shards, the client a manifest; the arrays must equal a one-worker local
job's, through a killed worker, a resume over damaged shards and a shard that cannot be
written."""

from __future__ import annotations

import os
import resource
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import h5py
import numpy as np
import pytest
from click.testing import CliRunner

from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.apps.dataset.generate import DatasetJobStoppedError, generate_dataset
from aaria_pin.apps.dataset.shards import write_shard_task
from aaria_pin.cli import main
from aaria_pin.core.record import RunRecord
from aaria_pin.errors import ParameterError
from aaria_pin.files.dataset.manifest import missing_shards, shard_files
from aaria_pin.files.dataset.reader import DatasetReader
from aaria_pin.files.dataset.store import partial_path

pytest.importorskip("distributed")
pytestmark = pytest.mark.slow

RUNS = 40
HERE = Path(__file__).parent
SETTINGS = {"n_runs": RUNS, "seed": 5, "duration": 2.0, "rate": 100.0}


class Cluster:
    """A scheduler and worker processes, each in its own process group."""

    def __init__(self, folder: Path, workers: int = 2) -> None:
        self.folder = folder
        self.file = folder / "scheduler.json"
        dask = [sys.executable, "-m", "dask"]
        # The workers import this module by its name (pytest's rootdir import) for the specs
        # defined here.
        path = os.pathsep.join(filter(None, [str(HERE), os.environ.get("PYTHONPATH")]))
        common = {
            "start_new_session": True,
            "stdout": subprocess.DEVNULL,
            "env": {**os.environ, "PYTHONPATH": path},
        }
        self.logs = [open(folder / f"log{i}.txt", "w") for i in range(workers + 1)]
        self.scheduler = subprocess.Popen(
            [*dask, "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
             "--scheduler-file", str(self.file)],
            stderr=self.logs[0], **common,
        )  # fmt: skip
        assert __name__ == "test_dataset_cluster", __name__
        deadline = time.monotonic() + 60
        while not self.file.exists() and time.monotonic() < deadline:
            time.sleep(0.05)
        worker = [*dask, "worker", "--scheduler-file", str(self.file), "--nworkers", "1"]
        worker += ["--nthreads", "1", "--host", "127.0.0.1", "--no-dashboard"]
        self.workers = [
            subprocess.Popen(worker, stderr=self.logs[i + 1], **common) for i in range(workers)
        ]
        from dask.distributed import Client

        with Client(scheduler_file=str(self.file), timeout=60) as client:
            client.wait_for_workers(workers, timeout=120)
            self.address = client.scheduler.address

    def kill_worker(self, index: int) -> None:
        """SIGKILL a worker's whole process group (its nanny and its worker process)."""
        os.killpg(self.workers[index].pid, signal.SIGKILL)
        self.workers[index].wait()

    def workers_cpu(self) -> float:
        """CPU time of the worker processes so far [s] (user + system)."""
        from dask.distributed import Client

        def cpu() -> float:
            usage = resource.getrusage(resource.RUSAGE_SELF)
            return usage.ru_utime + usage.ru_stime

        with Client(self.address, timeout=30) as client:
            return float(sum(client.run(cpu).values()))

    def stop(self) -> None:
        for process in [*self.workers, self.scheduler]:
            if process.poll() is None:
                os.killpg(process.pid, signal.SIGKILL)
                process.wait()
        for log in self.logs:
            log.close()


@pytest.fixture(scope="module")
def cluster(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Cluster]:
    started = Cluster(tmp_path_factory.mktemp("cluster"))
    try:
        yield started
    finally:
        started.stop()


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("reference") / "ref.h5"
    generate_dataset(path, DhDatasetSpec(**SETTINGS), workers=1)
    return path


def _assert_same(a: Path, b: Path) -> None:
    """Every stored array, view and flag equal (h5py reads the manifest as one file)."""
    with DatasetReader(a) as reader:
        names = (*reader.names, "complete", "failed")
    with h5py.File(a, "r") as left, h5py.File(b, "r") as right:
        for name in names:
            assert left[name].shape == right[name].shape, name
            np.testing.assert_array_equal(left[name][()], right[name][()], err_msg=name)


def test_sharded_job_equals_a_one_worker_job(
    cluster: Cluster, reference: Path, tmp_path: Path
) -> None:
    out = tmp_path / "data"
    out.mkdir()
    workers_before = cluster.workers_cpu()
    client_before = time.process_time()
    report = generate_dataset(
        out / "ds.h5", DhDatasetSpec(**SETTINGS), scheduler=cluster.address, command="aaria x"
    )
    client_cpu = time.process_time() - client_before
    workers_cpu = cluster.workers_cpu() - workers_before
    assert (report.complete, report.written, report.failures) == (RUNS, RUNS, {})
    _assert_same(reference, out / "ds.h5")
    shards = sorted(out.glob("ds-*.h5"))
    assert len(shards) == report.shards > 1  # the runs are in the shards, not in the manifest
    with h5py.File(out / "ds.h5", "r") as handle:
        assert handle["imu"].is_virtual and handle["senSen"].is_virtual
        assert handle.attrs["shard_dir"] == "." and handle.attrs["command"] == "aaria x"
    shard_bytes = sum(path.stat().st_size for path in shards)
    assert (out / "ds.h5").stat().st_size < 0.2 * shard_bytes
    print(
        f"\nclient CPU {client_cpu:.2f} s, workers' CPU {workers_cpu:.2f} s "
        f"({client_cpu / workers_cpu:.0%}); manifest {(out / 'ds.h5').stat().st_size} B, "
        f"{len(shards)} shards {shard_bytes} B"
    )
    assert client_cpu < 0.5 * workers_cpu
    moved = tmp_path / "moved"
    shutil.move(out, moved)  # relative sources: the folder moves with its shards
    _assert_same(reference, moved / "ds.h5")
    with DatasetReader(moved / "ds.h5") as reader:
        np.testing.assert_array_equal(reader.record(7).imu, reader.run(7)["imu"])
    with h5py.File(moved / "ds.h5", "r") as handle:
        assert shard_files(handle, moved / "ds.h5") == sorted(moved.glob("ds-*.h5"))
        assert missing_shards(handle, moved / "ds.h5") == []
        (moved / shards[2].name).unlink()  # HDF5 would read its runs as zeros: found missing
        assert missing_shards(handle, moved / "ds.h5") == [moved / shards[2].name]
    with h5py.File(reference, "r") as handle:
        assert shard_files(handle, reference) == []


def test_shards_in_another_folder_and_resume_over_damaged_shards(
    cluster: Cluster, reference: Path, tmp_path: Path
) -> None:
    (tmp_path / "out").mkdir()
    (tmp_path / "shards").mkdir()
    path = tmp_path / "out" / "ds.h5"
    spec = DhDatasetSpec(**SETTINGS)
    generate_dataset(path, spec, scheduler=cluster.address, shards=tmp_path / "shards")
    with h5py.File(path, "r") as handle:
        assert handle.attrs["shard_dir"] == "../shards"
    shards = sorted((tmp_path / "shards").glob("ds-*.h5"))
    deleted = shards[1]
    with h5py.File(deleted, "r") as handle:
        lost = set(handle["run"][()].tolist())
    deleted.unlink()
    with h5py.File(shards[0], "r") as handle:  # a damaged chunk: its checksum fails
        damaged_run = int(handle["run"][1])
        info = handle["imu"].id.get_chunk_info_by_coord((1, 0, 0, 0))
    with open(shards[0], "r+b") as raw:
        raw.seek(info.byte_offset + info.size // 2)
        raw.write(b"\xff" * 16)
    with pytest.raises(ParameterError, match="written in shards"):  # not by local workers
        generate_dataset(path, spec, workers=1, resume=True)
    report = generate_dataset(path, spec, scheduler=cluster.address, resume=True)
    assert report.written == len(lost) + 1 and report.complete == RUNS
    assert damaged_run not in lost
    _assert_same(reference, path)


@dataclass(frozen=True)
class _SlowSpec(DhDatasetSpec):
    """The same runs, 30 ms slower each, so a worker is killed mid-task."""

    def make_run(self, run: int) -> RunRecord:
        time.sleep(0.03)
        return super().make_run(run)


def test_killed_worker_gives_the_identical_file(reference: Path, tmp_path: Path) -> None:
    own = Cluster(tmp_path)
    try:
        killed: list[int] = []

        def kill_after_first_shard(done: int, total: int, seconds: float) -> None:
            if not killed:  # both workers are busy: 7 of 8 shards left
                own.kill_worker(1)
                killed.append(done)

        report = generate_dataset(
            tmp_path / "ds.h5",
            _SlowSpec(**SETTINGS),
            scheduler=own.address,
            progress=kill_after_first_shard,
        )
        assert own.workers[1].poll() is not None and killed[0] < RUNS
    finally:
        own.stop()
    assert report.failures == {} and report.complete == RUNS
    _assert_same(reference, tmp_path / "ds.h5")
    assert not list(tmp_path.glob(".ds-*"))  # the killed worker's temporary shard is gone


def test_a_lost_scheduler_is_one_line_and_the_runs_are_kept(
    cluster: Cluster, reference: Path, tmp_path: Path
) -> None:
    own = Cluster(tmp_path)
    path = tmp_path / "ds.h5"
    try:

        def kill_scheduler(done: int, total: int, seconds: float) -> None:
            if own.scheduler.poll() is None:
                os.killpg(own.scheduler.pid, signal.SIGKILL)
                own.scheduler.wait()

        with pytest.raises(DatasetJobStoppedError) as stopped:
            generate_dataset(
                path, _SlowSpec(**SETTINGS), scheduler=own.address, progress=kill_scheduler
            )
        message = str(stopped.value)
        assert f"lost the Dask scheduler at {own.address}" in message and "\n" not in message
        assert "--resume" in message
        assert stopped.value.saved is not None and 0 < stopped.value.saved < RUNS
    finally:
        own.stop()
    with h5py.File(path, "r") as handle:  # the runs acknowledged before the loss are in it
        assert int(handle["complete"][()].sum()) == stopped.value.saved
    report = generate_dataset(
        path, DhDatasetSpec(**SETTINGS), scheduler=cluster.address, resume=True
    )  # another scheduler
    assert report.complete == RUNS and report.written <= RUNS - stopped.value.saved
    _assert_same(reference, path)


@dataclass(frozen=True)
class _BlockedShardSpec(DhDatasetSpec):
    """Run 7 puts a folder where its shard is to be renamed to (as a full or read-only disk
    would, the shard cannot be written); every run is an ordinary one."""

    folder: str = ""

    def make_run(self, run: int) -> RunRecord:
        if run == 7:
            for temporary in Path(self.folder).glob(".*.h5.*"):
                final = temporary.name[1:].split(".h5.")[0] + ".h5"
                if "-000000005-" in final:  # the shard of runs 5-9
                    (Path(self.folder) / final).mkdir(exist_ok=True)
        return super().make_run(run)


def test_a_shard_that_cannot_be_written_fails_only_its_runs(
    cluster: Cluster, reference: Path, tmp_path: Path
) -> None:
    spec = _BlockedShardSpec(**SETTINGS, folder=str(tmp_path))
    report = generate_dataset(tmp_path / "ds.h5", spec, scheduler=cluster.address)
    assert sorted(report.failures) == [5, 6, 7, 8, 9]
    message = report.failures[7]
    print(f"\n{message}")
    assert "cannot be written" in message and "\n" not in message, message
    with DatasetReader(tmp_path / "ds.h5") as got, DatasetReader(reference) as want:
        assert sorted(got.attributes["failures"]) == ["5", "6", "7", "8", "9"]
        assert got.complete.sum() == RUNS - 5
        for k in (0, 4, 10, 39):
            np.testing.assert_array_equal(got.run(k)["imu"], want.run(k)["imu"])


def test_a_shard_task_reports_an_unwritable_shard(tmp_path: Path) -> None:
    spec = DhDatasetSpec(n_runs=4, duration=0.2)
    (tmp_path / "blocked").mkdir()
    ack = write_shard_task(spec, [0, 1], str(tmp_path / "missing"), "p")
    assert [run for run, _ in ack.errors] == [0, 1] and not ack.stored
    assert "does not exist" in ack.errors[0][1]
    ack = write_shard_task(spec, [2, 3], str(tmp_path), "p")
    assert [(run, row) for run, row, _ in ack.stored] == [(2, 0), (3, 1)] and not ack.errors


def test_piped_job_prints_the_estimate_and_progress_lines(
    cluster: Cluster, reference: Path, tmp_path: Path
) -> None:
    args = ["-n", str(RUNS), "--seed", "5", "--duration", "2", "--progress-every", "0"]
    result = subprocess.run(
        [sys.executable, "-m", "aaria_pin.cli", "dataset", *args,
         "--scheduler", cluster.address, "-o", str(tmp_path / "ds.h5")],
        capture_output=True, text=True, check=True,
    )  # fmt: skip
    lines = result.stderr.splitlines()
    assert lines[0].startswith(f"aaria: estimate for {RUNS} runs: "), lines  # before any run
    progress = [line for line in lines if " runs/s, ETA " in line]
    assert len(progress) >= 2 and progress[-1].startswith(f"aaria: {RUNS}/{RUNS} runs, ")
    assert "\r" not in result.stderr  # no bar in a log
    _assert_same(reference, tmp_path / "ds.h5")
    with DatasetReader(tmp_path / "ds.h5") as reader:
        assert reader.attributes["command"].startswith(f"aaria dataset -n {RUNS} --seed 5")
        assert set(reader.attributes["versions"]) >= {"aaria_pin", "pinocchio", "numpy", "h5py"}


def test_shards_need_a_scheduler(reference: Path, tmp_path: Path) -> None:
    result = CliRunner().invoke(
        main, ["dataset", "-n", "2", "--shards", str(tmp_path), "-o", str(tmp_path / "ds.h5")]
    )
    assert result.exit_code == 2 and "--shards needs --scheduler" in result.output
    copy = tmp_path / "one-file.h5"  # made by local workers: resumed by local workers
    copy.write_bytes(reference.read_bytes())
    with pytest.raises(ParameterError, match="written by local workers in one file"):
        generate_dataset(
            copy, DhDatasetSpec(**SETTINGS), scheduler="tcp://127.0.0.1:9", resume=True
        )
    assert copy.read_bytes() == reference.read_bytes()


def test_an_overwrite_keeps_the_old_data_set_until_the_new_one_is_whole(
    cluster: Cluster, reference: Path, tmp_path: Path
) -> None:
    path = tmp_path / "ds.h5"
    spec = DhDatasetSpec(**SETTINGS)
    generate_dataset(path, spec, scheduler=cluster.address)
    old_shards = sorted(tmp_path.glob("ds-*.h5"))
    before = path.read_bytes()
    seen: list[tuple[bool, bool, bool]] = []

    def look(done: int, total: int, seconds: float) -> None:  # while the new shards come
        whole = path.read_bytes() == before and all(shard.is_file() for shard in old_shards)
        seen.append((whole, partial_path(path).is_file(), len(list(tmp_path.glob("ds-*.h5"))) > 0))

    report = generate_dataset(path, spec, scheduler=cluster.address, overwrite=True, progress=look)
    assert report.complete == RUNS and seen and all(all(step) for step in seen)
    assert not partial_path(path).exists()
    assert not any(shard.exists() for shard in old_shards)  # the old data set's, removed
    _assert_same(reference, path)
