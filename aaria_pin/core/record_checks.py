"""The checks of a run read from a file: the layout of its kind, its attributes, finite data.

A reader (a run file's :func:`~aaria_pin.files.runfile.read_run`, a data set's run) makes a
:class:`~aaria_pin.core.record.RunRecord` of what it read, then calls :func:`check_record`, so
every command that reads a run refuses the same damage in one line, naming the file (and the
run of a data set) and what is wrong:

- the layout of its kind (:data:`KIND_TABLES`): a ``kind`` attribute that names a known kind
  (a file without one, written before kinds were stored, is recognised by its tables), and the
  input tables that kind keeps (a DH run's ``senSenDH``, ``senSenJ``, ``senSenB``); the shapes
  of the series are the record's own check (T rows everywhere, n joints, S IMUs);
- the types of the attributes every kind shares (``rate`` and ``duration`` positive numbers,
  ``seed`` an integer, ``noise`` a bool, names text), read by
  :meth:`~aaria_pin.core.run_metadata.RunMetadata.from_attributes`;
- finite data (:func:`check_finite`): the simulator never writes a NaN or an infinity, so one in
  a stored series is damage; the message names the array, the run and the first bad sample;
- increasing time (:func:`check_time`): the sample times strictly increase (2+ samples);
- the joint hardware's optional tables (:func:`check_joint_tables`): ``q_measured``,
  ``tau_measured``, ``tau_motor``, ``tau_armature``, ``tau_friction``, ``current_measured`` are
  T × n and ``encoder_offset``, ``torque_sensor_bias``, ``torque_sensor_scale``,
  ``current_sensor_bias``, ``current_sensor_scale`` are 1 × n.

Example::

    from aaria_pin.core.record_checks import check_record, record_source

    check_record(record, record_source("ds.h5", run=3))  # "run 3 of ds.h5: tau has NaN at ..."
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from typing import Any

import numpy as np

from aaria_pin.core.record import (
    CONTROL_RUN_TABLES,
    CONTROL_SERIES,
    JOINT_RUN_TABLES,
    JOINT_SERIES,
    SERIES,
    RunRecord,
)
from aaria_pin.core.se3 import Array
from aaria_pin.errors import InputFileError

__all__ = [
    "ATTRIBUTE_TYPES",
    "KIND_TABLES",
    "check_attributes",
    "check_finite",
    "check_joint_tables",
    "check_kind",
    "check_kind_layout",
    "check_record",
    "check_time",
    "record_source",
]

_SERIES = (*JOINT_SERIES, *CONTROL_SERIES)
"""The optional T × n tables of the joint hardware and of a closed-loop drive."""
_RUN_TABLES = (*JOINT_RUN_TABLES, *CONTROL_RUN_TABLES)
"""Their optional 1 × n tables."""

KIND_TABLES: Mapping[str, tuple[str, ...]] = {
    "dh": ("senSenDH", "senSenJ", "senSenB"),
    "urdf": ("joint_table",),
    "wrist": (),
    "pick-place": (),
}
"""The known run kinds (the ``kind`` attribute) and the input tables a run of each must hold.

A wrist run keeps its targets as a table (``targets``) or, written by 0.1.0, as the attribute
``targets_rad``; a pick-and-place run keeps its task in attributes: neither requires a table.
"""

ATTRIBUTE_TYPES: Mapping[str, str] = {
    **dict.fromkeys(
        (
            "kind",
            "robot",
            "source",
            "drive",
            "motion",
            "base_frame",
            "tool_frame",
            "base_wrench_frame",
            "branch",
            "command",
            "dtype",
            "payload_joint",
            "preset",
            "profile",
            "task",
            "urdf_dir",
            "version",
        ),
        "text",
    ),
    **dict.fromkeys(
        ("rate", "duration", "acceleration_rad_s2", "speed_rad_s", "start_s"), "number"
    ),
    **dict.fromkeys(("N", "samples", "seed", "noise_stream", "format_version", "run"), "integer"),
    **dict.fromkeys(("moving_base", "noise"), "bool"),
    **dict.fromkeys(
        (
            "gravity",
            "held_interval",
            "peak_payload_share",
            "phase_end",
            "phase_start",
            "place",
            "targets_rad",
        ),
        "numbers",
    ),
}
"""The type of each attribute a run of any kind (or version) may carry, when present.

