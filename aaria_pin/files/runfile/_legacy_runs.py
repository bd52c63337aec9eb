"""Reading the run files aaria_pin 0.1.0 wrote, as today's :class:`RunRecord`.

Four 0.1.0 layouts (fixtures in ``tests/fixtures/v0_1_0``):

- an Aaria DH run, ``.h5`` or ``.mat`` (``format = "aaria_pin run"``, ``format_version = 1``):
  ``senSen`` T × 91 with its column names, ``senSenDH``, ``senSenJ``, ``senSenB``, ``q`` … ``tau``
  (T × 6), ``base_wrench``, ``tool_pose``, ``imu_mount`` 14 × 4 × 4. The record gets joints
  ``joint1`` … ``joint6``, the 14 slots named by the ``senSen`` columns (parent ``base`` for
  ``imu_base``, ``tool_tip`` for ``imu_tool``, ``link{i}`` for ``imu_link{i}_a``/``_b``, and ``""``
  for a slot whose stored mount is all zeros: an empty module), ``imu`` from the ``senSen`` IMU
  columns, ``base_pose`` from the ``senSenB`` sines (the file does not store it), the ``senSen``
  view, the three tables, no URDF, and attributes ``kind = "dh"``, ``robot = "aaria-arm"``
  (0.1.0 did not store the preset's name);
- a URDF robot's run, ``.h5`` (``format = "aaria_pin generic run"``): ``signals`` (time, q, the IMU
  signals), ``q`` … ``tau``, ``base_pose``, ``base_wrench``, ``tool_pose``, ``imu_mount`` with
  ``imu_names``/``imu_parents``, ``urdf``, and ``joint_table``/``base_table`` as tables;
  ``kind = "urdf"``;
- the pick-place arm's run: a URDF robot's run without IMUs whose ``task`` attribute is
  ``"pick-place"``; ``kind = "pick-place"``, ``robot = "pick-place-arm"`` (0.1.0 wrote
  ``pick_place_arm``);
- the wrist's run, ``.h5`` or ``.mat`` (no ``format``): ``time``, ``q`` … ``tau`` (T × 3),
  ``tool_pose`` and attributes ``targets_rad``, ``speed_rad_s``, ``acceleration_rad_s2``,
  ``profile``. Its base is fixed (``base_pose`` the identity) and no IMU is mounted; the mount
  wrench was not computed, so ``base_wrench`` is zeros and the attribute
  ``base_wrench_known = False`` says so. ``kind = "wrist"``, ``robot = "spherical-wrist"``,
  joints ``joint1`` … ``joint3``.
"""

from __future__ import annotations

from collections.abc import Container, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.record import (
    IMU_SIGNALS,
    ImuMount,
    RunRecord,
    record_shapes,
    signal_columns,
)
from aaria_pin.core.se3 import Array
from aaria_pin.errors import AariaError, InputFileError, ParameterError
from aaria_pin.files._stored import decode_attribute
from aaria_pin.files.legacy_arm import base_pose_from_table, legacy_arm
from aaria_pin.files.runfile._attributes import RUN_FORMAT, _check_format
from aaria_pin.files.runfile._columns import fitted, read_view
from aaria_pin.files.runfile._hdf5 import _hdf5_attributes, _strings
from aaria_pin.files.runfile._mat import (
    mat_attributes,
    mat_format,
    mat_strings,
    mat_value,
)

URDF_V1_FORMAT = "aaria_pin generic run"
"""The ``format`` of a 0.1.0 URDF robot's (and the pick-place arm's) run file (0.1.0's name)."""

LAYOUT_V2 = "aaria_pin run"
LAYOUT_DH = "0.1.0 Aaria DH run"
LAYOUT_URDF = "0.1.0 URDF run"
LAYOUT_WRIST = "0.1.0 wrist run"
"""The layouts :func:`aaria_pin.files.runfile.run_file_summary` names."""

_DH_TABLES: dict[str, tuple[int, ...]] = {"senSenDH": (8, 5), "senSenJ": (8, 5), "senSenB": (-1, 4)}
_DH_SHAPES = (*_DH_TABLES, "imu_mount")
_DH_SERIES = ("q", "qd", "qdd", "tau", "base_wrench", "tool_pose")
_URDF_SERIES = ("signals", "q", "qd", "qdd", "tau", "base_pose", "base_wrench", "tool_pose")
_WRIST_ARRAYS = ("time", "q", "qd", "qdd", "tau", "tool_pose")
_WRIST_ATTRIBUTES = ("targets_rad", "speed_rad_s", "acceleration_rad_s2", "profile")


# --- which layout --------------------------------------------------------------------------------


