"""Data sets written by aaria_pin 0.1 (format version 1), read as run records.

Version 1 stored the arrays of a run file with a leading run axis, two ways:

- a data set of Aaria arms (no ``layout_json``): ``senSen`` (N × T × 91), ``senSenDH``,
  ``senSenJ`` (N × 8 × 5), ``senSenB`` (N × 6 × 4), ``q`` … ``tau``, ``base_wrench`` (N × T × 6),
  ``tool_pose`` and ``imu_mount``;
- a data set of a URDF robot (``layout_json``): ``signals`` (N × T × C), ``joint_table``,
  ``base_table`` (zeros on a fixed base), the same joint series, ``tool_pose``, ``imu_mount``,
  the text ``urdf`` and the attribute ``robot`` (names, frames, base mode).

Neither stored ``base_pose``: it is re-made from the run's base table (identity on a fixed
base), as the run computed it. The IMU signals are the columns of ``senSen``/``signals``.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.record import (
    IMU_SIGNALS,
    VIEW_UNITS,
    RunRecord,
    mounts_from_poses,
    signals_view,
)
from aaria_pin.files.dataset.header import DatasetHeader
from aaria_pin.files.dataset.layout import record_attributes
from aaria_pin.files.legacy_arm import base_pose_from_table, legacy_arm

__all__ = ["LEGACY_VERSION", "legacy_names", "legacy_record"]

LEGACY_VERSION = 1

_AARIA_ARRAYS = (
    "senSen",
    "senSenDH",
    "senSenJ",
    "senSenB",
    "q",
    "qd",
    "qdd",
    "tau",
    "base_wrench",
    "tool_pose",
    "imu_mount",
)
"""The per-run arrays of a version 1 Aaria data set, in file order."""
_NOISE_STREAM = 3
"""0.1's noise stream of run k: ``SeedSequence(seed, spawn_key=(k, 3))``."""


def legacy_names(handle: Any) -> tuple[str, ...]:
    """The per-run arrays of an open version 1 data set, in file order."""
    text = handle.attrs.get("layout_json")
    if text is None:
        return _AARIA_ARRAYS
    return tuple(json.loads(text)["shapes"])


def _columns(dataset: Any) -> tuple[str, ...]:
    return tuple(c.decode() if isinstance(c, bytes) else str(c) for c in dataset.attrs["columns"])


def legacy_record(handle: Any, run: int, header: DatasetHeader) -> RunRecord:
    """Run ``run`` of an open version 1 data set as a run record (arrays in float64).

    Args:
        handle: the open h5py file
        run: the run index (a complete run)
        header: its header
    """
    aaria = "layout_json" not in handle.attrs
    flat = np.asarray(handle["senSen" if aaria else "signals"][run], dtype=float)
    columns = _columns(handle["senSen" if aaria else "signals"])
    samples = flat.shape[0]
    time = flat[:, 0]
    attributes = record_attributes(header.attributes, run, _NOISE_STREAM)
    mounts = np.asarray(handle["imu_mount"][run], float)
    if aaria:
        arm = legacy_arm(Path(handle.filename))
        joints = arm.joints
        imus = tuple(name[: -len("_wx")] for name in columns[1 + arm.modules :: 6])
        imu_mounts = arm.mounts(imus, mounts)
        tables = {name: np.asarray(handle[name][run], float) for name in _AARIA_ARRAYS[1:4]}
        base_table: np.ndarray | None = tables["senSenB"]
        urdf = ""
        attributes.update(kind="dh", robot=arm.robot)
    else:
        robot = header.robot_info or {}
        joints = tuple(robot["joint_names"])
        imus = tuple(robot["imu_names"])
        imu_mounts = mounts_from_poses(imus, robot["imu_parents"], mounts)
        moving = bool(robot.get("moving_base", True))
        tables = {"joint_table": np.asarray(handle["joint_table"][run], float)}
        base_table = np.asarray(handle["base_table"][run], float) if moving else None
        if base_table is not None:
            tables["base_table"] = base_table
        urdf = handle["urdf"].asstr()[()] if "urdf" in handle else ""
        attributes.update(kind="urdf", robot=robot.get("name", ""))
        for key in ("source", "moving_base", "base_frame", "tool_frame"):
            if key in robot:
                attributes[key] = robot[key]
    n = len(joints)
    q = flat[:, 1 : 1 + n]
    imu = flat[:, 1 + n :].reshape(samples, len(imus), len(IMU_SIGNALS))
    base_pose = base_pose_from_table(base_table, time)
    views = {}
    if aaria:  # the Aaria view first, as a version 2 file lists it
        views["senSen"] = signals_view(joints, imus, columns, VIEW_UNITS)
    views["signals"] = signals_view(joints, imus)

    def series(name: str) -> np.ndarray:
        return np.asarray(handle[name][run], dtype=float)

    return RunRecord(
        time=time,
        joint_names=joints,
        q=q,
        qd=series("qd"),
        qdd=series("qdd"),
        tau=series("tau"),
        base_pose=base_pose,
        base_wrench=series("base_wrench"),
        tool_pose=series("tool_pose"),
        imu=imu,
        imu_mounts=imu_mounts,
        urdf=urdf,
        tables=tables,
        views=views,
        attributes=attributes,
    )
