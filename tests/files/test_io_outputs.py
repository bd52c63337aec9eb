"""Outputs that lose nothing: special paths, two writers, stale temporaries, names, full disks."""

from __future__ import annotations

import errno
import os
import subprocess
import sys
import textwrap
import threading
from pathlib import Path

import pytest

from aaria_pin.errors import OutputFileError
from aaria_pin.files.io import (
    atomic_output,
    check_outputs,
    output_lock,
    write_text_atomic,
)


def _names(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


def test_a_symlink_is_followed_and_kept(tmp_path: Path) -> None:
    target = tmp_path / "data" / "out.txt"
    target.parent.mkdir()
    target.write_text("old")
    link = tmp_path / "link.txt"
    link.symlink_to(target)
    write_text_atomic(link, "new")
    assert link.is_symlink() and os.readlink(link) == str(target)
    assert target.read_text() == "new"
    assert _names(target.parent) == ["out.txt"]  # no temporary, no lock file left


def test_a_dangling_symlink_creates_its_target(tmp_path: Path) -> None:
    link = tmp_path / "link.txt"
    link.symlink_to(tmp_path / "made.txt")
    write_text_atomic(link, "x")
    assert link.is_symlink() and (tmp_path / "made.txt").read_text() == "x"


def test_dev_null_is_written_through_and_stays_a_device() -> None:
    write_text_atomic("/dev/null", "nothing to see")
    assert Path("/dev/null").is_char_device()


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="no /dev/full")
def test_dev_full_reports_no_space_and_stays_a_device() -> None:
    with pytest.raises(OutputFileError, match=r"^no space left on device writing /dev/full"):
        write_text_atomic("/dev/full", "x" * 10)
    assert Path("/dev/full").is_char_device()


def test_a_fifo_is_written_through(tmp_path: Path) -> None:
    fifo = tmp_path / "pipe.txt"
    os.mkfifo(fifo)
    received: list[bytes] = []
    reader = threading.Thread(target=lambda: received.append(fifo.read_bytes()))
    reader.start()
    write_text_atomic(fifo, "through the pipe")
    reader.join(10)
    assert received == [b"through the pipe"]
    assert fifo.is_fifo() and _names(tmp_path) == ["pipe.txt"]


@pytest.mark.parametrize("name", ["-", ""])
def test_standard_output_is_refused(name: str) -> None:
    with pytest.raises(OutputFileError, match="allowed: a file path"):
        write_text_atomic(name, "x")


def test_a_socket_is_refused(tmp_path: Path) -> None:
    import socket

    path = tmp_path / "s.sock"
    with socket.socket(socket.AF_UNIX) as server:
        server.bind(str(path))
        with pytest.raises(OutputFileError, match="is a socket; allowed: a regular file"):
            write_text_atomic(path, "x")


@pytest.mark.parametrize("size", [256, 1000])
def test_names_over_the_limit_are_one_line(tmp_path: Path, size: int) -> None:
    name = "é" * (size // 2) + ".h5"  # multi-byte characters: the limit is in bytes
    with pytest.raises(OutputFileError, match=r"is a name of \d+ bytes; allowed: at most 255"):
        write_text_atomic(tmp_path / name, "x")
    assert _names(tmp_path) == []


def test_a_name_at_the_limit_gets_its_temporary(tmp_path: Path) -> None:
    name = "n" * 252 + ".h5"  # 255 bytes: the temporary's name would not fit as it is
    seen = []
    with atomic_output(tmp_path / name) as temporary:
        seen = _names(tmp_path)
        assert len(os.fsencode(temporary.name)) <= 255
        temporary.write_text("x")
    assert any(n.endswith(".lock") for n in seen)
    assert _names(tmp_path) == [name]


def test_a_stale_temporary_is_removed(tmp_path: Path) -> None:
    dead = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"],
        capture_output=True,
        text=True,
        check=True,
    )
    pid = int(dead.stdout)
    stale = tmp_path / f".out.h5.{pid}.abcd1234.tmp.h5"
    stale.write_bytes(b"57 MB of a crashed job")
    alive = tmp_path / f".out.h5.{os.getppid()}.abcd1234.tmp.h5"  # a live process: kept
    alive.write_bytes(b"still being written")
    other = tmp_path / "unrelated.txt"
    other.write_text("mine")
    write_text_atomic(tmp_path / "out.h5", "x")
    assert _names(tmp_path) == sorted([alive.name, "out.h5", "unrelated.txt"])


def test_overwrite_false_refuses_an_output_that_appears_meanwhile(tmp_path: Path) -> None:
    target = tmp_path / "out.txt"
    with pytest.raises(OutputFileError, match="appeared while it was being written"):
        with atomic_output(target, overwrite=False) as temporary:
            temporary.write_text("mine")
            target.write_text("someone else's")
    assert target.read_text() == "someone else's"
    assert _names(tmp_path) == ["out.txt"]
    with pytest.raises(OutputFileError, match="exists; allowed: a new file"):
        write_text_atomic(target, "x", overwrite=False)


