"""Reading a data set without loading it: one run as a record, raw arrays, windows.

Example::

    from aaria_pin.files.dataset_reader import DatasetReader

    with DatasetReader("ds.h5") as ds:
        print(len(ds), ds.samples, ds.attributes["seed"])
        record = ds.record(3)                     # a RunRecord: record.imu, record.view("senSen")
        arrays = ds.run(3, ("senSen", "tau"))     # stored arrays (and views) as stored
        for run_index, start, window in ds.windows(200, stride=100, names=("senSen", "tau")):
            ...                                   # window["senSen"]: (200, 91)

Data sets of both format versions read: version 2 (one layout for every robot, views as HDF5
virtual datasets) and version 1, written by aaria_pin 0.1 (:mod:`.legacy`). Only complete runs
are read; each run is one chunk (a few for poses) on disk, so a window costs one run's read.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.record import RunRecord, mounts_from_poses
from aaria_pin.core.se3 import Array
from aaria_pin.errors import InputFileError, ParameterError
from aaria_pin.files._stored import decode_attributes
from aaria_pin.files.dataset.layout import (
    DATASET_FORMAT,
    DATASET_FORMAT_VERSION,
    DatasetLayout,
    record_attributes,
)
from aaria_pin.files.dataset.legacy import LEGACY_VERSION, legacy_names, legacy_record
from aaria_pin.files.dataset.store import read_layout

__all__ = ["DatasetReader", "dataset_summary"]

_NOISE_STREAM = 3
"""The noise stream of a run when the file records none (as the engine draws it)."""


class DatasetReader:
    """A data set file opened for reading.

    Args:
        path: the data set's ``.h5`` file (format version 1 or 2)

    Attributes:
        path: the file
        version: its format version
        complete: which runs are complete (N booleans)
        names: what :meth:`run` reads, in file order: the stored per-run arrays, then (version
            2) the views
        layout: the fixed per-run layout (version 2; None for version 1)

    Raises:
        InputFileError: missing, unreadable, not a data set, or of an unknown version.
    """

    def __init__(self, path: str | os.PathLike[str]) -> None:
        import h5py

        self.path = Path(path)
        try:
            self._handle = h5py.File(self.path, "r")
        except OSError as exc:
            raise InputFileError(f"{self.path}: cannot be read as a data set ({exc})") from None
        attrs = self._handle.attrs
        if attrs.get("format") != DATASET_FORMAT:
            self._handle.close()
            raise InputFileError(f"{self.path}: not an aaria_pin data set")
        self.version = int(attrs.get("format_version", LEGACY_VERSION))
        if self.version not in (LEGACY_VERSION, DATASET_FORMAT_VERSION):
            self._handle.close()
            raise InputFileError(
                f"{self.path}: data set format version is {self.version}; allowed: "
                f"{LEGACY_VERSION}, {DATASET_FORMAT_VERSION} (a newer aaria_pin wrote it)"
            )
        self.complete = self._handle["complete"][()].astype(bool)
        self.layout: DatasetLayout | None = None
        if self.version == LEGACY_VERSION:
            self.names: tuple[str, ...] = legacy_names(self._handle)
        else:
            self.layout = read_layout(self._handle)
            self.names = (*self.layout.names, *self.layout.views)

    def __len__(self) -> int:
        return int(self._handle.attrs["N"])

    @property
    def samples(self) -> int:
        """Samples per run T."""
        return int(self._handle.attrs["samples"])

    @property
    def attributes(self) -> dict[str, Any]:
        """File attributes, JSON ones decoded (keys without the ``_json`` suffix)."""
        return decode_attributes(self._handle.attrs, self.path)

    @property
    def stored_names(self) -> tuple[str, ...]:
        """The arrays stored per run (the views apart), in file order."""
        return self.layout.names if self.layout is not None else self.names

    def _check_run(self, index: int) -> None:
        if not 0 <= index < len(self):
            raise ParameterError(f"run {index}; allowed: 0 to {len(self) - 1}")
        if not self.complete[index]:
            raise ParameterError(f"run {index} is not complete in {self.path}")

    def run(self, index: int, names: Sequence[str] | None = None) -> dict[str, Array]:
        """Arrays of one complete run as stored (by default every stored array, in file order).

        Args:
            index: the run
            names: arrays or views to read (see :attr:`names`)

        Raises:
            ParameterError: index out of range, a run that is not complete, or an unknown name.
        """
        self._check_run(index)
        names = self.stored_names if names is None else names
        unknown = [name for name in names if name not in self.names]
        if unknown:
            raise ParameterError(f"array {unknown[0]!r}; allowed: {', '.join(self.names)}")
        return {name: self._handle[name][index] for name in names}

    def record(self, index: int) -> RunRecord:
        """Run ``index`` as a run record (arrays in float64), whatever the format version.

        Its attributes are those of a single run: ``kind``, ``robot``, rate, duration, noise
        settings, the run's noise seed (``seed`` and ``noise_spawn_key``) and ``run``.

        Raises:
            ParameterError: index out of range, or a run that is not complete.
        """
        self._check_run(index)
        attributes = self.attributes
        if self.layout is None:
            return legacy_record(self._handle, index, attributes)
        layout = self.layout
        arrays = {name: np.asarray(self._handle[name][index], dtype=float) for name in layout.names}
        mounts = mounts_from_poses(layout.imu_names, layout.imu_parents, arrays["imu_mount"])
        return RunRecord(
            time=arrays["time"],
            joint_names=layout.joint_names,
            q=arrays["q"],
            qd=arrays["qd"],
            qdd=arrays["qdd"],
            tau=arrays["tau"],
            base_pose=arrays["base_pose"],
            base_wrench=arrays["base_wrench"],
            tool_pose=arrays["tool_pose"],
            imu=arrays["imu"],
            imu_mounts=mounts,
            urdf=layout.urdf,
            tables={name: arrays[name] for name in layout.tables},
            views=dict(layout.views),
            attributes=record_attributes(
                attributes, index, int(attributes.get("noise_stream", _NOISE_STREAM))
            ),
        )

    def windows(
        self, length: int, stride: int | None = None, names: Sequence[str] | None = None
    ) -> Iterator[tuple[int, int, dict[str, Array]]]:
        """Fixed-length windows over every complete run, run by run.

        Args:
            length: samples per window
            stride: samples between window starts (default ``length``: no overlap)
            names: time-series arrays or views to cut (``senSen``, ``signals``, ``q``, ``tau``,
                ...; default the first view, ``senSen`` or ``signals``)

        Yields:
            ``(run index, first sample, {name: (length, ...) array})``.
        """
        stride = stride or length
        if names is None:
            first = next(iter(self.layout.views)) if self.layout is not None else self.names[0]
            names = (first,)
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
    """Runs, shapes, sizes, seed, config and completeness of a data set (for ``aaria info``).

    Returns:
        ``path``, ``format_version``, ``kind`` (``"dh"`` or ``"urdf"``), ``runs``,
        ``complete``, ``failed``, ``samples``, ``dtype``, ``seed``, ``vary``, ``rate``,
        ``duration``, ``noise``, ``arrays`` (stored name → shape), ``views`` (name → shape),
        ``file_bytes``, ``data_bytes`` (the stored arrays uncompressed), ``config``, and for a
        URDF robot ``robot`` (its name, source, frames, joint and IMU names, base mode).
    """
    with DatasetReader(path) as reader:
        handle = reader._handle
        attributes = reader.attributes
        stored = reader.stored_names
        views = tuple(reader.layout.views) if reader.layout is not None else ()
        robot = attributes.get("robot_info") if reader.layout is not None else None
        if reader.layout is None and isinstance(attributes.get("robot"), dict):
            robot = attributes["robot"]
        kind = attributes.get("kind") or ("urdf" if robot else "dh")
        return {
            "path": str(reader.path),
            "format_version": reader.version,
            "kind": kind,
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
            "arrays": {name: list(handle[name].shape) for name in stored},
            "views": {name: list(handle[name].shape) for name in views},
            "file_bytes": reader.path.stat().st_size,
            "data_bytes": int(
                sum(handle[name].size * handle[name].dtype.itemsize for name in stored)
            ),
            "config": attributes.get("config"),
            **({"robot": robot} if robot else {}),
        }
