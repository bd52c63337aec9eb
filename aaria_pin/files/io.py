"""Reading tables from files and writing outputs atomically.

Tables come as CSV (comma separated, ``#`` comments, no header), ``.npy``, or MATLAB ``.mat``
holding a named array (the paper's ``senSenDH``, ``senSenJ``, ``senSenB``). Every output is
written to a temporary file beside its destination and renamed when complete, so a failure
never leaves a partial file behind.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
import warnings
from collections.abc import Iterator, Sequence
from pathlib import Path

import numpy as np

from aaria_pin.core.se3 import Array
from aaria_pin.errors import InputFileError, OutputFileError

__all__ = ["atomic_output", "existing_input", "read_table", "write_text_atomic"]

_TABLE_SUFFIXES = (".csv", ".txt", ".npy", ".mat")


def existing_input(path: str | os.PathLike[str], suffixes: Sequence[str], kind: str) -> Path:
    """The path of an existing input file whose suffix is one of ``suffixes``.

    Args:
        path: the file
        suffixes: the allowed suffixes, lower case with the dot (``(".h5", ".mat")``)
        kind: what the file holds, for the message (``"table"``, ``"run"``)

    Raises:
        InputFileError: another suffix (checked first), or no such file.
    """
    file = Path(path)
    suffix = file.suffix.lower()
    if suffix not in suffixes:
        raise InputFileError(
            f"{file}: unknown {kind} file type {suffix!r}; allowed: {', '.join(suffixes)}"
        )
    if not file.is_file():
        raise InputFileError(f"{file}: no such file")
    return file


def read_table(path: str | os.PathLike[str], mat_name: str = "senSenDH") -> Array:
    """Read a 2-D numeric table from a CSV, ``.npy`` or ``.mat`` file.

    Args:
        path: the file
        mat_name: name of the array to take from a ``.mat`` file

    Returns:
        The table as a 2-D float array (shape is checked by the table's validator).

    Raises:
        InputFileError: the file is missing, unreadable, of an unknown kind, or not numeric.
    """
    file = existing_input(path, _TABLE_SUFFIXES, "table")
    suffix = file.suffix.lower()
    try:
        if suffix == ".npy":
            data = np.load(file, allow_pickle=False)
        elif suffix == ".mat":
            data = _read_mat_array(file, mat_name)
        else:
            with warnings.catch_warnings():
                warnings.simplefilter("error")  # an empty file is an error, not a warning
                data = np.loadtxt(file, delimiter=",", comments="#", ndmin=2)
        if np.iscomplexobj(data):
            raise InputFileError(f"{file}: holds complex numbers; allowed: a real table")
        table = np.asarray(data, dtype=float)
    except InputFileError:
        raise
    except UserWarning:
        raise InputFileError(f"{file}: is empty; allowed: a numeric table") from None
    except (OSError, ValueError, TypeError) as exc:
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise InputFileError(f"{file}: cannot be read as a numeric table ({reason})") from None
    if table.ndim == 1:
        table = table.reshape(1, -1)
    if table.ndim != 2:
        raise InputFileError(f"{file}: holds a {table.ndim}-D array; expected a 2-D table")
    return table


def _read_mat_array(file: Path, name: str) -> Array:
    """One array of a MATLAB file: v4–v7 through scipy, v7.3 (HDF5) through h5py."""
    from scipy.io import loadmat
    from scipy.io.matlab import MatReadError

    try:
        contents = loadmat(file)
    except NotImplementedError:  # a v7.3 file is HDF5, stored column-major
        import h5py

        with h5py.File(file, "r") as handle:
            if name not in handle:
                raise InputFileError(
                    f"{file}: no array {name!r} in the .mat file; has {sorted(handle)}"
                ) from None
            return np.asarray(handle[name][()], dtype=float).T
    except MatReadError as exc:
        raise ValueError(str(exc)) from None
    if name not in contents:
        names = sorted(k for k in contents if not k.startswith("__"))
        raise InputFileError(f"{file}: no array {name!r} in the .mat file; has {names}")
    return np.asarray(contents[name], dtype=float)


@contextlib.contextmanager
def atomic_output(path: str | os.PathLike[str]) -> Iterator[Path]:
    """Give a temporary path beside ``path``; rename it onto ``path`` when the block succeeds.

    On any exception the temporary file is removed and ``path`` is left as it was.

    Args:
        path: the final output file

    Yields:
        The temporary file to write (same folder and suffix as ``path``).

    Raises:
        OutputFileError: the destination folder does not exist or is not writable.
    """
    final = Path(path)
    folder = final.parent if str(final.parent) else Path(".")
    if not folder.is_dir():
        raise OutputFileError(f"{final}: folder {folder} does not exist")
    if final.is_dir():
        raise OutputFileError(f"{final}: is a folder; expected a file path")
    try:
        handle, name = tempfile.mkstemp(prefix=f".{final.name}.", suffix=final.suffix, dir=folder)
    except OSError as exc:
        raise OutputFileError(f"{final}: cannot write in {folder} ({exc.strerror})") from None
    os.close(handle)
    temporary = Path(name)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(temporary, 0o666 & ~umask)  # as a plain open() would have made it
    try:
        yield temporary
        os.replace(temporary, final)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def write_text_atomic(path: str | os.PathLike[str], text: str) -> None:
    """Write a text file atomically (see :func:`atomic_output`)."""
    with atomic_output(path) as temporary:
        temporary.write_text(text, encoding="utf-8")
