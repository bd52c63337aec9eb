"""Data-set jobs under faults: nothing lost, no traceback, no hang (issue 18).

Two jobs on one output, bad fixed inputs with ``--overwrite``, a damaged ``complete`` flag,
a killed local worker, a full disk, Ctrl-C, stale temporaries, and a resumed file that must
equal an uninterrupted one in every array and attribute. The numbers are checked against an
uninterrupted job of the same settings (one worker), never against the job itself.
"""

from __future__ import annotations

import contextlib
import os
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

from aaria_pin.aaria.presets import get_preset
from aaria_pin.apps.dataset import generate as engine
from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.apps.dataset.generate import DatasetJobStoppedError, generate_dataset
from aaria_pin.cli import main
from aaria_pin.core.record import RunRecord

HERE = Path(__file__).parent
SHORT = {"duration": 0.5, "rate": 100.0}
SETTINGS = {"n_runs": 24, "seed": 7, **SHORT}
ARGS = ["-n", "24", "--seed", "7", "--duration", "0.5", "--rate", "100", "--quiet"]


def _contents(path: Path) -> tuple[list[tuple[str, str]], dict[str, np.ndarray]]:
    """Every attribute (in order, as text) and every dataset (views included) of a file."""
    with h5py.File(path, "r") as handle:
        attributes = [(key, str(handle.attrs[key])) for key in handle.attrs]
        names: list[str] = []
        handle.visit(names.append)
        arrays = {
            n: np.asarray(handle[n][()]) for n in names if isinstance(handle[n], h5py.Dataset)
        }
    return attributes, arrays


def _assert_identical(want: Path, got: Path, skip: tuple[str, ...] = ()) -> None:
    """The same attributes in the same order, and the same datasets bit for bit."""
    want_attributes, want_arrays = _contents(want)
    got_attributes, got_arrays = _contents(got)
    keep = [(k, v) for k, v in want_attributes if k not in skip]
    assert [(k, v) for k, v in got_attributes if k not in skip] == keep
    assert sorted(got_arrays) == sorted(want_arrays)
    for name, array in want_arrays.items():
        assert got_arrays[name].dtype == array.dtype, name
        np.testing.assert_array_equal(got_arrays[name], array, err_msg=name)


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """An uninterrupted job, one worker."""
    path = tmp_path_factory.mktemp("ref") / "ref.h5"
    generate_dataset(path, DhDatasetSpec(**SETTINGS), workers=1)
    return path


def _stop_after(runs: int) -> engine.Progress:
    def progress(done: int, total: int, seconds: float) -> None:
        if done == runs:
            raise KeyboardInterrupt

    return progress


def _interrupted(path: Path, runs: int) -> None:
    """A job stopped by Ctrl-C after ``runs`` runs (the runs so far flagged and kept)."""
    with pytest.raises(DatasetJobStoppedError, match=rf"{runs}/24 runs saved.*--resume"):
        generate_dataset(path, DhDatasetSpec(**SETTINGS), workers=2, progress=_stop_after(runs))


def test_a_stopped_job_is_an_output_error_naming_the_file(tmp_path: Path) -> None:
    from aaria_pin.errors import AariaError, OutputFileError

    path = tmp_path / "stopped.h5"
    with pytest.raises(DatasetJobStoppedError) as stopped:
        generate_dataset(path, DhDatasetSpec(**SETTINGS), workers=1, progress=_stop_after(3))
    error = stopped.value
    assert isinstance(error, OutputFileError) and isinstance(error, OSError)  # in the family
    assert isinstance(error, AariaError) and error.parameter == "path"
    assert error.value == str(path) and (error.saved, error.total) == (3, 24)
    assert error.exit_status == 130


def test_a_resumed_file_equals_an_uninterrupted_one(reference: Path, tmp_path: Path) -> None:
    path = tmp_path / "resumed.h5"
    _interrupted(path, 9)
    report = generate_dataset(path, DhDatasetSpec(**SETTINGS), workers=2, resume=True)
    assert (report.written, report.complete) == (24 - 9, 24)
    _assert_identical(reference, path)  # checksum, attributes and their order included


def test_a_damaged_complete_flag_is_a_run_to_redo(reference: Path, tmp_path: Path) -> None:
    path = tmp_path / "flag.h5"
    _interrupted(path, 6)
    with h5py.File(path, "r+") as handle:
        never = int(np.flatnonzero(handle["complete"][()] == 0)[0])
        handle["complete"][never] = 1  # a run never written, flagged complete
        with pytest.raises(RuntimeError, match="storage size of chunk"):
            handle["imu"].id.read_direct_chunk((never, 0, 0, 0))
    report = generate_dataset(path, DhDatasetSpec(**SETTINGS), workers=1, resume=True)
    assert report.complete == 24 and report.written == 24 - 6
    _assert_identical(reference, path)