_WRITER = textwrap.dedent(
    """
    import sys, time
    from aaria_pin.files.io import atomic_output
    from aaria_pin.errors import OutputFileError
    try:
        with atomic_output(sys.argv[1]) as temporary:
            print("writing", flush=True)
            temporary.write_text(sys.argv[2])
            time.sleep(float(sys.argv[3]))
    except OutputFileError as exc:
        print(exc, file=sys.stderr)
        sys.exit(2)
    """
)


def test_two_writers_of_one_output_one_is_refused(tmp_path: Path) -> None:
    target = tmp_path / "c.h5"
    first = subprocess.Popen(
        [sys.executable, "-c", _WRITER, str(target), "seed 7", "3"],
        stdout=subprocess.PIPE,
        text=True,
    )
    assert first.stdout is not None and first.stdout.readline() == "writing\n"
    second = subprocess.run(
        [sys.executable, "-c", _WRITER, str(target), "seed 8", "0"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert first.wait(60) == 0
    assert second.returncode == 2
    assert f"is being written by another aaria process (pid {first.pid})" in second.stderr
    assert len(second.stderr.strip().splitlines()) == 1
    assert target.read_text() == "seed 7"
    assert _names(tmp_path) == ["c.h5"]


def test_check_outputs_names_the_busy_output(tmp_path: Path) -> None:
    target = tmp_path / "c.h5"
    holder = subprocess.Popen(
        [sys.executable, "-c", _WRITER, str(target), "x", "3"], stdout=subprocess.PIPE, text=True
    )
    assert holder.stdout is not None and holder.stdout.readline() == "writing\n"
    try:
        with pytest.raises(OutputFileError, match=f"pid {holder.pid}"):
            check_outputs(tmp_path / "free.png", target)
    finally:
        holder.wait(60)


def test_the_lock_is_reentrant_in_a_process(tmp_path: Path) -> None:
    target = tmp_path / "ds.h5"
    with output_lock(target):
        write_text_atomic(target, "made")
        write_text_atomic(target, "resumed")
    assert target.read_text() == "resumed"
    assert _names(tmp_path) == ["ds.h5"]


def test_check_outputs_refuses_an_unwritable_folder(tmp_path: Path) -> None:
    existing = tmp_path / "existing.h5"
    existing.write_text("keep")
    readonly = tmp_path / "ro"
    readonly.mkdir()
    readonly.chmod(0o500)
    try:
        if os.access(readonly, os.W_OK):
            pytest.skip("running as a user who writes anywhere (root)")
        with pytest.raises(OutputFileError, match=r"cannot be written in .*permission denied"):
            check_outputs(existing, readonly / "s.png", None)
    finally:
        readonly.chmod(0o700)
    assert existing.read_text() == "keep"


def test_check_outputs_checks_every_output_first(tmp_path: Path) -> None:
    existing = tmp_path / "existing.h5"
    existing.write_text("keep")
    with pytest.raises(OutputFileError, match="given for two outputs"):
        check_outputs(existing, tmp_path / "." / "existing.h5")
    with pytest.raises(OutputFileError, match=r"existing\.h5 is not a folder"):
        check_outputs(existing, existing / "x.png")  # a file where a folder should be
    with pytest.raises(OutputFileError, match="is a folder"):
        check_outputs(tmp_path)
    with pytest.raises(OutputFileError, match="exists; allowed: a new file"):
        check_outputs(tmp_path / "new.png", existing, overwrite=False)
    assert check_outputs(existing, None, tmp_path / "new.png") == [existing, tmp_path / "new.png"]
    assert existing.read_text() == "keep" and _names(tmp_path) == ["existing.h5"]


def test_check_outputs_refuses_a_missing_folder_before_anything(tmp_path: Path) -> None:
    with pytest.raises(OutputFileError, match=r"folder .* does not exist"):
        check_outputs(tmp_path / "a.h5", tmp_path / "missing" / "b.png")
    assert _names(tmp_path) == []


def test_disk_full_while_writing_leaves_the_old_file(tmp_path: Path) -> None:
    target = tmp_path / "out.h5"
    target.write_text("old")

    def full(*_: object) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    with pytest.raises(OutputFileError, match=f"^no space left on device writing {target}"):
        with atomic_output(target) as temporary:
            temporary.write_text("part")
            full()
    assert target.read_text() == "old" and _names(tmp_path) == ["out.h5"]


def test_disk_full_from_a_file_size_limit(tmp_path: Path) -> None:
    """A real write that runs out of room: RLIMIT_FSIZE in a child makes write() fail."""
    script = textwrap.dedent(
        """
        import resource, signal, sys
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # EFBIG instead of a signal
        resource.setrlimit(resource.RLIMIT_FSIZE, (4096, 4096))
        from aaria_pin.files.io import write_text_atomic
        from aaria_pin.errors import OutputFileError
        try:
            write_text_atomic(sys.argv[1], "x" * 100_000)
        except OutputFileError as exc:
            print(exc)
            sys.exit(1)
        """
    )
    target = tmp_path / "big.txt"
    target.write_text("old")
    result = subprocess.run(
        [sys.executable, "-c", script, str(target)], capture_output=True, text=True, timeout=60
    )
    assert result.returncode == 1, result.stderr
    assert result.stdout.startswith(f"no space left on device writing {target}")
    assert target.read_text() == "old" and _names(tmp_path) == ["big.txt"]
