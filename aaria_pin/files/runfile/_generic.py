"""The HDF5 layout of a generic run file (a :class:`~aaria_pin.core.record.GenericRunRecord`).

Datasets at the root, float64: ``signals`` (T × C, attribute ``columns``), ``q``, ``qd``,
``qdd``, ``tau`` (T × n, attribute ``joint_names``), ``base_pose`` and ``tool_pose``
(T × 4 × 4), ``base_wrench`` (T × 6), ``imu_mount`` (S × 4 × 4, attributes ``imu_names`` and
``imu_parents``), and when the run was made from tables ``joint_table`` (n × 5) and
``base_table``; ``urdf`` is a UTF-8 string dataset holding the robot's URDF. Every numeric dataset
has a ``units`` attribute. The root carries ``format = "aaria_pin generic run"``,
``format_version = 1`` and the record's attributes, encoded as in an Aaria run file.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.record import GenericRunRecord, ImuMount
from aaria_pin.core.se3 import Array
from aaria_pin.errors import InputFileError, OutputFileError
from aaria_pin.files.runfile._attributes import _check_format, _encode_attributes, _reason
from aaria_pin.files.runfile._hdf5 import _hdf5_attributes, _hdf5_errors

GENERIC_FORMAT = "aaria_pin generic run"
"""Value of the ``format`` attribute that marks a generic run file."""
GENERIC_FORMAT_VERSION = 1

_UNITS = {
    "signals": "see columns: s, rad or m, rad/s, m/s^2",
    "q": "rad or m",
    "qd": "rad/s or m/s",
    "qdd": "rad/s^2 or m/s^2",
    "tau": "N*m or N",
    "base_pose": "m",
    "base_wrench": "N, N*m (world-aligned axes, about the base origin)",
    "tool_pose": "m",
    "imu_mount": "m",
    "joint_table": "columns: amplitude rad, prismatic amplitude m, bias rad or m, "
    "frequency rad/s, phase rad",
    "base_table": "columns: amplitude m or rad, bias m or rad, frequency rad/s, phase rad",
}
_SERIES = ("signals", "q", "qd", "qdd", "tau", "base_pose", "base_wrench", "tool_pose")


def write_generic_hdf5(temporary: Path, final: Path, record: GenericRunRecord) -> None:
    """Write a generic run record to ``temporary`` (renamed onto ``final`` by the caller)."""
    import h5py

    attributes = _encode_attributes(final, record.attributes)
    arrays: dict[str, Any] = {name: getattr(record, name) for name in _SERIES}
    arrays["imu_mount"] = np.array(
        [mount.T_parent_imu for mount in record.imu_mounts], dtype=float
    ).reshape(-1, 4, 4)
    for name in ("joint_table", "base_table"):
        if getattr(record, name) is not None:
            arrays[name] = getattr(record, name)
    strings = h5py.string_dtype("utf-8")
    try:
        with h5py.File(temporary, "w", track_order=True) as handle:
            handle.attrs["format"] = GENERIC_FORMAT
            handle.attrs["format_version"] = GENERIC_FORMAT_VERSION
            for key, value in attributes:
                handle.attrs[key] = value
            for name, data in arrays.items():
                dataset = handle.create_dataset(name, data=np.asarray(data, dtype=np.float64))
                dataset.attrs["units"] = _UNITS[name]
            handle["signals"].attrs.create("columns", list(record.columns), dtype=strings)
            for name in ("q", "qd", "qdd", "tau"):
                handle[name].attrs.create("joint_names", list(record.joint_names), dtype=strings)
            mounts = handle["imu_mount"]
            mounts.attrs.create("imu_names", [m.name for m in record.imu_mounts], dtype=strings)
            mounts.attrs.create("imu_parents", [m.parent for m in record.imu_mounts], dtype=strings)
            handle.create_dataset("urdf", data=record.urdf, dtype=strings)
    except (OSError, TypeError, ValueError) as exc:
        raise OutputFileError(f"{final}: cannot be written ({_reason(exc)})") from None


def is_generic_hdf5(file: Path) -> bool:
    """Whether an HDF5 file is marked as a generic run file."""
    import h5py

    try:
        with h5py.File(file, "r") as handle:
            fmt = handle.attrs.get("format")
    except OSError:
        return False
    if isinstance(fmt, bytes):
        fmt = fmt.decode("utf-8", errors="replace")
    return bool(fmt == GENERIC_FORMAT)


def _strings_attribute(item: Any, name: str) -> list[str]:
    """A string-list attribute of an HDF5 object (empty if absent)."""
    values = np.atleast_1d(item.attrs.get(name, []))
    return [v.decode("utf-8") if isinstance(v, bytes) else str(v) for v in values]


def summarise_generic_hdf5(file: Path) -> dict[str, Any]:
    """Shapes, names and attributes of a generic run file, without reading its arrays.

    Returns:
        ``arrays`` (name → shape), ``columns``, ``joints``, ``imus`` and ``attributes``.

    Raises:
        InputFileError: not a generic run file, a newer version, or unreadable.
    """
    import h5py

    with _hdf5_errors(file), h5py.File(file, "r") as handle:
        _check_generic(file, handle)
        return {
            "arrays": {name: tuple(handle[name].shape) for name in (*_SERIES, "imu_mount")},
            "columns": _strings_attribute(handle["signals"], "columns"),
            "joints": _strings_attribute(handle["q"], "joint_names"),
            "imus": _strings_attribute(handle["imu_mount"], "imu_names"),
            "attributes": _hdf5_attributes(file, handle.attrs),
        }


def _check_generic(file: Path, handle: Any) -> None:
    """Refuse a file that is not a generic run file of a known version, or lacks a dataset."""
    _check_format(
        file,
        handle.attrs.get("format"),
        handle.attrs.get("format_version"),
        GENERIC_FORMAT,
        GENERIC_FORMAT_VERSION,
    )
    missing = [n for n in (*_SERIES, "imu_mount", "urdf") if n not in handle]
    if missing:
        raise InputFileError(f"{file}: generic run file without {', '.join(missing)}")


def read_generic_hdf5(file: Path) -> GenericRunRecord:
    """Read a generic run file written by :func:`write_generic_hdf5`.

    Raises:
        InputFileError: not a generic run file, a newer version, or a missing or ill-shaped
            dataset.
    """
    import h5py

    with _hdf5_errors(file), h5py.File(file, "r") as handle:
        _check_generic(file, handle)
        arrays: dict[str, Array] = {
            name: np.asarray(handle[name][()], dtype=float) for name in _SERIES
        }
        tables = {
            name: np.asarray(handle[name][()], dtype=float) if name in handle else None
            for name in ("joint_table", "base_table")
        }
        mounts_ds = handle["imu_mount"]
        mounts = tuple(
            ImuMount(name, parent, pose)
            for name, parent, pose in zip(
                _strings_attribute(mounts_ds, "imu_names"),
                _strings_attribute(mounts_ds, "imu_parents"),
                np.asarray(mounts_ds[()], dtype=float).reshape(-1, 4, 4),
                strict=True,
            )
        )
        joint_names = tuple(_strings_attribute(handle["q"], "joint_names"))
        urdf = handle["urdf"].asstr()[()]
        attributes = _hdf5_attributes(file, handle.attrs)
    try:
        return GenericRunRecord(
            **arrays,
            joint_names=joint_names,
            imu_mounts=mounts,
            urdf=urdf,
            joint_table=tables["joint_table"],
            base_table=tables["base_table"],
            attributes=attributes,
        )
    except ValueError as exc:  # ParameterError from the record's shape check
        raise InputFileError(f"{file}: {exc}") from None