def _layout_of(
    file: Path, fmt: Any, version: Any, arrays: Container[str], attributes: Container[str]
) -> str:
    """The layout of a run file from its format marks and names; InputFileError if none."""
    if isinstance(fmt, bytes):
        fmt = fmt.decode("utf-8", errors="replace")
    if fmt is None:
        if all(name in arrays for name in _WRIST_ARRAYS) and "targets_rad" in attributes:
            return LAYOUT_WRIST
        raise InputFileError(
            f"{file}: not an aaria_pin run file (no 'format' attribute)", parameter="file"
        )
    if fmt == URDF_V1_FORMAT:
        _check_format(file, fmt, version, URDF_V1_FORMAT, 1)
        return LAYOUT_URDF
    return LAYOUT_V2 if _check_format(file, fmt, version, RUN_FORMAT) == 2 else LAYOUT_DH


def hdf5_layout(file: Path, handle: Any) -> str:
    """The layout of an open HDF5 run file (:data:`LAYOUT_V2`, ...)."""
    attrs = handle.attrs
    return _layout_of(
        file, attrs.get("format"), attrs.get("format_version"), list(handle), list(attrs)
    )


def mat_layout(file: Path, contents: Mapping[str, Any], variables: Container[str]) -> str:
    """The layout of a ``.mat`` run file from its ``attr_`` variables and variable names."""
    fmt, version = mat_format(contents)
    return _layout_of(file, fmt, version, variables, variables)


# --- reading -------------------------------------------------------------------------------------


def read_legacy_hdf5(file: Path, handle: Any, layout: str) -> RunRecord:
    """The record of an open 0.1.0 HDF5 run file of a layout from :func:`hdf5_layout`."""
    import h5py

    names = (
        ("senSen", *_DH_SHAPES, *_DH_SERIES)
        if layout == LAYOUT_DH
        else (*_URDF_SERIES, "imu_mount", "urdf")
        if layout == LAYOUT_URDF
        else _WRIST_ARRAYS
    )
    for name in names:
        if not isinstance(handle.get(name), h5py.Dataset):
            raise InputFileError(
                f"{file}: not an aaria_pin run file (no dataset {name!r})", parameter="file"
            )
    attributes = _hdf5_attributes(file, handle.attrs)
    if layout == LAYOUT_DH:
        arrays = {name: handle[name][()] for name in names}
        return _dh_record(file, arrays, _strings(handle["senSen"].attrs["columns"]), attributes)
    if layout == LAYOUT_WRIST:
        return _wrist_record(file, {name: handle[name][()] for name in names}, attributes)
    return _urdf_record(file, handle, attributes)


def read_legacy_mat(file: Path, contents: Mapping[str, Any], layout: str) -> RunRecord:
    """The record of loaded 0.1.0 ``.mat`` variables (an Aaria DH run or a wrist run)."""
    if layout == LAYOUT_WRIST:
        attributes: dict[str, Any] = {}
        for name in _WRIST_ATTRIBUTES:
            if name in contents:
                key, value = decode_attribute(file, name, mat_value(contents[name]))
                attributes[key] = value
        return _wrist_record(file, contents, attributes)
    for name in ("senSen", "senSen_columns", *_DH_SHAPES, *_DH_SERIES):
        if name not in contents:
            raise InputFileError(
                f"{file}: not an aaria_pin run file (no array {name!r})", parameter="file"
            )
    return _dh_record(
        file, contents, mat_strings(contents["senSen_columns"]), mat_attributes(file, contents)
    )


def _dh_record(
    file: Path, stored: Mapping[str, Any], columns: Sequence[str], attributes: dict[str, Any]
) -> RunRecord:
    """A DH arm's run record from the 0.1.0 arrays (see the module docstring).

    The arm (its joints, slots and their parents, its name) is the registered
    :class:`~aaria_pin.files.legacy_arm.LegacyArm`.
    """
    arm = legacy_arm(file)
    width = 1 + arm.modules + len(IMU_SIGNALS) * arm.slots
    sensen = fitted(file, "senSen", stored["senSen"], (-1, width))
    samples = sensen.shape[0]
    arrays = {name: fitted(file, name, stored[name], shape) for name, shape in _DH_TABLES.items()}
    shapes = record_shapes(samples, arm.modules, arm.slots)
    for name in ("imu_mount", *_DH_SERIES):
        arrays[name] = fitted(file, name, stored[name], shapes[name])
    joint_names = arm.joints
    slots = _dh_slot_names(file, columns, arm.modules, arm.slots)
    mounts = arm.mounts(slots, arrays["imu_mount"])
    time = np.ascontiguousarray(sensen[:, 0])
    imu = np.ascontiguousarray(sensen[:, 1 + arm.modules :]).reshape(samples, arm.slots, 6)
    view = read_view(file, "senSen", columns, (joint_names, slots))
    return _record(
        file,
        time=time,
        joint_names=joint_names,
        **{name: arrays[name] for name in _DH_SERIES},
        base_pose=_dh_base_pose(file, arrays["senSenB"], time),
        imu=imu,
        imu_mounts=mounts,
        tables={name: arrays[name] for name in ("senSenDH", "senSenJ", "senSenB")},
        views={"senSen": view},
        attributes={**attributes, "kind": "dh", "robot": attributes.get("robot", arm.robot)},
    )


