"""Running out of room on the device: the one error, checks before writing, HDF5 closed safely.

Every writer ends a full disk (``ENOSPC``, ``EDQUOT``, ``EFBIG``) with one
:class:`~aaria_pin.errors.NoSpaceError`, "no space left on device writing X; nothing was
replaced" (:func:`no_space_error`), which the command line turns into exit status 1.

HDF5 (libhdf5 2.0 through h5py 3.16) cannot be left to meet a full disk on its own. Measured on
a 2 MiB tmpfs: ``aaria simulate --duration 20 -o x.h5`` (2.3 MB of series) failed its first
series write with ENOSPC; closing the file then failed too (``H5Fclose`` flushes the object
headers of the datasets: "Can't decrement id ref count (file write failed … errno = 28)"),
which left the dataset identifiers registered over a half-freed file; when the traceback that
held them was dropped, ``H5D_close`` ran over that memory and the process died with SIGSEGV
(exit 139, no message; the same for ``.mat`` v7.3, for a data set's layout and for
``dataset-stats --store``, which writes in place). So:

- an HDF5 file written under a temporary name is closed by :func:`close_hdf5`: it is flushed
  first (a failure there is reported while every identifier can still be closed), and after
  any failure the temporary is truncated to nothing before it is closed, which gives HDF5 back
  the room its closing writes need (the file is removed next anyway); the close is tried again
  while it fails (after a failed flush HDF5 fails a close or two with "slist already
  enabled?" before it closes the file), so every identifier is invalid when it returns;
- a write into an existing file (which cannot be truncated) holds a reserve of the device for
  as long as it writes (:func:`spare_room`) and keeps every object it opens until the file is
  closed (h5py closing a dropped object ignores a failure, which breaks the file the same
  way); on a failure the reserve is freed before the file is closed (:func:`close_hdf5` with
  ``make_room``), so the close has the room it needs;
- a run file's size (its preallocated series, tables, names and URDF) is checked against the
  device's free space before it is made (:func:`check_space`; ``os.statvfs``, a few µs), so a
  long simulation is not computed for a file that cannot hold it; a compressed one is checked
  against its uncompressed size, as a bound: its chunks wait in HDF5's chunk cache until the
  close, and a full device met there ("Can't destroy cache") left the file open for good;
- every output is refused when the device has less than :data:`METADATA_BYTES` free
  (``atomic_output``): with 8 kB left a data set's layout failed inside h5py's own closing of
  the objects it drops, which crashed the process too.

Not covered: a device that fills up (another process writing) between the check and the end
of a compressed run file, or while a ``.mat`` v7.3 lays out its variables, can still meet
HDF5's failure inside a close h5py ignores.
"""

from __future__ import annotations

import contextlib
import errno
import os
import shutil
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from aaria_pin.errors import NoSpaceError

__all__ = ["check_space", "close_hdf5", "no_space", "no_space_error", "spare_room"]

_NO_SPACE = (errno.ENOSPC, errno.EDQUOT, errno.EFBIG)
_NO_SPACE_TEXT = ("No space left on device", "Disk quota exceeded", "File too large", "errno = 28")

METADATA_BYTES = 1 << 16
"""Room an HDF5 file's metadata takes beside its data, at most, in the files aaria writes
[bytes] (object headers, heaps, B-trees: 10-40 kB measured for a run file)."""


def no_space(exc: BaseException) -> bool:
    """Whether an error says the file system ran out of room."""
    if isinstance(exc, NoSpaceError):
        return True
    if isinstance(exc, OSError) and exc.errno in _NO_SPACE:
        return True
    text = str(exc)
    return isinstance(exc, OSError | RuntimeError) and any(t in text for t in _NO_SPACE_TEXT)


def no_space_error(final: str | os.PathLike[str]) -> NoSpaceError:
    """The one error of a full device while writing output ``final``."""
    return NoSpaceError(
        f"no space left on device writing {final}; nothing was replaced",
        parameter="path",
        value=str(final),
        element=str(final),
    )


def _folder(final: Path) -> Path:
    return final.parent if str(final.parent) else Path(".")


