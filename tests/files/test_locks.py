"""The output lock (``files/_locks.py``): the stamp, stale lock files, nesting, refusals."""

from __future__ import annotations

import os
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from aaria_pin.errors import OutputFileError
from aaria_pin.files._locks import lock_holder, output_lock

_HOLDER = (
    "import sys, time; from aaria_pin.files._locks import output_lock\n"
    "with output_lock(sys.argv[1]):\n"
    "    print('held', flush=True); sys.stdin.readline()\n"
)


def test_the_lock_file_holds_our_pid_and_goes_after(tmp_path: Path) -> None:
    target = tmp_path / "out.h5"
    lock = tmp_path / ".out.h5.lock"
    with output_lock(target) as final:
        assert final == target
        assert lock.read_text() == f"{os.getpid()}\n"
        assert lock_holder(target) is None  # ours: not another process's
    assert not lock.exists()


def test_a_stale_lock_file_is_taken_over_and_removed(tmp_path: Path) -> None:
    target = tmp_path / "out.h5"
    lock = tmp_path / ".out.h5.lock"
    lock.write_text("4000000\nleft by a killed job\n")  # no flock on it: its holder is gone
    assert lock_holder(target) is None
    with output_lock(target):
        assert lock.read_text() == f"{os.getpid()}\n"  # the stamp trimmed to our pid
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def test_another_process_is_named_by_its_pid(tmp_path: Path) -> None:
    target = tmp_path / "out.h5"
    holder = subprocess.Popen(
        [sys.executable, "-c", _HOLDER, str(target)],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert holder.stdout is not None and holder.stdout.readline() == "held\n"
        assert lock_holder(target) == holder.pid
        with pytest.raises(OutputFileError) as caught, output_lock(target):
            pass
        assert f"being written by another aaria process (pid {holder.pid})" in str(caught.value)
        assert caught.value.parameter == "path" and caught.value.element == str(target)
    finally:
        assert holder.stdin is not None
        holder.stdin.write("\n")
        holder.stdin.close()
        holder.wait(60)
    assert lock_holder(target) is None
    with output_lock(target):  # free again
        pass
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def test_the_lock_is_reentrant_across_threads(tmp_path: Path) -> None:
    target = tmp_path / "ds.h5"
    lock = tmp_path / ".ds.h5.lock"
    inner: list[bool] = []

    def nested() -> None:
        with output_lock(target):
            inner.append(lock.exists())

    with output_lock(target):
        worker = threading.Thread(target=nested)
        worker.start()
        worker.join(10)
        assert inner == [True]
        assert lock.exists()  # the inner block does not remove the outer one's lock file
    assert not lock.exists()


def test_a_missing_folder_is_refused_not_made(tmp_path: Path) -> None:
    target = tmp_path / "nowhere" / "out.h5"
    with pytest.raises(OutputFileError) as caught, output_lock(target):
        pass
    assert str(caught.value) == (
        f"{target}: cannot lock it in {target.parent} (No such file or directory); "
        "allowed: a file in a writable folder"
    )
    assert caught.value.parameter == "path"
    assert not target.parent.exists()


def test_a_symbolic_link_locks_its_target(tmp_path: Path) -> None:
    real = tmp_path / "data" / "out.h5"
    real.parent.mkdir()
    link = tmp_path / "link.h5"
    link.symlink_to(real)
    with output_lock(link) as final:
        assert final == real
        assert (real.parent / ".out.h5.lock").exists()
        assert not (tmp_path / ".link.h5.lock").exists()


def test_a_stamp_that_cannot_be_written_leaves_no_lock(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A full device: the lock is released, its file removed, the error the one NoSpaceError."""
    from aaria_pin.errors import NoSpaceError

    def full(*_: object) -> int:
        raise OSError(28, "No space left on device")

    target = tmp_path / "out.h5"
    with monkeypatch.context() as patch:
        patch.setattr(os, "pwrite", full)
        with pytest.raises(NoSpaceError, match=r"no space left on device writing .*out\.h5"):
            with output_lock(target):
                pytest.fail("the block must not run")
    assert list(tmp_path.iterdir()) == []
    with output_lock(target):  # taken again at once: nothing was left held
        assert lock_holder(target) is None
