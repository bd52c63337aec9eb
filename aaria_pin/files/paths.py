"""Input and output paths: inputs that exist and can be read, outputs written atomically.

Every output goes through :func:`atomic_output`:

- a regular file (or a new one) is written to a hidden temporary beside it,
  ``.<name>.<pid>.<random>.tmp<suffix>``, and renamed onto it when complete, under the output's
  exclusive lock (:func:`~aaria_pin.files._locks.output_lock`): a second aaria process writing
  the same output is refused at once, a failure leaves the old file as it was, and the next
  job on the output removes the temporaries of writers that died (their pid is gone);
- a symbolic link is followed: its target is written atomically and the link kept;
- a character device or a FIFO (``/dev/null``, ``/dev/stdout``, a named pipe) is written
  through: the output is made in a temporary of the system's temporary folder (HDF5 and the
  picture writers need a file they can seek in) and copied into the device when complete, with
  no rename, so the device stays what it was;
- a block device, a socket, a folder, ``-`` (standard output, which the commands do not write
  to) and a name longer than the file system allows are refused in one line.

Running out of space (``ENOSPC``, ``EDQUOT``, ``EFBIG``) while writing is one line, "no space
left on device writing X; nothing was replaced", with the temporary removed (and the lock).
A device with less than :data:`~aaria_pin.files._space.METADATA_BYTES` free is refused before
the lock is taken: HDF5 meeting a full device while it lays a file out can crash the process
(measured with 8 kB left, :mod:`aaria_pin.files._space`).
:func:`check_outputs` runs the same checks on every output of a command before the first one is
written.
"""

from __future__ import annotations

import contextlib
import os
import re
import shutil
import stat
import tempfile
from collections.abc import Iterator, Sequence
from pathlib import Path

from aaria_pin.errors import AariaError, InputFileError, OutputFileError
from aaria_pin.files._locks import hidden_stem, lock_holder, name_max, output_lock
from aaria_pin.files._space import check_space, no_space, no_space_error

__all__ = [
    "atomic_output",
    "check_name_lengths",
    "check_output",
    "check_outputs",
    "existing_input",
    "no_space",
    "output_lock",
    "write_failure",
    "write_text_atomic",
]


def existing_input(path: str | os.PathLike[str], suffixes: Sequence[str] | None, kind: str) -> Path:
    """The path of an existing, readable regular input file whose suffix is one of ``suffixes``.

    A FIFO, a device or a socket is refused (reading one could wait forever, or never end).

    Args:
        path: the file
        suffixes: the allowed suffixes, lower case with the dot (``(".h5", ".mat")``); None:
            any
        kind: what the file holds, for the message (``"table"``, ``"run"``)

    Raises:
        InputFileError: another suffix (checked first), no such file, a folder, not a regular
            file, or not readable (``parameter="file"``: an input; errors of an output name
            ``"path"``, which the command line maps to ``-o/--output``).
    """
    file = Path(path)
    suffix = file.suffix.lower()
    if suffixes is not None and suffix not in suffixes:
        raise InputFileError(
            f"{file}: unknown {kind} file type {suffix!r}; allowed: {', '.join(suffixes)}",
            parameter="file",
        )
    try:
        mode = file.stat().st_mode
    except OSError:
        raise InputFileError(f"{file}: no such file", parameter="file") from None
    if stat.S_ISDIR(mode):
        raise InputFileError(f"{file}: is a folder; allowed: a {kind} file", parameter="file")
    if not stat.S_ISREG(mode):
        raise InputFileError(
            f"{file}: is a {_kind_of(mode)}; allowed: a regular {kind} file (copy it to one)",
            parameter="file",
        )
    if not os.access(file, os.R_OK):
        raise InputFileError(f"{file}: cannot be read (permission denied)", parameter="file")
    return file


def _kind_of(mode: int) -> str:
    """What a non-regular file is, in words."""
    if stat.S_ISFIFO(mode):
        return "FIFO (named pipe)"
    if stat.S_ISCHR(mode):
        return "character device"
    if stat.S_ISBLK(mode):
        return "block device"
    if stat.S_ISSOCK(mode):
        return "socket"
    return "special file"


def _refused(final: Path | str, what: str, allowed: str) -> OutputFileError:
    return OutputFileError(
        f"{final}: {what}; allowed: {allowed}",
        parameter="path",
        value=str(final),
        element=str(final),
    )


_PATH_MAX = 4096
"""The longest path Linux takes [bytes] (``PATH_MAX``)."""


