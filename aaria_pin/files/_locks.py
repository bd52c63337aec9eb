"""An output's exclusive lock: one aaria process writes a given output at a time.

The lock is ``fcntl.flock`` on a small file beside the output, ``.<name>.lock``, holding the
writer's pid. ``flock`` locks belong to the open file and go away with the process however it
ends (SIGKILL included), so a crash never leaves a lock held; the lock file a crash leaves is
taken over and removed by the next job. The lock is re-entrant within a process (the data-set
engine holds it for a whole job and writes its file through
:func:`~aaria_pin.files.paths.atomic_output`, which takes it too).
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import os
import threading
from collections.abc import Iterator
from pathlib import Path

from aaria_pin.errors import OutputFileError

__all__ = ["hidden_stem", "lock_holder", "output_lock"]

_HELD: dict[str, int] = {}
"""Locks this process holds: lock file path → nesting depth."""

_HELD_GUARD = threading.Lock()

_SPARE_BYTES = 40
"""Bytes a hidden companion name adds to the output's name: ``.`` + ``.<pid>.<8>.tmp`` + suffix."""


def name_max(folder: Path) -> int:
    """The longest file name the folder's file system takes [bytes] (255 where unknown)."""
    try:
        return int(os.pathconf(folder, "PC_NAME_MAX"))
    except (OSError, ValueError):
        return 255


def hidden_stem(final: Path) -> str:
    """The name hidden companions of ``final`` start with (its lock, its temporaries).

    The output's own name, or, where a companion's name would pass the file system's limit, a
    digest of it (so a name of up to the limit still gets its companions).
    """
    name = final.name
    limit = name_max(final.parent if str(final.parent) else Path("."))
    if len(os.fsencode(name)) + len(os.fsencode(final.suffix)) + _SPARE_BYTES > limit:
        return "aaria-" + hashlib.sha1(os.fsencode(name)).hexdigest()[:20]
    return name


def _lock_path(final: Path) -> Path:
    return final.parent / f".{hidden_stem(final)}.lock"


def lock_holder(final: Path) -> int | None:
    """The pid of another process that holds ``final``'s lock, or None (free, or ours)."""
    lock = _lock_path(final)
    if str(lock) in _HELD:
        return None
    try:
        descriptor = os.open(lock, os.O_RDONLY)
    except OSError:
        return None
    try:
        import fcntl

        try:
            fcntl.flock(descriptor, fcntl.LOCK_SH | fcntl.LOCK_NB)
        except BlockingIOError:
            return _pid_in(descriptor)
        fcntl.flock(descriptor, fcntl.LOCK_UN)
        return None
    finally:
        os.close(descriptor)


def _pid_in(descriptor: int) -> int:
    """The pid a lock file holds (0 when it cannot be read)."""
    try:
        return int(os.pread(descriptor, 32, 0).decode("ascii", "replace").strip() or 0)
    except (OSError, ValueError):
        return 0


def _busy(final: Path, pid: int) -> OutputFileError:
    shown = f"pid {pid}" if pid else "pid unknown"
    return OutputFileError(
        f"{final}: is being written by another aaria process ({shown}); allowed: an output "
        "no other job is writing (wait for it, or choose another file)",
        parameter="path",
        value=str(final),
        element=str(final),
    )


@contextlib.contextmanager
def output_lock(path: str | os.PathLike[str]) -> Iterator[Path]:
    """Hold the exclusive lock of output ``path`` for the block (re-entrant in a process).

    A second process asking for the same output is refused at once (it does not wait).

    Example::

        with output_lock("ds.h5"):
            ...  # make, resume and rename ds.h5: no other aaria process writes it meanwhile

    Args:
        path: the output file (a symbolic link is followed: the lock is the target's)

    Yields:
        The output path the lock covers (symbolic links resolved).

    Raises:
        OutputFileError: another process holds the lock (naming its pid), or the lock file
            cannot be made in the output's folder.
    """
    import fcntl

    final = Path(os.path.realpath(path)) if os.path.islink(path) else Path(path)
    lock = _lock_path(final)
    key = str(lock)
    with _HELD_GUARD:
        if key in _HELD:
            _HELD[key] += 1
            nested = True
        else:
            nested = False
    if nested:
        try:
            yield final
        finally:
            with _HELD_GUARD:
                _HELD[key] -= 1
        return
    descriptor = _acquire(final, lock, fcntl)
    with _HELD_GUARD:
        _HELD[key] = 1
    try:
        yield final
    finally:
        with _HELD_GUARD:
            del _HELD[key]
        with contextlib.suppress(OSError):
            os.unlink(lock)  # still locked: a waiting opener sees another inode and retries
        os.close(descriptor)


def _acquire(final: Path, lock: Path, fcntl: object) -> int:
    """Open, lock and stamp the lock file; the descriptor stays open while the lock is held."""
    flock = fcntl.flock  # type: ignore[attr-defined]
    exclusive = fcntl.LOCK_EX | fcntl.LOCK_NB  # type: ignore[attr-defined]
    for _ in range(20):
        try:
            descriptor = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as exc:
            raise OutputFileError(
                f"{final}: cannot lock it in {lock.parent} ({exc.strerror}); allowed: a file "
                "in a writable folder",
                parameter="path",
                value=str(final),
                element=str(final),
            ) from None
        try:
            flock(descriptor, exclusive)
        except OSError as exc:
            pid = _pid_in(descriptor)
            os.close(descriptor)
            if exc.errno in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                raise _busy(final, pid) from None
            raise OutputFileError(f"{final}: cannot be locked ({exc.strerror})") from None
        try:
            same = os.fstat(descriptor).st_ino == os.stat(lock).st_ino
        except FileNotFoundError:
            same = False
        if same:  # not a lock file its last holder removed while we opened it
            # The stamp is written, then the file trimmed to it: truncating to zero first made
            # ext4 write the file out when the descriptor closed (auto_da_alloc: a file
            # truncated to zero and written again is flushed on close), 2.5-4 ms of every
            # output (more on a busy disk) against 0.14 ms so.
            stamp = f"{os.getpid()}\n".encode()
            os.pwrite(descriptor, stamp, 0)
            os.ftruncate(descriptor, len(stamp))
            return descriptor
        os.close(descriptor)
    raise _busy(final, 0)
