"""``--overwrite`` never loses the old data set; ``--resume`` verifies complete runs too.

A killed overwrite (SIGKILL once the new data set is being written beside the old one) leaves
the old file bit for bit (its SHA-256), and the same command continues what it built, ending
with the arrays of a clean job. A complete data set with a damaged run is not "already
complete": its resume re-makes the run and says so. Expectations come from clean jobs of the
same settings, never from the job under test.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
from conftest import run_cli

from aaria_pin.files.dataset.store import partial_path

SMALL = ["--duration", "0.2", "--rate", "100", "--quiet"]


def sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def arrays(path: Path) -> dict[str, np.ndarray]:
    with h5py.File(path, "r") as handle:
        return {name: handle[name][()] for name in handle if isinstance(handle[name], h5py.Dataset)}


def assert_same_arrays(got: Path, want: Path) -> None:
    got_arrays, want_arrays = arrays(got), arrays(want)
    assert sorted(got_arrays) == sorted(want_arrays)
    for name, array in want_arrays.items():
        assert np.array_equal(got_arrays[name], array), name


def test_a_killed_overwrite_keeps_the_old_data_set_and_goes_on(tmp_path: Path) -> None:
    old = tmp_path / "ds.h5"
    status, _, err = run_cli("dataset", "-n", "3", *SMALL, "-o", str(old))
    assert status == 0, err
    before = sha256(old)
    new_settings = ["dataset", "-n", "200", "--seed", "5", "--workers", "1", *SMALL]
    command = [sys.executable, "-m", "aaria_pin.cli", *new_settings, "-o", str(old), "--overwrite"]
    job = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=tmp_path)
    partial = partial_path(old)
    assert partial == tmp_path / ".ds.partial.h5"
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and job.poll() is None:
        if partial.is_file() and partial.stat().st_size > 200_000:  # runs are being written
            break
        time.sleep(0.02)
    assert job.poll() is None, "the overwrite ended before it could be killed"
    os.kill(job.pid, signal.SIGKILL)
    job.wait()
    assert sha256(old) == before  # the old data set, bit for bit
    assert partial.is_file()
    with h5py.File(partial, "r") as handle:
        built = int(np.count_nonzero(handle["complete"][()]))
    status, out, err = run_cli(*new_settings, "-o", str(old), "--overwrite")
    assert status == 0, err
    assert f"{200 - built} in this job" in out  # it continued what the killed job built
    assert not partial.exists()
    clean = tmp_path / "clean.h5"
    status, _, err = run_cli(*new_settings, "-o", str(clean))
    assert status == 0, err
    assert_same_arrays(old, clean)


def test_resume_of_a_complete_data_set_remakes_a_damaged_run(tmp_path: Path) -> None:
    clean = tmp_path / "clean.h5"
    status, _, err = run_cli("dataset", "-n", "3", *SMALL, "-o", str(clean))
    assert status == 0, err
    damaged = tmp_path / "ds.h5"
    shutil.copy(clean, damaged)
    with h5py.File(damaged, "r+") as handle:
        handle["tau"][2, 4, 1] += 1.0  # the flags still say complete
    status, out, err = run_cli("dataset", "-n", "3", *SMALL, "-o", str(damaged), "--resume")
    assert status == 0, err
    assert "run 2 was damaged; re-made" in out and "1 in this job" in out
    assert "nothing to do" not in out
    assert_same_arrays(damaged, clean)
    status, out, _ = run_cli("dataset", "-n", "3", *SMALL, "-o", str(damaged), "--resume")
    assert status == 0 and "already complete (3/3 runs); nothing to do" in out


def test_a_left_partial_is_continued_by_resume_or_started_anew(tmp_path: Path) -> None:
    """A partial of the job's settings is continued (--resume too); one of others is not."""
    old = tmp_path / "ds.h5"
    status, _, err = run_cli("dataset", "-n", "3", *SMALL, "-o", str(old))
    assert status == 0, err
    new_settings = ["dataset", "-n", "3", "--seed", "4", *SMALL]
    partial = partial_path(old)
    status, _, err = run_cli(*new_settings, "-o", str(partial))  # as a killed overwrite left it
    assert status == 0, err
    with h5py.File(partial, "r+") as handle:
        handle["complete"][1] = 0
    before = sha256(old)
    status, out, err = run_cli("dataset", "-n", "3", *SMALL, "-o", str(old), "--resume")
    assert status == 0 and "nothing to do" in out and sha256(old) == before  # other settings
    status, out, err = run_cli(*new_settings, "-o", str(old), "--resume")
    assert status == 0, err
    assert "3/3 runs complete (1 in this job" in out and not partial.exists()
    clean = tmp_path / "clean.h5"
    status, _, err = run_cli(*new_settings, "-o", str(clean))
    assert status == 0, err
    assert_same_arrays(old, clean)
    status, _, err = run_cli(*new_settings, "-o", str(partial))  # a partial of seed 4 again
    assert status == 0, err
    status, out, err = run_cli("dataset", "-n", "3", *SMALL, "-o", str(old), "--overwrite")
    assert status == 0 and "(3 in this job" in out and not partial.exists()  # seed 0: anew
