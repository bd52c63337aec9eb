"""Checking a whole file: every complete run of a data set, or a run file, read and verified.

:func:`check_file` is ``aaria check FILE``: it reads what a command would read and keeps
what is wrong instead of stopping at the first damage.

- A data set: its header and layout (:class:`~aaria_pin.files.dataset.reader.DatasetReader`),
  then every complete run, each stored array read whole, checked finite and compared with its
  checksum (:meth:`~aaria_pin.files.dataset.reader.DatasetReader.check_run`). Runs not
  complete are not read (a resumed job makes them). A format version 1 data set records no
  checksums of its numbers: its runs are read and checked finite only (a note says so).
- A run file: :func:`~aaria_pin.files.source.open_record`, which reads and checks it whole.

Example::

    from aaria_pin.apps.check import check_file

    result = check_file("ds.h5")
    if not result.ok:
        for run, why in result.damaged.items():
            print(run, why)
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

__all__ = ["FileCheck", "check_file"]


@dataclass(frozen=True)
class FileCheck:
    """What :func:`check_file` found.

    Attributes:
        path: the file
        kind: ``"dataset"`` or ``"run"``
        runs: runs in the file (N of a data set; 1 for a run file)
        checked: runs read and checked (a data set's complete runs)
        damaged: what is wrong, one line each, by run (None: the file as a whole: a header,
            an array missing, a run file that does not read)
        notes: what could not be checked (a file without checksums)
    """

    path: Path
    kind: str
    runs: int
    checked: int
    damaged: dict[int | None, str] = field(default_factory=dict)
    notes: tuple[str, ...] = ()

    @property
    def ok(self) -> bool:
        """Whether nothing is damaged."""
        return not self.damaged

    def report(self) -> str:
        """The text ``aaria check`` prints: a summary line, notes, then one line per damage."""
        what = "data set" if self.kind == "dataset" else "run file"
        runs = f", {self.checked} of {self.runs} runs complete" if self.kind == "dataset" else ""
        state = "all intact" if self.ok else f"{len(self.damaged)} damaged"
        head = f"{self.path}: {what}: damaged" if None in self.damaged else f"{self.path}: "
        head += "" if None in self.damaged else f"{what}{runs}: {state}"
        notes = [f"note: {note}" for note in self.notes]
        return "\n".join([head, *notes, *self.damaged.values()])

    def to_json(self) -> dict[str, Any]:
        """A JSON-ready dict: the fields, ``damaged`` as a list of ``{run, error}``, ``ok``."""
        return {
            "path": str(self.path),
            "kind": self.kind,
            "runs": self.runs,
            "checked": self.checked,
            "ok": self.ok,
            "damaged": [{"run": run, "error": why} for run, why in self.damaged.items()],
            "notes": list(self.notes),
        }


def check_file(path: str | os.PathLike[str]) -> FileCheck:
    """Verify a whole run file or data set and list what is damaged.

    Args:
        path: a run file (``.h5``, ``.hdf5``, ``.mat``) or a data set (``.h5``)

    Returns:
        What was checked and what is damaged (:attr:`FileCheck.ok`: nothing).

    Raises:
        InputFileError: a missing file, another suffix, a file HDF5 cannot open at all, or
            one without the marks of a run file or data set (nothing to check;
            ``parameter="file"``).
    """
    from aaria_pin.files.detection import file_format

    file = Path(path)
    if file_format(file) == "dataset":
        return _check_dataset(file)
    return _check_run_file(file)


def _check_dataset(file: Path) -> FileCheck:
    """Every complete run of a data set, each checked whole (see the module docstring)."""
    import numpy as np

    from aaria_pin.core.record_checks import check_attributes, check_kind
    from aaria_pin.errors import InputFileError
    from aaria_pin.files.dataset.reader import DatasetReader

    try:
        reader = DatasetReader(file)
    except InputFileError as exc:
        return FileCheck(file, "dataset", 0, 0, {None: str(exc)})
    damaged: dict[int | None, str] = {}
    with reader:
        complete = [int(run) for run in np.flatnonzero(reader.complete)]
        try:  # the attributes every run shares (kind, rate, ...), as a command checks them
            if reader.layout is not None:  # version 1 (0.1) stores them in its own forms
                check_attributes(reader.attributes, str(file))
                check_kind(reader.attributes, str(file))
        except InputFileError as exc:
            return FileCheck(file, "dataset", len(reader), len(complete), {None: str(exc)})
        for run in complete:
            try:
                reader.check_run(run)
            except InputFileError as exc:
                damaged[run] = str(exc)
        notes = () if reader.verifiable else (_UNVERIFIABLE,)
        return FileCheck(file, "dataset", len(reader), len(complete), damaged, notes)


_UNVERIFIABLE = (
    "format version 1 (aaria_pin 0.1): no checksums of the numbers; runs read and checked "
    "for finite numbers only"
)


def _check_run_file(file: Path) -> FileCheck:
    """A run file read whole (:func:`~aaria_pin.files.source.open_record`)."""
    from aaria_pin.errors import InputFileError
    from aaria_pin.files._stored import DamagedFileError
    from aaria_pin.files.runfile import is_recorded_file, is_run_file, read_recorded_run
    from aaria_pin.files.source import open_record

    try:
        read_recorded_run(file) if is_recorded_file(file) else open_record(file)
    except InputFileError as exc:
        damaged = isinstance(exc, DamagedFileError)  # a .mat whose bytes do not inflate too
        if not damaged and not is_run_file(file):  # not an aaria_pin file: nothing to check
            raise
        return FileCheck(file, "run", 1, 1, {None: str(exc)})
    return FileCheck(file, "run", 1, 1)
