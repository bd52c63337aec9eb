"""A data set's summary: runs, shapes, sizes, seed, config (what ``aaria info`` prints)."""

from __future__ import annotations

import os
from typing import Any

from aaria_pin.files.dataset.manifest import shard_files
from aaria_pin.files.dataset.reader import DatasetReader

__all__ = ["dataset_summary", "reader_summary"]


def dataset_summary(path: str | os.PathLike[str]) -> dict[str, Any]:
    """The summary of a data set file (:func:`reader_summary` of the file opened once).

    Raises:
        InputFileError: as :class:`~aaria_pin.files.dataset.reader.DatasetReader`.
    """
    with DatasetReader(path) as reader:
        return reader_summary(reader)


def reader_summary(reader: DatasetReader) -> dict[str, Any]:
    """Runs, shapes, sizes, seed, config and completeness of a data set (for ``aaria info``).

    Returns:
        ``path``, ``format_version``, ``kind`` (``"dh"`` or ``"urdf"``), ``runs``,
        ``complete``, ``failed``, ``samples``, ``dtype``, ``seed``, ``vary``, ``rate``,
        ``duration``, ``noise``, ``arrays`` (stored name → shape), ``views`` (name → shape),
        ``file_bytes`` (with its shards), ``shards`` (how many files), ``data_bytes`` (the stored
        arrays uncompressed), ``config``, and for a
        URDF robot ``robot`` (its name, source, frames, joint and IMU names, base mode).
    """
    handle = reader.handle
    header = reader.header
    stored = reader.stored_names
    views = tuple(reader.layout.views) if reader.layout is not None else ()
    shards = shard_files(handle, reader.path) if reader.layout is not None else []
    robot = header.robot_info
    return {
        "path": str(reader.path),
        "format_version": reader.version,
        "kind": header.kind,
        "runs": len(reader),
        "complete": int(reader.complete.sum()),
        "failed": sorted(header.failures),
        "samples": reader.samples,
        "dtype": header.dtype,
        "seed": header.seed,
        "vary": header.vary,
        "rate": header.rate,
        "duration": header.duration,
        "noise": header.noise,
        "arrays": {name: list(handle[name].shape) for name in stored},
        "views": {name: list(handle[name].shape) for name in views},
        "file_bytes": reader.path.stat().st_size
        + sum(p.stat().st_size for p in shards if p.is_file()),
        "shards": len(shards),
        "data_bytes": int(sum(handle[name].size * handle[name].dtype.itemsize for name in stored)),
        "config": header.config,
        **({"robot": robot} if robot else {}),
    }
