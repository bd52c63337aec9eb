"""The HDF5 layout of a generic run file (a :class:`~aaria_pin.generic_record.GenericRunRecord`).

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

from aaria_pin._se3 import Array
from aaria_pin.errors import InputFileError, OutputFileError
from aaria_pin.generic_record import GenericRunRecord, ImuMount
from aaria_pin.runfile._attributes import (
    _RESERVED_ATTRIBUTES,
    _decode_attribute,
    _encode_attributes,
    _reason,
)

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


def _strings(values: Any) -> list[str]:
    return [v.decode("utf-8") if isinstance(v, bytes) else str(v) for v in np.atleast_1d(values)]


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


def read_generic_hdf5(file: Path) -> GenericRunRecord:
    """Read a generic run file written by :func:`write_generic_hdf5`.

    Raises:
        InputFileError: not a generic run file, a newer version, or a missing or ill-shaped
            dataset.
    """
    import h5py

    try:
        with h5py.File(file, "r") as handle:
            fmt = handle.attrs.get("format")
            if isinstance(fmt, bytes):
                fmt = fmt.decode("utf-8", errors="replace")
            if fmt != GENERIC_FORMAT:
                raise InputFileError(
                    f"{file}: not a generic run file (format {fmt!r}; expected {GENERIC_FORMAT!r})"
                )
            version = int(handle.attrs.get("format_version", 0))
            if not 1 <= version <= GENERIC_FORMAT_VERSION:
                raise InputFileError(
                    f"{file}: format_version {version} is not supported; "
                    f"this aaria_pin reads 1 to {GENERIC_FORMAT_VERSION}"
                )
            missing = [n for n in (*_SERIES, "imu_mount", "urdf") if n not in handle]
            if missing:
                raise InputFileError(f"{file}: generic run file without {', '.join(missing)}")
            arrays: dict[str, Array] = {
                name: np.asarray(handle[name][()], dtype=float) for name in _SERIES
            }
            tables = {
                name: np.asarray(handle[name][()], dtype=float) if name in handle else None
                for name in ("joint_table", "base_table")
            }
            mounts_ds = handle["imu_mount"]
            poses = np.asarray(mounts_ds[()], dtype=float).reshape(-1, 4, 4)
            mounts = tuple(
                ImuMount(name, parent, pose)
                for name, parent, pose in zip(
                    _strings(mounts_ds.attrs.get("imu_names", [])),
                    _strings(mounts_ds.attrs.get("imu_parents", [])),
                    poses,
                    strict=True,
                )
            )
            joint_names = tuple(_strings(handle["q"].attrs.get("joint_names", [])))
            urdf = handle["urdf"][()]
            attributes: dict[str, Any] = {}
            for name in handle.attrs:
                if name not in _RESERVED_ATTRIBUTES:
                    key, value = _decode_attribute(file, name, handle.attrs[name])
                    attributes[key] = value
    except InputFileError:
        raise
    except (OSError, KeyError, TypeError, ValueError) as exc:
        raise InputFileError(
            f"{file}: cannot be read as a generic run file ({_reason(exc)})"
        ) from None
    try:
        return GenericRunRecord(
            **arrays,
            joint_names=joint_names,
            imu_mounts=mounts,
            urdf=urdf.decode("utf-8") if isinstance(urdf, bytes) else str(urdf),
            joint_table=tables["joint_table"],
            base_table=tables["base_table"],
            attributes=attributes,
        )
    except ValueError as exc:  # ParameterError from the record's shape check
        raise InputFileError(f"{file}: {exc}") from None