def test_ctrl_c_says_what_is_saved_and_resume_goes_on(
    reference: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from aaria_pin.apps.dataset import progress

    monkeypatch.setattr(progress, "progress_report", lambda quiet, every: _stop_after(5))
    path = tmp_path / "ds.h5"
    result = CliRunner().invoke(main, ["dataset", *ARGS, "--workers", "2", "-o", str(path)])
    assert result.exit_code == 130
    assert result.stderr.strip().splitlines() == [
        f"aaria: interrupted: 5/24 runs saved in {path}; the same command with --resume goes on"
    ]
    monkeypatch.undo()
    result = CliRunner().invoke(main, ["dataset", *ARGS, "-o", str(path), "--resume"])
    assert result.exit_code == 0, result.output
    _assert_identical(reference, path, skip=("command", "card_json"))  # the CLI's command


def test_resuming_a_complete_file_says_so_at_once(reference: Path, tmp_path: Path) -> None:
    path = tmp_path / "done.h5"
    shutil.copyfile(reference, path)
    before = (path.stat().st_mtime_ns, path.read_bytes())
    result = CliRunner().invoke(main, ["dataset", *ARGS, "-o", str(path), "--resume"])
    assert result.exit_code == 0, result.output
    assert result.stdout == f"{path}: already complete (24/24 runs); nothing to do\n"
    assert (path.stat().st_mtime_ns, path.read_bytes()) == before


def test_stale_temporaries_are_removed_by_resume(reference: Path, tmp_path: Path) -> None:
    path = tmp_path / "ds.h5"
    _interrupted(path, 4)
    dead = 4_000_000  # above Linux's pid_max default: no process has it
    with pytest.raises(ProcessLookupError):
        os.kill(dead, 0)
    stale = tmp_path / f".ds.h5.{dead}.abcd1234.tmp.h5"
    stale.write_bytes(b"\0" * 4096)  # what a job killed just before its rename leaves
    generate_dataset(path, DhDatasetSpec(**SETTINGS), workers=1, resume=True)
    assert not stale.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ds.h5"]


# --- two jobs, one output --------------------------------------------------------------------


@contextlib.contextmanager
def _lock_held_elsewhere(path: Path) -> Iterator[subprocess.Popen[bytes]]:
    """Another process holding the output's lock (as a running job does)."""
    code = (
        "import sys, time; from aaria_pin.files.io import output_lock\n"
        "with output_lock(sys.argv[1]):\n"
        "    print('held', flush=True); time.sleep(60)\n"
    )
    holder = subprocess.Popen(
        [sys.executable, "-c", code, str(path)], stdout=subprocess.PIPE, start_new_session=True
    )
    try:
        assert holder.stdout is not None and holder.stdout.readline() == b"held\n"
        yield holder
    finally:
        holder.kill()
        holder.wait()


@pytest.mark.parametrize("flag", [[], ["--overwrite"], ["--resume"]])
def test_an_output_another_job_writes_is_refused(
    reference: Path, tmp_path: Path, flag: list[str]
) -> None:
    path = tmp_path / "busy.h5"
    shutil.copyfile(reference, path)
    before = path.read_bytes()
    with _lock_held_elsewhere(path) as holder:
        result = CliRunner().invoke(main, ["dataset", *ARGS, "-o", str(path), *flag])
    assert result.exit_code == 2
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.stderr
    assert f"being written by another aaria process (pid {holder.pid})" in result.stderr
    assert "--overwrite" not in result.stderr and "--resume" not in result.stderr
    assert path.read_bytes() == before


def test_two_jobs_on_one_output_one_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "c.h5"
    lock = tmp_path / ".c.h5.lock"
    first = subprocess.Popen(
        [sys.executable, "-m", "aaria_pin.cli", "dataset", "-n", "400", "--seed", "7",
         "--duration", "0.5", "--workers", "1", "--quiet", "-o", str(path)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        start_new_session=True,
    )  # fmt: skip
    try:
        deadline = time.monotonic() + 120
        while not lock.exists() and first.poll() is None and time.monotonic() < deadline:
            time.sleep(0.01)
        assert first.poll() is None, "the first job ended before the second started"
        second = CliRunner().invoke(
            main, ["dataset", "-n", "400", "--seed", "8", "--duration", "0.5", "-o", str(path)]
        )
        out, err = first.communicate(timeout=300)
    finally:
        if first.poll() is None:
            os.killpg(first.pid, signal.SIGKILL)
    assert second.exit_code == 2 and "being written by another aaria process" in second.stderr
    assert first.returncode == 0, err
    assert b"400/400 runs complete" in out
    with h5py.File(path, "r") as handle:  # the first job's data set, whole
        assert int(handle.attrs["seed"]) == 7 and handle["complete"][()].all()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.h5"]


# --- bad inputs: one line, exit 2, nothing changed -------------------------------------------


def _bad_inputs(folder: Path) -> dict[str, list[str]]:
    """Files of bad inputs, by case: the arguments that give each."""
    fig2 = get_preset("aaria-fig2")

    def csv(name: str, table: np.ndarray) -> str:
        np.savetxt(folder / name, table, delimiter=",")
        return str(folder / name)

    nan_dh = fig2.table.copy()
    nan_dh[2, 1] = np.nan
    type3 = fig2.table.copy()
    type3[0, 4] = 3
    all_empty = fig2.table.copy()
    all_empty[:6, 4] = 0
    np.save(folder / "empty.npy", np.zeros((0, 5)))
    nan_joints = fig2.joint_table.copy()
    nan_joints[0, 0] = np.nan
    far_joints = fig2.joint_table.copy()
    far_joints[0, 2] = 40.0  # a bias far out of the revolute range
    inf_base = fig2.base_table.copy()
    inf_base[0, 0] = np.inf
    (folder / "huge.toml").write_text("a = [1e300, 1e301]\n")
    (folder / "text.toml").write_text('a = "long"\n')
    (folder / "latin1.toml").write_bytes("# réglage\na = [0.5, 0.9]\n".encode("latin-1"))
    (folder / "noise.toml").write_text("[noise.gyro]\nnoise_density = -1.0\n")
    wrist = csv("wrist.csv", get_preset("spherical-wrist").table)
    fixed = ["--vary", "base"]
    return {
        "dh NaN": ["--dh", csv("nan.csv", nan_dh)],
        "dh 7 x 5": ["--dh", csv("seven.csv", fig2.table[:7])],
        "dh link type 3": ["--dh", csv("type3.csv", type3)],
        "dh all empty": ["--dh", csv("empty.csv", all_empty)],
        "dh empty npy": ["--dh", str(folder / "empty.npy")],
        "joints NaN": ["--preset", "aaria-fig2", "--joints", csv("jn.csv", nan_joints), *fixed],
        "joints 8 x 4": ["--preset", "aaria-fig2", "--joints", csv("j4.csv", np.ones((8, 4)))],
        "joints out of range": ["--preset", "aaria-fig2", "--joints", csv("jf.csv", far_joints)],
        "base inf": ["--preset", "aaria-fig2", "--base", csv("bi.csv", inf_base)],
        "base 3 x 4": ["--preset", "aaria-fig2", "--base", csv("b3.csv", np.zeros((3, 4)))],
        "config 1e300": ["--config", str(folder / "huge.toml")],
        "config text": ["--config", str(folder / "text.toml")],
        "config latin-1": ["--config", str(folder / "latin1.toml")],
        "config noise": ["--config", str(folder / "noise.toml")],
        "convention": ["--dh", wrist, "--convention", "standard"],
        "scheduler empty": ["--scheduler", ""],
    }  # fmt: skip


CASES = [
    ("dh NaN", "row 3, column 2"),
    ("dh 7 x 5", "shape (7, 5)"),
    ("dh link type 3", "link type) is 3"),
    ("dh all empty", "every module (rows 1-6) is empty"),
    ("dh empty npy", "empty table"),
    ("joints NaN", "row 1, column 1"),
    ("joints 8 x 4", "shape (8, 4)"),
    ("joints out of range", "allowed: within its range"),
    ("base inf", "row 1, column 1"),
    ("base 3 x 4", "shape (3, 4)"),
    ("config 1e300", "drawn from the config ranges"),
    ("config text", "a is 'long'; allowed: a list of numbers"),
    ("config latin-1", "is not UTF-8 text"),
    ("config noise", "noise.gyro.noise_density is -1.0"),
    ("convention", "--convention is 'standard'; allowed: aaria"),
    ("scheduler empty", "--scheduler is ''"),
]


@pytest.mark.parametrize(("case", "pattern"), CASES, ids=[case for case, _ in CASES])
def test_bad_inputs_leave_an_existing_data_set_untouched(
    reference: Path, tmp_path: Path, case: str, pattern: str
) -> None:
    inputs = tmp_path / "inputs"
    inputs.mkdir()
    args = _bad_inputs(inputs)[case]
    out = tmp_path / "out"
    out.mkdir()
    path = out / "existing.h5"
    shutil.copyfile(reference, path)
    before = (path.stat().st_mtime_ns, path.read_bytes())
    begin = time.monotonic()
    result = CliRunner().invoke(main, ["dataset", *ARGS, *args, "--overwrite", "-o", str(path)])
    assert time.monotonic() - begin < 60  # refused before any run of the job
    assert result.exit_code == 2, result.output
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.stderr
    assert pattern in result.stderr, result.stderr
    assert (path.stat().st_mtime_ns, path.read_bytes()) == before
    assert [p.name for p in out.iterdir()] == ["existing.h5"]  # no lock, no temporary left


def test_info_of_a_data_set_without_its_complete_array(reference: Path, tmp_path: Path) -> None:
    path = tmp_path / "no-complete.h5"
    shutil.copyfile(reference, path)
    with h5py.File(path, "r+") as handle:
        del handle["complete"]
    for args in (["info", str(path)], ["info", "--card", str(path)]):
        result = CliRunner().invoke(main, args)
        assert result.exit_code == 2, result.output
        assert result.stderr.count("\n") == 1 and "damaged data set" in result.stderr


def test_noise_model_from_the_config(tmp_path: Path) -> None:
    from aaria_pin.apps.dataset.config import load_dataset_config
    from aaria_pin.core.imu_noise import ADIS16485

    config = tmp_path / "noise.toml"
    config.write_text(
        "a = [0.5, 0.9]\n[noise]\nbias_correlation_time = 50.0\n"
        "[noise.gyro]\nnoise_density = 2.0e-4\n"
    )
    ranges, hardware = load_dataset_config(config)
    model = hardware.nominal(0).imu
    assert ranges.a == (0.5, 0.9)
    assert model.bias_correlation_time == 50.0 and model.gyro.noise_density == 2.0e-4
    assert model.accel == ADIS16485.accel and model.gyro.range == ADIS16485.gyro.range
    path = tmp_path / "ds.h5"
    result = CliRunner().invoke(
        main, ["dataset", "-n", "2", "--duration", "0.5", "--quiet", "--config", str(config),
               "-o", str(path)],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    from aaria_pin.files.dataset.reader import DatasetReader

    with DatasetReader(path) as reader:
        stored = reader.attributes["noise_parameters"]
    assert stored["gyro_noise_density_rad_s_sqrtHz"] == 2.0e-4
    result = CliRunner().invoke(
        main, ["dataset", "-n", "2", "--duration", "0.5", "--quiet", "-o", str(path), "--resume"]
    )  # another noise model than the file's: refused
    assert result.exit_code == 2 and "noise_parameters" in result.stderr


# --- a killed local worker --------------------------------------------------------------------


def _worker_pids() -> list[int]:
    """The pids of this process's children (its local workers)."""
    children: list[int] = []
    for task in Path("/proc/self/task").iterdir():
        with contextlib.suppress(OSError):
            children += [int(p) for p in (task / "children").read_text().split()]
    return children


def killed_worker_job(path: str, kills: int) -> None:
    """A two-worker job whose progress kills a worker ``kills`` times (in a subprocess).

    Kills come 8 runs apart, after the lost runs of the last one were tried again (a run tried
    alone whose worker dies again is failed, as a run that kills its worker).
    """
    done_kills: list[int] = []

    def progress(done: int, total: int, seconds: float) -> None:
        if done % 8 == 4 and len(done_kills) < kills:
            pids = _worker_pids()
            os.kill(pids[len(done_kills) % len(pids)], signal.SIGKILL)
            done_kills.append(done)

    report = generate_dataset(path, DhDatasetSpec(**SETTINGS), workers=2, progress=progress)
    assert len(done_kills) == kills, done_kills
    assert not report.failures and report.complete == 24, report


@dataclass(frozen=True)
class _DiesOnceSpec(DhDatasetSpec):
    """Run 10's first worker dies mid-run (SIGKILL); tried again, it is an ordinary run."""

    marker: str = ""

    def make_run(self, run: int) -> RunRecord:
        if run == 10 and not os.path.exists(self.marker):
            Path(self.marker).touch()
            os.kill(os.getpid(), signal.SIGKILL)
        return super().make_run(run)


@pytest.mark.skipif(not Path("/proc/self/task").is_dir(), reason="needs Linux's /proc")
def test_killed_local_workers_no_hang_identical_arrays(reference: Path, tmp_path: Path) -> None:
    for trial in range(4):  # a worker killed at any point of its task: mid-run, mid-answer
        path = tmp_path / f"killed{trial}.h5"
        code = (
            "import sys; from test_dataset_faults import killed_worker_job; "
            "killed_worker_job(sys.argv[1], 2)"
        )
        paths = [str(HERE), os.environ.get("PYTHONPATH", "")]
        env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, paths))}
        done = subprocess.run(
            [sys.executable, "-c", code, str(path)],
            capture_output=True,
            text=True,
            timeout=240,  # a hang fails here
            env=env,
        )
        assert done.returncode == 0, done.stderr
        _assert_identical(reference, path)


