"""Checking what is read of a data set's run: readable, finite, and the numbers it was written with.

Every read of run K (:class:`~.reader.DatasetReader`'s ``run``, ``record``, ``windows`` and
``statistics``) goes through a :class:`RunCheck`:

- an h5py/HDF5 error while reading (a damaged chunk: "filter returned failure during read")
  becomes "run K of FILE is damaged (…)", an :class:`~aaria_pin.errors.InputFileError`;
- a NaN or an infinity in a stored array is refused with the array, the run and the first index
  (the simulator never writes one);
- each stored array of the run is compared, once per check object (per reader, per process of a
  window dataset), with the CRC-32 its writer recorded in ``checksum``: the CRC-32 of its chunks'
  bytes before deflate (:func:`~.layout.array_checksum`), computed from the numbers read, so a
  manifest's virtual datasets are checked as a file's own. A data set of an early 0.2, which
  recorded the CRC-32 of the deflated bytes, is checked against those (read again raw).

Format version 1 data sets (aaria_pin 0.1) record no checksum of the numbers: they are read
and checked for finiteness only (:attr:`RunCheck.verifiable` is False).
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.record_checks import check_finite
from aaria_pin.errors import InputFileError
from aaria_pin.files._stored import HDF5_READ_ERRORS, first_line, require_arrays
from aaria_pin.files.dataset.layout import array_checksum

__all__ = [
    "READ_ERRORS",
    "RunCheck",
    "check_arrays",
    "check_flags",
    "damaged_run",
    "run_check",
]

READ_ERRORS = HDF5_READ_ERRORS
"""What h5py raises on a damaged file: a chunk that does not inflate (OSError), a broken index
or a missing source."""


def damaged_run(path: str | os.PathLike[str], run: int, why: str) -> InputFileError:
    """The one-line error of a damaged run ("run K of FILE is damaged (why)")."""
    return InputFileError(
        f"run {run} of {path} is damaged ({' '.join(why.split())}); allowed: an intact run "
        "(aaria check lists the damaged runs; aaria dataset --resume makes them again)",
        parameter="file",
        value=str(path),
    )


@dataclass
class RunCheck:
    """How the runs of one data set are checked as they are read (picklable: a few numbers).

    Args:
        path: the data set, for messages
        n_runs: its runs N
        columns: each stored array's column of ``checksum`` (empty: nothing to verify)
        chunks: each stored array's chunk of one run (how its checksum was computed)
    """

    path: Path
    n_runs: int
    columns: Mapping[str, int] = field(default_factory=dict)
    chunks: Mapping[str, tuple[int, ...]] = field(default_factory=dict)
    _checked: dict[str, np.ndarray] = field(default_factory=dict, repr=False)

    def is_checked(self, name: str, run: int) -> bool:
        """Whether array ``name`` of run ``run`` was read whole and checked already."""
        done = self._checked.get(name)
        return done is not None and bool(done[run])

    def _mark(self, name: str, run: int) -> None:
        done = self._checked.get(name)
        if done is None:
            done = self._checked[name] = np.zeros(self.n_runs, dtype=bool)
        done[run] = True

    @property
    def verifiable(self) -> bool:
        """Whether the file records checksums of its runs' numbers."""
        return bool(self.columns)

    def read(self, source: Any, name: str, run: int, where: Any = None) -> np.ndarray:
        """Array ``name`` of run ``run`` (``where``: a slice of its samples), its errors ours.

        Args:
            source: the open file, or its dataset ``name`` (looked up once by the caller)
            name: the array
            run: the run
            where: a slice of its samples (None: the whole array)

        Raises:
            InputFileError: h5py cannot read it (the run is damaged).
        """
        try:
            dataset = source[name] if hasattr(source, "keys") else source
            return np.asarray(dataset[run] if where is None else dataset[run, where])
        except READ_ERRORS as exc:
            raise damaged_run(self.path, run, f"{name}: {first_line(exc)}") from None

    def finite(self, name: str, run: int, array: np.ndarray) -> None:
        """Refuse a NaN or an infinity in a run's whole array, naming the array, run and index.

        Raises:
            InputFileError: not finite (:func:`~aaria_pin.core.record_checks.check_finite`:
                ``"run K of FILE: tau has NaN at sample 5, joint 2; allowed: finite values"``).
        """
        check_finite({name: array}, f"run {run} of {self.path}")

    def verify(self, handle: Any, name: str, run: int, array: np.ndarray) -> None:
        """Compare a whole stored array of a run with its checksum.

        Raises:
            InputFileError: it differs (the run is damaged).
        """
        column = self.columns.get(name)
        if column is None:
            return
        try:
            recorded = int(handle["checksum"][run, column])
        except READ_ERRORS as exc:
            raise damaged_run(self.path, run, f"checksum: {first_line(exc)}") from None
        if array_checksum(array, self.chunks[name]) != recorded and not self._deflated_match(
            handle, name, run, recorded
        ):
            raise damaged_run(self.path, run, f"{name} differs from its checksum")

    def _deflated_match(self, handle: Any, name: str, run: int, recorded: int) -> bool:
        """Whether an early 0.2 file's checksum (of the deflated chunks) matches the array's."""
        from aaria_pin.files.dataset.layout import read_run_chunks

        dataset = handle[name]
        if dataset.is_virtual or dataset.chunks is None:
            return False
        try:
            _, _, stored = read_run_chunks(handle, [name], run)
        except READ_ERRORS:
            return False
        return stored == [recorded]

    def checked(self, handle: Any, name: str, run: int, dataset: Any = None) -> np.ndarray:
        """A whole stored array of a run, read, finite and verified (then noted as checked).

        Args:
            handle: the open file
            name: the array
            run: the run
            dataset: its h5py dataset, if the caller holds it (else looked up)
        """
        array = self.read(handle if dataset is None else dataset, name, run)
        self.finite(name, run, array)
        self.verify(handle, name, run, array)
        self._mark(name, run)
        return array

    def verify_run(self, handle: Any, run: int, names: Any = None) -> None:
        """Read and check every stored array of a run (or ``names`` of them).

        Raises:
            InputFileError: the run is damaged or holds a NaN or an infinity.
        """
        for name in self.columns if names is None else names:
            if not self.is_checked(name, run):
                self.checked(handle, name, run)