def check_name_lengths(path: str | os.PathLike[str]) -> None:
    """Refuse an output path with a file or folder name longer than its file system takes.

    Every name of the path is checked (a 300-character folder too, which the system refuses
    with ``ENAMETOOLONG`` at the first look), and the whole path against ``PATH_MAX``.
    :func:`check_output` runs it first; a command that makes the output's folder runs it on
    the files it will write there.

    Args:
        path: the output file (its folders need not exist)

    Raises:
        OutputFileError: a name longer than the limit of the file system of its nearest
            existing folder (255 bytes on most), or a path longer than 4096 bytes.
    """
    encoded = os.fsencode(os.fspath(path))
    if len(encoded) >= _PATH_MAX:
        shown = os.fspath(path)[:60] + "…"
        raise _refused(shown, f"is a path of {len(encoded)} bytes", f"at most {_PATH_MAX - 1}")
    existing = Path(path).parent
    while str(existing) not in ("", ".", existing.anchor) and not os.path.isdir(existing):
        existing = existing.parent
    limit = name_max(existing if str(existing) else Path("."))
    for name in Path(path).parts:
        size = len(os.fsencode(name))
        if size > limit:
            raise _refused(name[:40] + "…", f"is a name of {size} bytes", f"at most {limit} bytes")


def check_output(
    path: str | os.PathLike[str],
    *,
    overwrite: bool = True,
    suffixes: Sequence[str] | None = None,
) -> Path:
    """Check that ``path`` can be written, without touching anything.

    Args:
        path: the output file
        overwrite: whether an existing regular file may be replaced
        suffixes: the allowed suffixes, lower case with the dot (any when None)

    Returns:
        The path to write: ``path``, or the target of a symbolic link.

    Raises:
        OutputFileError: ``-``; another suffix; a file or folder name longer than the file
            system takes (:func:`check_name_lengths`); a missing or unwritable folder; a
            folder, block device or socket at ``path``; an existing file when ``overwrite`` is
            false; an output another aaria process is writing.
    """
    if os.fspath(path) in ("-", ""):
        raise _refused(
            repr(os.fspath(path)),
            "is not a file path",
            "a file path (this command does not write to standard output)",
        )
    check_name_lengths(path)
    given = Path(path)
    final = Path(os.path.realpath(given)) if os.path.islink(given) else given
    if suffixes is not None and final.suffix.lower() not in suffixes:
        raise _refused(final, f"has the suffix {final.suffix!r}", ", ".join(suffixes))
    try:
        mode: int | None = final.stat().st_mode
    except FileNotFoundError:
        mode = None
    except NotADirectoryError:
        raise _refused(
            final, f"folder {final.parent} is not a folder", "a file in an existing folder"
        ) from None
    except OSError as exc:
        raise _refused(
            final, f"cannot be reached ({exc.strerror})", "a writable file path"
        ) from None
    if mode is not None and stat.S_ISDIR(mode):
        raise _refused(final, "is a folder", "a file path")
    if mode is not None and not stat.S_ISREG(mode):
        if stat.S_ISCHR(mode) or stat.S_ISFIFO(mode):
            if not os.access(final, os.W_OK):
                raise _refused(final, "cannot be written (permission denied)", "a writable file")
            return final
        raise _refused(
            final, f"is a {_kind_of(mode)}", "a regular file, a character device or a FIFO"
        )
    folder = final.parent if str(final.parent) else Path(".")
    if not folder.is_dir():
        raise _refused(final, f"folder {folder} does not exist", "a file in an existing folder")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise _refused(
            final,
            f"cannot be written in {folder} (permission denied)",
            "a file in a writable folder",
        )
    if mode is not None and not overwrite:
        raise _refused(final, "exists", "a new file (or overwrite it)")
    holder = lock_holder(final)
    if holder is not None:
        raise _refused(
            final,
            f"is being written by another aaria process (pid {holder or 'unknown'})",
            "an output no other job is writing",
        )
    return final


def check_outputs(*paths: str | os.PathLike[str] | None, overwrite: bool = True) -> list[Path]:
    """Check every output of a command before the first is written (None entries skipped).

    Args:
        paths: the outputs
        overwrite: whether existing regular files may be replaced

    Returns:
        The paths to write (see :func:`check_output`), in order, without the None entries.

    Raises:
        OutputFileError: as :func:`check_output`, or two outputs that are the same file.
    """
    checked = [check_output(p, overwrite=overwrite) for p in paths if p is not None]
    seen: dict[str, Path] = {}
    for final in checked:
        key = os.path.realpath(final)
        if key in seen and not _is_device(final):
            raise _refused(final, "is given for two outputs", "a different file for each")
        seen[key] = final
    return checked


def _is_device(final: Path) -> bool:
    try:
        mode = final.stat().st_mode
    except OSError:
        return False
    return stat.S_ISCHR(mode) or stat.S_ISFIFO(mode)


def write_failure(final: Path, exc: BaseException) -> OutputFileError:
    """The one-line error of a write of ``final`` that failed with ``exc``.

    ``exc`` is an error of h5py, scipy or the system: a full device gives the
    :class:`~aaria_pin.errors.NoSpaceError`, anything else "X: cannot be written (reason)".
    """
    if no_space(exc):
        return no_space_error(final)
    reason = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
    return OutputFileError(f"{final}: cannot be written ({reason})", parameter="path")