def test_a_worker_killed_mid_run_is_retried(reference: Path, tmp_path: Path) -> None:
    spec = _DiesOnceSpec(**SETTINGS, marker=str(tmp_path / "died"))
    report = generate_dataset(tmp_path / "ds.h5", spec, workers=2)
    assert (tmp_path / "died").exists() and not report.failures and report.complete == 24
    _, want = _contents(reference)
    _, got = _contents(tmp_path / "ds.h5")
    for name in want:
        np.testing.assert_array_equal(got[name], want[name], err_msg=name)


# --- a full disk ------------------------------------------------------------------------------


def _mount_tmpfs(folder: Path, size: str) -> bool:
    """Mount a tmpfs of ``size`` at ``folder`` (root only); False where it cannot."""
    if not hasattr(os, "geteuid") or os.geteuid() != 0 or shutil.which("mount") is None:
        return False
    done = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(folder)],
        capture_output=True,
    )
    return done.returncode == 0


def test_a_full_disk_keeps_the_runs_and_resumes(tmp_path: Path) -> None:
    disk = tmp_path / "disk"
    disk.mkdir()
    if not _mount_tmpfs(disk, "400k"):
        pytest.skip("a small tmpfs needs root and mount (a size-limited file system)")
    try:
        args = ["dataset", "-n", "40", "--seed", "3", "--duration", "1", "--workers", "2"]
        args += ["--quiet", "-o", "ds.h5"]
        code = (
            "import sys; from aaria_pin.apps.dataset import generate as engine; "
            "engine.FLUSH_SECONDS = 0; "
            "from aaria_pin.cli import main; main()"
        )
        full = subprocess.run(
            [sys.executable, "-c", code, *args], cwd=disk, capture_output=True, text=True,
            timeout=240,
        )  # fmt: skip
        assert full.returncode == 1, full.stderr
        lines = full.stderr.strip().splitlines()
        assert len(lines) == 1 and "no space left on device writing ds.h5" in lines[0]
        saved = int(lines[0].split(": ")[2].split("/")[0])
        assert 0 < saved < 40 and "--resume" in lines[0]
        assert sorted(p.name for p in disk.iterdir()) == ["ds.h5"]
        subprocess.run(["mount", "-o", "remount,size=8m", str(disk)], check=True)
        resumed = subprocess.run(
            [sys.executable, "-m", "aaria_pin.cli", *args, "--resume"], cwd=disk,
            capture_output=True, text=True, timeout=240,
        )  # fmt: skip
        assert resumed.returncode == 0, resumed.stderr
        (tmp_path / "whole").mkdir()
        whole = subprocess.run(
            [sys.executable, "-m", "aaria_pin.cli", *args], cwd=tmp_path / "whole",
            capture_output=True, text=True, timeout=240,
        )  # fmt: skip
        assert whole.returncode == 0, whole.stderr
        _assert_identical(tmp_path / "whole" / "ds.h5", disk / "ds.h5")
    finally:
        subprocess.run(["umount", "-l", str(disk)], check=False)


def test_without_room_for_a_copy_resume_continues_the_file_in_place(
    reference: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from aaria_pin.errors import NoSpaceError
    from aaria_pin.files.dataset import store

    path = tmp_path / "full.h5"
    _interrupted(path, 6)
    with h5py.File(path, "r+") as handle:
        never = int(np.flatnonzero(handle["complete"][()] == 0)[0])
        handle["complete"][never] = 1  # a damaged flag: found and redone in place too
    before = path.stat().st_ino

    def no_room(*args: object, **kwargs: object) -> None:
        raise NoSpaceError("no space left on device writing the copy")

    monkeypatch.setattr(store, "_new_file", no_room)  # the copy cannot be made
    report = generate_dataset(path, DhDatasetSpec(**SETTINGS), workers=1, resume=True)
    assert path.stat().st_ino == before  # the same file, continued: no second copy
    assert report.complete == 24 and report.written == 24 - 6
    _assert_identical(reference, path)
