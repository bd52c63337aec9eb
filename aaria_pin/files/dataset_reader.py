"""Reading a data set without loading it: one run by index, or fixed-length windows for training.

Example::

    from aaria_pin.files.dataset_reader import DatasetReader

    with DatasetReader("ds.h5") as ds:
        print(len(ds), ds.samples, ds.attributes["seed"])
        run = ds.run(3)                                   # {"senSen": (T, 91), "tau": (T, 6), ...}
        for run_index, start, window in ds.windows(200, stride=100, names=("senSen", "tau")):
            ...                                           # window["senSen"]: (200, 91)

Only complete runs are read; each run is one chunk on disk, so a window costs one run's read.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.se3 import Array
from aaria_pin.errors import InputFileError, ParameterError
from aaria_pin.files.dataset_file import DATASET_FORMAT, decode_attributes, file_layout

__all__ = ["DatasetReader", "dataset_summary"]


class DatasetReader:
    """A data set file opened for reading.

    Args:
        path: the data set's ``.h5`` file

    Raises:
        InputFileError: missing, unreadable, or not a data set.
    """

    def __init__(self, path: str | os.PathLike[str]) -> None:
        import h5py

        self.path = Path(path)
        try:
            self._handle = h5py.File(self.path, "r")
        except OSError as exc:
            raise InputFileError(f"{self.path}: cannot be read as a data set ({exc})") from None
        if self._handle.attrs.get("format") != DATASET_FORMAT:
            self._handle.close()
            raise InputFileError(f"{self.path}: not an aaria_pin data set")
        self.complete = self._handle["complete"][()].astype(bool)
        self.names = file_layout(self._handle).names
        """Names of a run's arrays, in file order."""

    def __len__(self) -> int:
        return int(self._handle.attrs["N"])

    @property
    def samples(self) -> int:
        """Samples per run T."""
        return int(self._handle.attrs["samples"])

    @property
    def attributes(self) -> dict[str, Any]:
        """File attributes, JSON ones decoded (keys without the ``_json`` suffix)."""
        return decode_attributes(self._handle.attrs)

    def run(self, index: int, names: Sequence[str] | None = None) -> dict[str, Array]:
        """The arrays of one complete run (by default all of them, in file order).

        Raises:
            ParameterError: index out of range, a run that is not complete, or an unknown name.
        """
        if not 0 <= index < len(self):
            raise ParameterError(f"run {index}; allowed: 0 to {len(self) - 1}")
        if not self.complete[index]:
            raise ParameterError(f"run {index} is not complete in {self.path}")
        names = self.names if names is None else names
        unknown = [name for name in names if name not in self.names]
        if unknown:
            raise ParameterError(f"array {unknown[0]!r}; allowed: {', '.join(self.names)}")
        return {name: self._handle[name][index] for name in names}

    def windows(
        self, length: int, stride: int | None = None, names: Sequence[str] | None = None
    ) -> Iterator[tuple[int, int, dict[str, Array]]]:
        """Fixed-length windows over every complete run, run by run.

        Args:
            length: samples per window
            stride: samples between window starts (default ``length``: no overlap)
            names: time-series arrays to cut (``senSen``, ``q``, ``tau``, ...; default the
                first array, ``senSen`` or ``signals``)

        Yields:
            ``(run index, first sample, {name: (length, ...) array})``.
        """
        stride = stride or length
        names = self.names[:1] if names is None else names
        if not (1 <= length <= self.samples and stride >= 1):
            raise ParameterError(
                f"window length {length}, stride {stride}; allowed: 1 <= length <= {self.samples}"
                ", stride >= 1"
            )
        for index in np.flatnonzero(self.complete):
            run = self.run(int(index), names)
            for start in range(0, self.samples - length + 1, stride):
                yield int(index), start, {name: run[name][start : start + length] for name in names}

    def close(self) -> None:
        """Close the file."""
        self._handle.close()

    def __enter__(self) -> DatasetReader:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def dataset_summary(path: str | os.PathLike[str]) -> dict[str, Any]:
    """Runs, shapes, sizes, seed, config and completeness of a data set (for ``aaria info``)."""
    with DatasetReader(path) as reader:
        handle = reader._handle
        attributes = reader.attributes
        return {
            "path": str(reader.path),
            "runs": len(reader),
            "complete": int(reader.complete.sum()),
            "failed": sorted(int(k) for k in attributes.get("failures", {})),
            "samples": reader.samples,
            "dtype": attributes.get("dtype"),
            "seed": attributes.get("seed"),
            "vary": attributes.get("vary"),
            "rate": attributes.get("rate"),
            "duration": attributes.get("duration"),
            "noise": attributes.get("noise"),
            "arrays": {name: list(handle[name].shape) for name in reader.names},
            "file_bytes": reader.path.stat().st_size,
            "data_bytes": int(
                sum(handle[name].size * handle[name].dtype.itemsize for name in reader.names)
            ),
            "config": attributes.get("config"),
            **({"robot": attributes["robot"]} if "robot" in attributes else {}),
        }