``text`` a str; ``number`` a finite real (not a bool); ``integer`` a whole number; ``bool``
true or false (MATLAB may re-save a bool as 0 or 1); ``numbers`` finite reals (a vector; the
``gravity`` three). Attributes not listed (a kind's own, JSON-decoded ones) are left to the code
that reads them.
"""

_ALLOWED_OF = {
    "gravity": "three finite numbers [m/s²]",
    "rate": "a positive number",
    "duration": "a positive number",
}
_ALLOWED = {
    "text": "text",
    "number": "a finite number",
    "integer": "an integer",
    "bool": "true or false",
    "numbers": "finite numbers",
}


def record_source(file: str | os.PathLike[str], run: int | None = None) -> str:
    """How a message names what was read: ``FILE``, or ``run K of FILE`` for a data set's run."""
    return str(file) if run is None else f"run {run} of {file}"


def check_record(record: RunRecord, source: str, series: bool = True, finite: bool = True) -> None:
    """Refuse a run read from a file whose kind, attributes or data are not a run's.

    Args:
        record: the run as read
        source: the file (or ``run K of FILE``), for messages (:func:`record_source`)
        series: whether the series were read (False: only the inputs, whose finite values are
            checked without the series)
        finite: check the arrays' values are finite (False: the reader checked each array as
            it read it, as a data set's does)

    Raises:
        InputFileError: an unknown kind, a table of its kind missing, an attribute of the
            wrong type, a joint hardware table of the wrong shape, a NaN or infinity in an
            array, or sample times that do not strictly increase (``parameter="file"``).
    """
    check_attributes(record.attributes, source)
    check_kind_layout(record, source)
    check_joint_tables(record, source, series)
    if finite:
        arrays = record.arrays()
        check_finite({k: v for k, v in arrays.items() if series or k not in SERIES}, source)
    if series:
        check_time(record.time, source)


def check_time(time: Array, source: str) -> None:
    """Refuse sample times that are not strictly increasing (2+ samples; finite, checked before).

    Raises:
        InputFileError: ``"FILE: time decreases at sample 5; allowed: strictly increasing
            times"`` (``parameter="file"``).
    """
    values = np.asarray(time, dtype=float).reshape(-1)
    if values.size < 2:
        return
    steps = np.diff(values)
    if (steps > 0).all():
        return
    sample = int(np.flatnonzero(~(steps > 0))[0]) + 1
    what = "repeats" if steps[sample - 1] == 0 else "decreases"
    raise InputFileError(
        f"{source}: time {what} at sample {sample}; allowed: strictly increasing times",
        parameter="file",
    )


def check_kind(attributes: Mapping[str, Any], source: str) -> str | None:
    """The ``kind`` attribute, refused unless a known kind (None: a file from before kinds).

    Raises:
        InputFileError: as :func:`check_record`.
    """
    kind = attributes.get("kind")
    if kind is not None and (not isinstance(kind, str) or kind not in KIND_TABLES):
        raise InputFileError(
            f"{source}: attribute 'kind' is {kind!r}; allowed: {', '.join(KIND_TABLES)}",
            parameter="file",
        )
    return kind


def check_kind_layout(record: RunRecord, source: str) -> None:
    """Refuse an unknown ``kind`` or a run without the tables its kind keeps.

    Raises:
        InputFileError: as :func:`check_record`.
    """
    kind = check_kind(record.attributes, source)
    if kind is None:
        return  # written before kinds were stored: recognised by its tables when re-made
    required = KIND_TABLES[kind]
    missing = [name for name in required if name not in record.tables]
    if missing:
        raise InputFileError(
            f"{source}: array {missing[0]} is missing; allowed: a {kind} run file has "
            + ", ".join(required),
            parameter="file",
        )


def check_joint_tables(record: RunRecord, source: str, series: bool = True) -> None:
    """Refuse a joint hardware table (``q_measured``, ``encoder_offset``, ...) of another shape.

    Each is optional; one that is there is T × n (:data:`~aaria_pin.core.record.JOINT_SERIES`,
    its rows checked only with ``series``) or 1 × n
    (:data:`~aaria_pin.core.record.JOINT_RUN_TABLES`),
    n the record's joints.

    Raises:
        InputFileError: ``"FILE: array q_measured has shape (10, 5); allowed: (10, 6) (T × n)"``
            (``parameter="file"``).
    """
    n = len(record.joint_names)
    expected = {name: ((record.n_samples if series else None), n) for name in _SERIES}
    expected.update({name: (1, n) for name in _RUN_TABLES})
    for name, shape in expected.items():
        if name not in record.tables:
            continue
        given = np.shape(record.tables[name])
        same = len(given) == len(shape)
        if not (same and all(e is None or g == e for g, e in zip(given, shape, strict=True))):
            what = "T × n" if name in _SERIES else "1 × n, one per joint"
            allowed = "(" + ", ".join("T" if e is None else str(e) for e in shape) + ")"
            raise InputFileError(
                f"{source}: array {name} has shape {given}; allowed: {allowed} ({what})",
                parameter="file",
            )


def check_attributes(attributes: Mapping[str, Any], source: str) -> None:
    """Refuse shared attributes of the wrong type (a text ``rate``, a numeric ``robot``, ...).

    Raises:
        InputFileError: as :func:`check_record`.
    """
    from aaria_pin.core.run_metadata import RunMetadata

    for name, kind in ATTRIBUTE_TYPES.items():
        value = attributes.get(name)
        if value is not None and not _is_of_type(name, value, kind):
            allowed = _ALLOWED_OF.get(name, _ALLOWED[kind])
            raise InputFileError(
                f"{source}: attribute {name!r} is {value!r}; allowed: {allowed}",
                parameter="file",
            )
    try:
        RunMetadata.from_attributes(attributes)
    except (InputFileError, ValueError, TypeError) as exc:
        raise InputFileError(f"{source}: {exc}", parameter="file") from None


def _is_of_type(name: str, value: Any, kind: str) -> bool:
    """Whether an attribute's value is of its :data:`ATTRIBUTE_TYPES` type."""
    if kind == "text":
        return isinstance(value, str)
    if kind == "bool":
        return isinstance(value, (bool, np.bool_)) or (
            isinstance(value, (int, np.integer)) and value in (0, 1)
        )
    if isinstance(value, (str, bytes, bool, np.bool_)):
        return False
    try:
        numbers = np.asarray(value)
    except (TypeError, ValueError):
        return False
    if numbers.dtype.kind not in "iuf" or not np.isfinite(numbers).all():
        return False
    if kind == "numbers":
        return numbers.ndim <= 1 and (name != "gravity" or numbers.shape == (3,))
    scalar = numbers.ndim == 0 or numbers.size == 1
    return scalar and (kind == "number" or float(numbers.reshape(-1)[0]).is_integer())


def check_finite(arrays: Mapping[str, Array], source: str) -> None:
    """Refuse a NaN or an infinity in any of ``arrays``, naming the first one.

    The whole arrays are checked at once; the first bad value is looked for only when one is
    not finite. A series' first index is its sample, the next its joint (``q`` … ``tau``), its
    IMU and signal (``imu``), or its row and column (a pose).

    Args:
        arrays: the arrays by name (a record's :meth:`~aaria_pin.core.record.RunRecord.arrays`,
            or a data set run's)
        source: the file (or ``run K of FILE``), for the message

    Raises:
        InputFileError: ``"FILE: tau has NaN at sample 17, joint 2; allowed: finite values"``
            (``parameter="file"``).
    """
    for name, array in arrays.items():
        values = np.asarray(array)
        if values.dtype.kind not in "fc" or np.isfinite(values).all():
            continue
        flat = int(np.flatnonzero(~np.isfinite(values))[0])
        index = np.unravel_index(flat, values.shape)
        bad = values[index]
        what = "NaN" if np.isnan(bad) else ("inf" if bad > 0 else "-inf")
        raise InputFileError(
            f"{source}: {name} has {what} at {_position(name, index)}; allowed: finite values",
            parameter="file",
        )


_AXES = {
    "q": ("joint",),
    "qd": ("joint",),
    "qdd": ("joint",),
    "tau": ("joint",),
    "imu": ("IMU", "signal"),
    "base_pose": ("row", "column"),
    "tool_pose": ("row", "column"),
    "base_wrench": ("component",),
    "imu_mount": ("IMU", "row", "column"),
    **{name: ("joint",) for name in _SERIES},
    **{name: ("row", "joint") for name in _RUN_TABLES},
}
"""How a message names the axes of an array after its first (the sample, for a series)."""


def _position(name: str, index: tuple[Any, ...]) -> str:
    """Where in an array an index is: ``sample 17, joint 2`` (0-based, as numpy counts)."""
    if name in ("imu_mount", *_RUN_TABLES):
        axes: tuple[str, ...] = _AXES[name]
    elif name in SERIES or name in _SERIES:
        axes = ("sample", *_AXES.get(name, ()))
    else:
        axes = ("row", "column")
    words = [
        f"{axes[k] if k < len(axes) else 'axis ' + str(k)} {int(i)}" for k, i in enumerate(index)
    ]
    return ", ".join(words) if words else "its value"