def check_arrays(
    handle: Any, path: Path, n_runs: int, shapes: Mapping[str, tuple[int, ...] | None]
) -> None:
    """Refuse a data set missing a per-run array, or holding one of another shape.

    Args:
        handle: the open file
        path: the file, for messages
        n_runs: its runs N (every per-run array has N rows)
        shapes: each per-run array's shape of one run (None: any), ``complete`` added

    Raises:
        InputFileError: naming the first array missing or of the wrong shape.
    """
    require_arrays(handle, path, (*shapes, "complete", "failed"))
    for name, shape in {**shapes, "complete": ()}.items():
        if name not in handle:
            raise InputFileError(
                f"{path}: a damaged data set: no {name!r} array; allowed: a complete "
                "aaria_pin data set (make it again)",
                parameter="file",
                value=str(path),
            )
        stored = tuple(handle[name].shape or ())
        if stored[:1] != (n_runs,) or (shape is not None and stored[1:] != tuple(shape)):
            wanted = f"{n_runs} × …" if shape is None else " × ".join(map(str, (n_runs, *shape)))
            raise InputFileError(
                f"{path}: a damaged data set: array {name!r} has shape "
                f"{' × '.join(map(str, stored)) or 'scalar'}; allowed: {wanted} (N = {n_runs})",
                parameter="file",
                value=str(path),
            )
    check_flags(handle, path, n_runs)


def check_flags(handle: Any, path: Path, n_runs: int) -> None:
    """Refuse ``complete``/``failed`` other than N integers 0 or 1, a ``checksum`` not unsigned.

    Raises:
        InputFileError: naming the first such array (``parameter="file"``).
    """
    for name, allowed in (
        ("complete", f"{n_runs} integers 0 or 1"),
        ("failed", f"{n_runs} integers 0 or 1"),
        ("checksum", "unsigned integers (CRC-32)"),
    ):
        if name not in handle:
            continue
        dataset = handle[name]
        if name == "checksum":
            wrong = dataset.dtype.kind != "u"
        else:
            values = np.asarray(dataset[()])
            wrong = (
                values.shape != (n_runs,)
                or values.dtype.kind not in "biu"
                or not bool(np.isin(values, (0, 1)).all())
            )
        if wrong:
            raise InputFileError(
                f"{path}: a damaged data set: array {name!r} is not "
                f"{allowed}; allowed: {allowed} (make the data set again)",
                parameter="file",
                value=str(path),
            )


def run_check(handle: Any, path: Path, n_runs: int, layout: Any) -> RunCheck:
    """The check of an open data set's runs (``layout`` None: version 1, nothing to verify)."""
    if layout is None:
        return RunCheck(path, n_runs)
    return RunCheck(
        path,
        n_runs,
        {name: column for column, name in enumerate(layout.names)},
        {name: layout.chunk(name, handle[name].shape[1:]) for name in layout.names},
    )