def check_space(final: str | os.PathLike[str], nbytes: int) -> None:
    """Refuse a write of ``nbytes`` (plus :data:`METADATA_BYTES`) the device cannot hold.

    Args:
        final: the output (its folder's device is checked)
        nbytes: the bytes about to be written [bytes]

    Raises:
        NoSpaceError: the device has less room free.
    """
    try:
        free = shutil.disk_usage(_folder(Path(final))).free
    except OSError:
        return  # a folder that cannot be asked is reported by the write itself
    if free < nbytes + METADATA_BYTES:
        raise no_space_error(final)


def close_hdf5(handle: Any, *, failed: bool, make_room: Callable[[], None] | None = None) -> None:
    """Close an h5py file written under a temporary name, safely also on a full device.

    The file is flushed, then closed. After a failure (``failed``, or a flush that fails) the
    file is truncated to nothing first: it is about to be removed, and that gives HDF5 the room
    its closing writes need (see the module docstring); the close is tried again while it
    fails and closes something (:func:`_close_all`), so every identifier is closed now.

    Args:
        handle: the open ``h5py.File`` (of a temporary the caller removes on failure)
        failed: whether the writing failed (the file is discarded)
        make_room: frees room on the device before a failed file is closed (default: truncate
            the file, a temporary the caller removes; a file written in place passes the
            function of :func:`spare_room`)

    Raises:
        OSError, RuntimeError: the flush failed (the file is closed all the same).
    """
    if not handle.id.valid:
        return
    error: BaseException | None = None
    if not failed:
        try:
            handle.flush()
        except BaseException as exc:  # a full device: reported once the file is closed
            error = exc
    if failed or error is not None:
        with contextlib.suppress(OSError):
            if make_room is None:
                os.truncate(handle.filename, 0)
            else:
                make_room()
    _close_all(handle, retry=failed or error is not None)
    if error is not None:
        raise error


def _close_all(handle: Any, *, retry: bool) -> None:
    """Close the file and its objects; with ``retry``, try again while it fails (a few times).

    On a full device each failing close still closes objects (HDF5 drops the one it failed
    on), so trying again ends every identifier: measured, a failed flush makes the first close
    or two fail ("slist already enabled?"), a compressed series' dirty chunks make each close
    fail on one dataset.
    """
    from h5py import h5f

    def still_open() -> int:
        return int(h5f.get_obj_count(handle.id, h5f.OBJ_ALL)) if handle.id.valid else 0

    stuck = 0
    while True:
        before = still_open()
        try:
            handle.close()
            return
        except BaseException:
            stuck = stuck + 1 if still_open() >= before else 0
            if not retry or not handle.id.valid or stuck >= _CLOSE_TRIES:
                raise


_CLOSE_TRIES = 4
"""Closes of a failed HDF5 file tried in a row without closing anything, before giving up."""


@contextlib.contextmanager
def spare_room(final: str | os.PathLike[str], nbytes: int) -> Iterator[Callable[[], None]]:
    """Hold ``nbytes`` of the device beside ``final`` while a file is written in place.

    A hidden file of that size (``.aaria-spare.<random>``) is allocated (``posix_fallocate``)
    before the block and removed after it; the block gets a function that removes it at once,
    to call when a write failed so that closing the file finds room (see the module docstring).

    Args:
        final: the file written in place
        nbytes: the room to hold [bytes] (at least what closing the file may write)

    Yields:
        A function that frees the room (idempotent).

    Raises:
        NoSpaceError: the device has not ``nbytes`` free (nothing is written).
    """
    try:
        descriptor, name = tempfile.mkstemp(prefix=".aaria-spare.", dir=_folder(Path(final)))
    except OSError as exc:
        if no_space(exc):
            raise no_space_error(final) from None
        raise
    spare = Path(name)
    try:
        os.posix_fallocate(descriptor, 0, max(1, nbytes))
    except OSError as exc:
        spare.unlink(missing_ok=True)
        if no_space(exc):
            raise no_space_error(final) from None
        raise
    finally:
        os.close(descriptor)

    def free() -> None:
        spare.unlink(missing_ok=True)

    try:
        yield free
    finally:
        free()
