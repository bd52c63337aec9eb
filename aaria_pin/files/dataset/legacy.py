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
import re
from typing import Any

import numpy as np

from aaria_pin.core.oscillation import base_motion
from aaria_pin.core.record import IMU_SIGNALS, ColumnSource, ColumnView, ImuMount, RunRecord
from aaria_pin.files.dataset.layout import record_attributes, signals_view

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
_AARIA_MODULES = 6
_AARIA_JOINTS = tuple(f"joint{m}" for m in range(1, _AARIA_MODULES + 1))
_AARIA_ROBOT = "aaria-arm"
"""The ``robot`` of an Aaria run whose table is not a named preset (as a 0.2 run records)."""
_AARIA_PARENTS = {"imu_base": "base", "imu_tool": "tool_tip"}
_AARIA_LINK_SLOT = re.compile(r"imu_(link[1-6])_[ab]")
_SENSEN_UNITS = "see columns: s, rad or m, rad/s, m/s^2"
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


def _aaria_parent(slot: str) -> str:
    link = _AARIA_LINK_SLOT.fullmatch(slot)
    return link[1] if link else _AARIA_PARENTS.get(slot, "")


def legacy_record(handle: Any, run: int, file_attributes: dict[str, Any]) -> RunRecord:
    """Run ``run`` of an open version 1 data set as a run record (arrays in float64).

    Args:
        handle: the open h5py file
        run: the run index (a complete run)
        file_attributes: its decoded attributes
    """
    aaria = "layout_json" not in handle.attrs
    flat = np.asarray(handle["senSen" if aaria else "signals"][run], dtype=float)
    columns = _columns(handle["senSen" if aaria else "signals"])
    samples = flat.shape[0]
    time = flat[:, 0]
    attributes = record_attributes(file_attributes, run, _NOISE_STREAM)
    if aaria:
        joints = _AARIA_JOINTS
        imus = tuple(name[: -len("_wx")] for name in columns[1 + _AARIA_MODULES :: 6])
        parents = tuple(_aaria_parent(name) for name in imus)
        tables = {name: np.asarray(handle[name][run], float) for name in _AARIA_ARRAYS[1:4]}
        base_table: np.ndarray | None = tables["senSenB"]
        urdf = ""
        attributes.update(kind="dh", robot=_AARIA_ROBOT)
    else:
        robot = file_attributes["robot"]
        joints = tuple(robot["joint_names"])
        imus = tuple(robot["imu_names"])
        parents = tuple(robot["imu_parents"])
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
    if base_table is None:
        base_pose = np.broadcast_to(np.eye(4), (samples, 4, 4)).copy()
    else:
        base_pose = base_motion(base_table, time).T_world_base()
    mounts = np.asarray(handle["imu_mount"][run], float)
    imu_mounts = tuple(
        ImuMount(name, parent if mount.any() else "", mount)
        for name, parent, mount in zip(imus, parents, mounts, strict=True)
    )
    views = {}
    if aaria:  # the Aaria view first, as a version 2 file lists it
        views["senSen"] = ColumnView(
            columns,
            (
                ColumnSource("time", ()),
                *(ColumnSource("q", (j,)) for j in range(n)),
                *(ColumnSource("imu", (s, k)) for s in range(len(imus)) for k in range(6)),
            ),
            _SENSEN_UNITS,
        )
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
