"""An output's exclusive lock: one aaria process writes a given output at a time.

The lock is a :class:`filelock.UnixFileLock` (``flock``) on a small file beside the output,
``.<name>.lock``, stamped with the writer's pid. ``flock`` locks belong to the open file and go
away with the process however it ends (SIGKILL included), so a crash never leaves a lock held;
the lock file a crash leaves (a stale lock) is taken over and removed by the next job. The lock
is re-entrant within a process (the data-set engine holds it for a whole job and writes its file
through :func:`~aaria_pin.files.paths.atomic_output`, which takes it too). ``filelock`` is
imported when a lock is first taken (25 ms; ``aaria --help`` does not pay it).
"""

from __future__ import annotations

import contextlib
import errno
import functools
import hashlib
import os
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING

from aaria_pin.errors import OutputFileError
from aaria_pin.files._space import no_space, no_space_error

if TYPE_CHECKING:
    from filelock import UnixFileLock

__all__ = ["hidden_stem", "lock_holder", "output_lock"]

_HELD: dict[str, UnixFileLock] = {}
"""Locks this process holds: lock file path → the lock (``filelock`` counts the nesting)."""

_HELD_GUARD = threading.Lock()

os.register_at_fork(after_in_child=_HELD.clear)  # a forked child holds none of them

_ATTEMPTS = 20
"""Tries to take a lock whose file its last holder removed while we opened it."""

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
    """The pid of another process that holds ``final``'s lock, or None (free, or ours).

    0 when another process holds it but its stamp cannot be read (not written yet).
    """
    lock = _lock_path(final)
    if str(lock) in _HELD:
        return None
    return _holder(lock)


def _holder(lock: Path) -> int | None:
    """The pid stamped in a lock file another open file holds (0 unreadable), or None (free)."""
    import fcntl

    try:
        descriptor = os.open(lock, os.O_RDONLY)
    except OSError:
        return None
    try:
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


def _stamp(lock_path: Path, descriptor: int) -> None:
    """Write our pid into the lock file just locked (``filelock``'s ``on_acquired``).

    The stamp is written, then the file trimmed to it: truncating to zero first made ext4 write
    the file out when the descriptor closed (auto_da_alloc: a file truncated to zero and written
    again is flushed on close), 2.5-4 ms of every output (more on a busy disk) against 0.14 ms so.
    When the stamp cannot be written (a full device), the lock file is removed while it is
    still locked (a waiting opener sees it gone) and the error raised: ``filelock`` then
    releases the lock, and :func:`_acquire` reports it.
    """
    stamp = f"{os.getpid()}\n".encode()
    try:
        os.pwrite(descriptor, stamp, 0)
        os.ftruncate(descriptor, len(stamp))
    except OSError:
        with contextlib.suppress(OSError):
            os.unlink(lock_path)
        raise


def _refused(final: Path, text: str, allowed: str) -> OutputFileError:
    """``"<final>: <text>; allowed: <allowed>"``, the output ``path`` at fault.

    No ``allowed`` field: the CLI prints the message as written (it names the file).
    """
    return OutputFileError(
        f"{final}: {text}; allowed: {allowed}",
        parameter="path",
        value=str(final),
        element=str(final),
    )


def _busy(final: Path, pid: int) -> OutputFileError:
    return _refused(
        final,
        f"is being written by another aaria process (pid {pid or 'unknown'})",
        "an output no other job is writing (wait for it, or choose another file)",
    )


def _unlockable(final: Path, reason: str) -> OutputFileError:
    return _refused(
        final, f"cannot lock it in {final.parent} ({reason})", "a file in a writable folder"
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
        NoSpaceError: no room on the device for the lock file or its stamp (nothing is left).
    """
    final = Path(os.path.realpath(path)) if os.path.islink(path) else Path(path)
    lock_path = _lock_path(final)
    key = str(lock_path)
    with _HELD_GUARD:
        lock = _HELD.get(key)
        if lock is not None:
            lock.acquire()  # nested: filelock counts it
        else:
            lock = _acquire(final, lock_path)
            _HELD[key] = lock
    try:
        yield final
    finally:
        with _HELD_GUARD:
            if lock.lock_counter == 1:
                del _HELD[key]
                with contextlib.suppress(OSError):
                    os.unlink(lock_path)  # still locked: a waiting opener sees it gone and retries
            lock.release()


def _acquire(final: Path, lock_path: Path) -> UnixFileLock:
    """Take and stamp the lock of ``final`` (non-blocking), or refuse naming the holder."""
    from filelock import Timeout, UnixFileLock

    folder = lock_path.parent
    if not folder.is_dir():  # filelock would make the folder
        raise _unlockable(final, os.strerror(errno.ENOENT))
    lock = UnixFileLock(
        lock_path,
        mode=0o644,
        thread_local=False,  # re-entrant in the process, whichever thread
        blocking=False,
        fallback_to_soft=False,  # a soft lock a crash leaves stays held
        on_acquired=functools.partial(_stamp, lock_path),
    )
    for _ in range(_ATTEMPTS):
        try:
            lock.acquire()
        except Timeout:
            pid = _holder(lock_path)
            if pid is not None:
                raise _busy(final, pid) from None
            continue  # its holder removed the file as we opened it: try the new one
        except OSError as exc:
            if no_space(exc):  # the lock file or its stamp: no room for either
                raise no_space_error(final) from None
            raise _unlockable(final, exc.strerror or str(exc)) from None
        return lock
    raise _busy(final, 0)
