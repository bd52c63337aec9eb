"""The predictions file of a benchmark task: an NPZ archive, one array per test run.

Format (``numpy.savez``, read with ``allow_pickle=False``): for each run ``k`` of the task's
test split (the data set's run index, listed in the card's ``splits.test``) one array named
``run_<k>`` (``run_7``), of the target's shape for one run (``structure``: ``8 × 5``, an
extended DH table; ``inverse-dynamics``: ``T × 6`` torques; ``sensor-to-state``: ``T × 6``
joint values; ``T`` the samples per run), any real number type, every value finite. Nothing
else is in the archive: a missing or an extra array, another shape or a value that is not
finite is refused (one line naming the file), never scored.
"""

from __future__ import annotations

import os
import zipfile
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.errors import InputFileError, OutputFileError

__all__ = ["read_predictions", "run_key", "write_predictions"]


def run_key(run: int) -> str:
    """The name of run ``run``'s array in a predictions file (``run_7``)."""
    return f"run_{int(run)}"


def write_predictions(path: str | os.PathLike[str], predictions: Mapping[int, np.ndarray]) -> None:
    """Write predictions (run index → array) as a predictions file, atomically.

    Raises:
        OutputFileError: the file cannot be written.
    """
    from aaria_pin.files.paths import atomic_output

    if Path(path).suffix.lower() != ".npz":
        raise OutputFileError(
            f"{path} is not an .npz file; allowed: a predictions file ending in .npz",
            parameter="path",
            value=str(path),
        )
    arrays: dict[str, Any] = {run_key(run): np.asarray(a) for run, a in sorted(predictions.items())}
    with atomic_output(path) as temporary, open(temporary, "wb") as stream:
        np.savez(stream, **arrays)


def _refused(path: object, what: str, allowed: str) -> InputFileError:
    return InputFileError(f"{path}: {what}; allowed: {allowed}", parameter="file", value=str(path))


def read_predictions(
    path: str | os.PathLike[str], runs: Sequence[int], shape: tuple[int, ...]
) -> dict[int, np.ndarray]:
    """The predictions of some runs from a predictions file, checked (see the module docstring).

    Args:
        path: the ``.npz`` file
        runs: the runs it must predict, no other
        shape: the shape of each run's array

    Returns:
        Run index → its prediction (float64).

    Raises:
        InputFileError: not a readable NPZ file, a missing or extra array, another shape, a
            value that is not a finite real number.
    """
    from aaria_pin.files.paths import existing_input

    file = existing_input(path, (".npz",), "predictions")
    try:
        with np.load(file, allow_pickle=False) as archive:
            arrays = {name: archive[name] for name in archive.files}
    except (OSError, ValueError, zipfile.BadZipFile) as exc:
        raise _refused(file, f"cannot be read as NPZ ({exc})", "a numpy.savez file") from None
    wanted = [run_key(run) for run in runs]
    missing = [name for name in wanted if name not in arrays]
    if missing:
        raise _refused(file, f"has no array {missing[0]}", f"one array per test run: {wanted}")
    extra = sorted(set(arrays) - set(wanted))
    if extra:
        raise _refused(file, f"has an extra array {extra[0]}", f"only the test runs: {wanted}")
    result: dict[int, np.ndarray] = {}
    for run, name in zip(runs, wanted, strict=True):
        array = arrays[name]
        if array.shape != tuple(shape):
            raise _refused(file, f"{name} has shape {array.shape}", f"shape {tuple(shape)}")
        if not (np.issubdtype(array.dtype, np.integer) or np.issubdtype(array.dtype, np.floating)):
            raise _refused(file, f"{name} is of type {array.dtype}", "real numbers")
        values = array.astype(np.float64)
        if not np.isfinite(values).all():
            index = np.unravel_index(int(np.argmin(np.isfinite(values))), values.shape)
            at = tuple(int(i) for i in index)
            raise _refused(file, f"{name}{list(at)} is {values[at]}", "finite numbers")
        result[int(run)] = values
    return result