def _dh_slot_names(
    file: Path, columns: Sequence[str], modules: int, n_slots: int
) -> tuple[str, ...]:
    """The ``n_slots`` slot names of a 0.1.0 ``senSen``'s column names."""
    expected_head = ["time", *(f"q{module}" for module in range(1, modules + 1))]
    slots = tuple(str(column)[: -len("_wx")] for column in columns[1 + modules :: len(IMU_SIGNALS)])
    expected = [*expected_head, *(f"{s}_{signal}" for s in slots for signal in IMU_SIGNALS)]
    if len(columns) != 1 + modules + len(IMU_SIGNALS) * n_slots or list(columns) != expected:
        raise InputFileError(
            f"{file}: senSen columns are not the 0.1.0 layout; expected time, q1..q{modules} "
            f"and {n_slots} × <slot>_<wx wy wz fx fy fz>",
            parameter="file",
            value=str(file),
        )
    return slots


def _dh_base_pose(file: Path, table: Array, time: Array) -> Array:
    """``T_world_base`` over time from a ``senSenB`` table (position and ``Rx·Ry·Rz``)."""
    try:
        return base_pose_from_table(table, time)
    except AariaError as exc:
        raise InputFileError(f"{file}: senSenB: {exc}", parameter="file") from None


def _urdf_record(file: Path, handle: Any, attributes: dict[str, Any]) -> RunRecord:
    """A URDF robot's (or the pick-place arm's) record from an open 0.1.0 URDF run file."""
    joint_names = tuple(_strings(handle["q"].attrs.get("joint_names", [])))
    imu_names = _strings(handle["imu_mount"].attrs.get("imu_names", []))
    parents = _strings(handle["imu_mount"].attrs.get("imu_parents", []))
    signals = fitted(
        file, "signals", handle["signals"][()], (-1, 1 + len(joint_names) + 6 * len(imu_names))
    )
    columns = _strings(handle["signals"].attrs.get("columns", []))
    if columns != list(signal_columns(joint_names, imu_names)):
        raise InputFileError(
            f"{file}: signals columns do not match its joint and IMU names; expected time, "
            "q:<joint> per joint, <imu>_<signal> per IMU",
            parameter="file",
        )
    samples = signals.shape[0]
    shapes = record_shapes(samples, len(joint_names), len(imu_names))
    arrays = {
        name: fitted(file, name, handle[name][()], shapes[name])
        for name in shapes
        if name in handle
    }
    if len(parents) != len(imu_names):
        raise InputFileError(
            f"{file}: imu_parents holds {len(parents)} names; expected {len(imu_names)}",
            parameter="file",
        )
    mounts = tuple(
        ImuMount(name, parent, pose)
        for name, parent, pose in zip(imu_names, parents, arrays["imu_mount"], strict=True)
    )
    tables = {
        name: np.asarray(handle[name][()], dtype=np.float64)
        for name in ("joint_table", "base_table")
        if name in handle
    }
    pick_place = attributes.get("task") == "pick-place"
    extra = {"kind": "pick-place", "robot": "pick-place-arm"} if pick_place else {"kind": "urdf"}
    return _record(
        file,
        time=np.ascontiguousarray(signals[:, 0]),
        joint_names=joint_names,
        **{
            name: arrays[name]
            for name in ("q", "qd", "qdd", "tau", "base_pose", "base_wrench", "tool_pose")
        },
        imu=np.ascontiguousarray(signals[:, 1 + len(joint_names) :]).reshape(
            samples, len(imu_names), 6
        ),
        imu_mounts=mounts,
        urdf=handle["urdf"].asstr()[()],
        tables=tables,
        attributes={**attributes, **extra},
    )


def _wrist_record(file: Path, stored: Mapping[str, Any], attributes: dict[str, Any]) -> RunRecord:
    """The wrist's record from the 0.1.0 arrays (see the module docstring)."""
    time = fitted(file, "time", stored["time"], (-1,))
    samples = time.shape[0]
    q = fitted(file, "q", stored["q"], (samples, -1))
    joints = q.shape[1]
    shapes = record_shapes(samples, joints, 0)
    arrays = {name: fitted(file, name, stored[name], shapes[name]) for name in _WRIST_ARRAYS}
    return _record(
        file,
        **arrays,
        joint_names=tuple(f"joint{j}" for j in range(1, joints + 1)),
        base_pose=base_pose_from_table(None, time),
        base_wrench=np.zeros((samples, 6)),
        imu=np.zeros((samples, 0, len(IMU_SIGNALS))),
        imu_mounts=(),
        attributes={
            **attributes,
            "kind": "wrist",
            "robot": "spherical-wrist",
            "base_wrench_known": False,
        },
    )


def _record(file: Path, **fields: Any) -> RunRecord:
    """A RunRecord; InputFileError if the arrays do not agree."""
    try:
        return RunRecord(**fields)
    except ParameterError as exc:
        raise InputFileError(f"{file}: {exc}", parameter="file") from None