_TEMPORARY = re.compile(r"\.(?P<pid>\d+)\.[A-Za-z0-9_]{8}\.tmp")


def _remove_stale_temporaries(final: Path, stem: str) -> None:
    """Remove the temporaries of ``final`` whose writer's process no longer exists."""
    folder = final.parent if str(final.parent) else Path(".")
    prefix = f".{stem}"
    pattern = re.compile(re.escape(prefix) + _TEMPORARY.pattern + re.escape(final.suffix) + "$")
    with contextlib.suppress(OSError), os.scandir(folder) as entries:
        for entry in entries:
            if not entry.name.startswith(prefix):
                continue
            match = pattern.match(entry.name)
            if match is None or int(match["pid"]) == os.getpid():
                continue
            if not _alive(int(match["pid"])):
                with contextlib.suppress(OSError):
                    os.unlink(entry.path)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True  # another user's process
    return True


def _new_temporary(folder: Path, stem: str, suffix: str) -> Path:
    handle, name = tempfile.mkstemp(
        prefix=f".{stem}.{os.getpid()}.", suffix=f".tmp{suffix}", dir=folder
    )
    os.close(handle)
    temporary = Path(name)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(temporary, 0o666 & ~umask)  # as a plain open() would have made it
    return temporary


@contextlib.contextmanager
def atomic_output(path: str | os.PathLike[str], *, overwrite: bool = True) -> Iterator[Path]:
    """Give a temporary path to write; it becomes ``path`` when the block succeeds.

    On any exception the temporary file is removed and ``path`` is left as it was. See the
    module docstring for links, devices and FIFOs, the lock and stale temporaries.

    Args:
        path: the final output file
        overwrite: whether an existing file may be replaced; when false, a file that appears
            at ``path`` while the block runs is not replaced either (the rename refuses)

    Yields:
        The temporary file to write (its suffix is ``path``'s).

    Raises:
        OutputFileError: as :func:`check_output`; no space left while writing; the output
            appeared meanwhile (``overwrite`` false).
    """
    final = check_output(path, overwrite=overwrite)
    if _is_device(final):
        with _through_device(final) as temporary:
            yield temporary
        return
    folder = final.parent if str(final.parent) else Path(".")
    check_space(final, 0)  # a device all but full: refused before HDF5 can meet it mid-layout
    with output_lock(final):
        stem = hidden_stem(final)
        _remove_stale_temporaries(final, stem)
        try:
            temporary = _new_temporary(folder, stem, final.suffix)
        except OSError as exc:
            if no_space(exc):
                raise no_space_error(final) from None
            raise _refused(
                final,
                f"cannot be written in {folder} ({exc.strerror})",
                "a file in a writable folder",
            ) from None
        try:
            yield temporary
            _rename(temporary, final, overwrite)
        except BaseException as exc:
            temporary.unlink(missing_ok=True)
            if no_space(exc):
                raise no_space_error(final) from None
            raise


def _rename(temporary: Path, final: Path, overwrite: bool) -> None:
    """Move the finished temporary onto ``final`` (never replacing a file unless allowed)."""
    if overwrite:
        os.replace(temporary, final)
        return
    try:
        os.link(temporary, final)  # atomic: fails if final exists
    except FileExistsError:
        raise _refused(
            final, "appeared while it was being written", "a new file (or overwrite it)"
        ) from None
    except OSError:  # a file system without hard links
        if final.exists():
            raise _refused(
                final, "appeared while it was being written", "a new file (or overwrite it)"
            ) from None
        os.replace(temporary, final)
        return
    temporary.unlink()


@contextlib.contextmanager
def _through_device(final: Path) -> Iterator[Path]:
    """Write a character device or FIFO: a temporary elsewhere, copied in when complete."""
    handle, name = tempfile.mkstemp(prefix="aaria-", suffix=f".tmp{final.suffix}")
    os.close(handle)
    temporary = Path(name)
    try:
        yield temporary
        with open(temporary, "rb") as source:
            descriptor = os.open(final, os.O_WRONLY)
            with open(descriptor, "wb", buffering=0, closefd=True) as target:
                shutil.copyfileobj(source, target, 1 << 20)
    except BaseException as exc:
        if no_space(exc):
            raise no_space_error(final) from None
        if isinstance(exc, OSError) and not isinstance(exc, AariaError):
            raise _refused(
                final, f"cannot be written ({exc.strerror})", "a writable file, device or FIFO"
            ) from None
        raise
    finally:
        temporary.unlink(missing_ok=True)


def write_text_atomic(path: str | os.PathLike[str], text: str, *, overwrite: bool = True) -> None:
    """Write a text file atomically (see :func:`atomic_output`)."""
    with atomic_output(path, overwrite=overwrite) as temporary:
        temporary.write_text(text, encoding="utf-8")
