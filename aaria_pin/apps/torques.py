"""Torque-level analysis of any run: peaks, RMS, the gravity / Coriolis / inertial split, power.

Any :class:`~aaria_pin.core.record.RunRecord` (a DH arm, a URDF robot, the wrist, the
pick-place arm; from a run file of any version or from a data set) is analysed the same way:

- the model is rebuilt from the record (:func:`record_model`): from its URDF text when it has
  one (every record of version 2), else (a 0.1.0 DH run, no URDF) from its ``senSenDH`` table;
- the base moves as the record's base table says (``senSenB`` or ``base_table``), else it rests
  where ``base_pose`` puts it (:func:`record_base`);
- the joints are matched by name (``record.joint_names``), so an empty Aaria module (a zero
  column) is left out;
- a pick-place run's samples where the hand holds the cylinder are split on the model with the
  cylinder on the hand, as they were computed (:mod:`aaria_pin.apps.arm.payload`).

The split comes from three batched RNEA passes over the whole trajectory, on the full model
with its moving base: gravity ``g(q)`` (RNEA at zero velocity and acceleration), Coriolis and
centrifugal ``C(q, v)·v`` (RNEA at zero acceleration, less gravity) and inertial ``M(q)·a`` (the
full RNEA less the zero-acceleration one), so the three add up to the RNEA torque at every
sample.
"""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin.core.record import RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory
from aaria_pin.errors import InputFileError, ModelError, ParameterError

if TYPE_CHECKING:  # Pinocchio loads only where a model is used
    from aaria_pin.core.model import RobotModel

__all__ = [
    "BASE_TABLES",
    "dataset_torque_report",
    "record_base",
    "record_columns",
    "record_joint_kinds",
    "record_model",
    "record_torque_report",
    "torque_split",
]

_TERMS = ("gravity", "coriolis", "inertial")

BASE_TABLES = ("senSenB", "base_table")
"""Names of a record's base oscillation table (Aaria, URDF robot), in the order looked up."""

_DH_TYPES = {1: "revolute", 2: "prismatic"}
"""Link type (column 5 of an Aaria table) → joint kind; 0 is an empty module."""


def _urdf_links(urdf: str) -> list[str]:
    """The link names of a URDF document, in document order (empty if it does not parse)."""
    try:
        root = ET.fromstring(urdf)
    except ET.ParseError:
        return []
    return [str(link.get("name")) for link in root.iter("link") if link.get("name")]


def _frame(wanted: object, default: str, links: list[str], first: bool) -> str:
    """A frame the record names, else the default if it is a link, else the first/last link."""
    if isinstance(wanted, str) and wanted:
        return wanted
    if default in links or not links:
        return default
    return links[0] if first else links[-1]


def record_model(record: RunRecord, moving_base: bool = True) -> RobotModel:
    """The model a record was computed on.

    From ``record.urdf`` when it is not empty (:func:`aaria_pin.core.model.build_model`; base and
    tool frames from the attributes ``base_frame`` and ``tool_frame``, else ``base`` and
    ``tool_tip`` where the URDF has them, else its first and last link); else, for an Aaria DH
    record of 0.1.0 (no URDF), from its ``senSenDH`` table and ``body_dimensions`` attribute
    (:func:`aaria_pin.aaria.dh_robot.build_dh_robot`), and for a wrist record of 0.1.0, the
    report's wrist (:func:`aaria_pin.apps.wrist.run.report_wrist`). Sensor frames are those IMU
    frames of the record's mounted IMUs that the model has.

    Args:
        record: the run record
        moving_base: give the model a free-flyer root joint carrying the base

    Returns:
        The model.

    Raises:
        InputFileError: a record with neither a URDF nor a ``senSenDH`` table, a URDF that
            cannot be built, or body dimensions that cannot be used.
    """
    from aaria_pin.core.model import build_model

    mounted = [mount.name for mount in record.imu_mounts if mount.parent]
    if record.urdf:
        attributes = record.attributes
        links = _urdf_links(record.urdf)
        base = _frame(attributes.get("base_frame"), "base", links, first=True)
        tool = _frame(attributes.get("tool_frame"), "tool_tip", links, first=False)
        sensors = [name for name in mounted if name in links]
        try:
            return build_model(
                record.urdf,
                moving_base=moving_base,
                base_frame=base,
                tool_frame=tool,
                sensor_frames=sensors,
            )
        except ModelError as exc:
            raise InputFileError(f"the run's URDF cannot be used: {exc}") from None
    if record.attributes.get("kind") == "wrist" and "senSenDH" not in record.tables:
        from aaria_pin.apps.wrist.run import report_wrist  # a wrist run of 0.1.0: no URDF

        return report_wrist().model(moving_base=moving_base)
    if "senSenDH" not in record.tables:
        raise InputFileError(
            "the run has no URDF and no senSenDH table; allowed: a run that stores its model"
        )
    from aaria_pin.aaria.dh_robot import BodyDimensions, build_dh_robot

    dims_attr = record.attributes.get("body_dimensions")
    try:
        dims = BodyDimensions(**dims_attr) if isinstance(dims_attr, dict) else None
    except (TypeError, ValueError, ParameterError) as exc:
        raise InputFileError(f"the run's body_dimensions cannot be used ({exc})") from None
    robot = build_dh_robot(record.tables["senSenDH"], "aaria", dims)
    return robot.model(moving_base=moving_base)


def record_base(record: RunRecord) -> BaseMotion | None:
    """The base's motion over a run: from its base table, else at rest; None on the origin.

    Returns:
        The motion from the record's ``senSenB`` or ``base_table``
        (:func:`aaria_pin.core.oscillation.base_motion`); else, a base at rest where
        ``base_pose`` puts it (zero velocity and acceleration); None when it rests at the world
        origin, world-aligned, all run long (a fixed base: wrist, pick-place arm).
    """
    from aaria_pin.core.oscillation import base_motion

    time = np.asarray(record.time, dtype=float)
    for name in BASE_TABLES:
        if name in record.tables:
            return base_motion(record.tables[name], time)
    pose = np.asarray(record.base_pose, dtype=float)
    if np.allclose(pose, np.eye(4), rtol=0.0, atol=1e-12):
        return None
    zeros = np.zeros((time.size, 3))
    rotation = np.ascontiguousarray(pose[:, :3, :3])
    position = np.ascontiguousarray(pose[:, :3, 3])
    return BaseMotion(position, zeros, zeros.copy(), rotation, zeros.copy(), zeros.copy())


def record_joint_kinds(robot: RobotModel) -> tuple[str, ...]:
    """``"revolute"`` or ``"prismatic"`` of each actuated joint of a model, in model order.

    Raises:
        InputFileError: a joint that is neither (a planar or spherical URDF joint).
    """
    from aaria_pin.core.kinematics import joint_kind

    first = 2 if robot.moving_base else 1
    kinds = []
    for index, name in enumerate(robot.joint_names, start=first):
        joint = robot.model.joints[index]
        try:
            kind, _ = joint_kind(joint)
        except ModelError:
            kind = ""
        if kind not in ("revolute", "prismatic"):
            raise InputFileError(
                f"joint {name!r} is a {joint.shortname()}; allowed: revolute and prismatic joints"
            )
        kinds.append(kind)
    return tuple(kinds)


_TRAJECTORY = ("time", "q", "qd", "qdd")
_BASE = ("position", "velocity", "acceleration", "rotation", "omega", "omega_dot")


def _held_payload(record: RunRecord, robot: RobotModel) -> tuple[RobotModel, np.ndarray] | None:
    """A pick-place run's model with the held cylinder on the hand, and where it is held.

    The stored torques of a pick-place run carry the cylinder while the hand holds it
    (:mod:`aaria_pin.apps.arm.payload`), which its URDF does not: the split of those samples is
    computed on the model with the payload. None for any other run.

    Raises:
        InputFileError: a pick-place run whose cylinder, arm or held interval cannot be used.
    """
    attributes = record.attributes
    if attributes.get("kind") != "pick-place" or "cylinder" not in attributes:
        return None
    from dataclasses import replace

    from aaria_pin.apps.arm.dims import get_arm_preset
    from aaria_pin.apps.arm.payload import HAND_JOINT, payload_inertia, with_payload
    from aaria_pin.apps.arm.task import Cylinder
    from aaria_pin.errors import AariaError

    try:
        c = attributes["cylinder"]
        cylinder = Cylinder(
            float(c["x"]),
            float(c["y"]),
            radius=float(c["radius"]),
            height=float(c["height"]),
            mass=float(c["mass"]),
        )
        dims = get_arm_preset(str(attributes.get("source") or "pick-place-arm"))
        start, end = (float(v) for v in attributes["held_interval"])
        joint = str(attributes.get("payload_joint") or HAND_JOINT)
        loaded = with_payload(robot.model, payload_inertia(dims, cylinder), joint)
    except (KeyError, TypeError, ValueError, AariaError) as exc:
        raise InputFileError(f"the run's pick-place attributes cannot be used ({exc})") from None
    time = np.asarray(record.time, dtype=float)
    return replace(robot, model=loaded), (time >= start) & (time < end)


def record_columns(record: RunRecord, robot: RobotModel) -> list[int]:
    """The record's column of each of the model's joints, matched by name."""
    missing = [name for name in robot.joint_names if name not in record.joint_names]
    if missing:
        raise InputFileError(
            f"joint {missing[0]!r} of the run's model has no column in the run; allowed: "
            + ", ".join(record.joint_names)
        )
    return [record.joint(name) for name in robot.joint_names]


def torque_split(
    robot: RobotModel, base: BaseMotion, trajectory: JointTrajectory
) -> dict[str, Array]:
    """Joint torques split into gravity, Coriolis/centrifugal and inertial terms, (T, n) each.

    Args:
        robot: the model
        base: the base motion (ignored on a fixed-base model)
        trajectory: joint values over time, columns in model order

    Returns:
        ``{"gravity", "coriolis", "inertial"}``, joint columns only; their sum is the RNEA torque.
    """
    from aaria_pin.core.dynamics import batched_rnea
    from aaria_pin.core.kinematics import full_state

    q, v, a = full_state(robot, base, trajectory)
    zeros = np.zeros_like(v)
    gravity = batched_rnea(robot.model, q, zeros, zeros)  # g(q)
    nonlinear = batched_rnea(robot.model, q, v, zeros)  # C(q, v)·v + g(q)
    total = batched_rnea(robot.model, q, v, a)  # M(q)·a + C(q, v)·v + g(q)
    n_base = robot.base_nv
    return {
        "gravity": gravity[:, n_base:],
        "coriolis": (nonlinear - gravity)[:, n_base:],
        "inertial": (total - nonlinear)[:, n_base:],
    }


def _rms(x: Array) -> Array:
    return np.sqrt(np.mean(np.square(x), axis=0))


def record_torque_report(record: RunRecord) -> dict[str, Any]:
    """Per joint torque statistics of any run, and the base wrench peaks.

    The model, the base motion and the joints come from the record (module docstring).

    Returns:
        A plain dictionary: ``joints`` (one entry per joint of the model, in model order:
        ``module`` its 1-based column in the record (the Aaria module of a DH run), ``joint``
        its name, type, unit, peak |tau|, RMS, RMS of each term of the split and its share of
        their sum, peak |tau·qd| and mean mechanical power, net and absolute mechanical
        energy), ``base_wrench_peak`` (per component), ``split_residual`` (largest
        ``|g + C·v + M·a - tau|``), ``samples``.

    Raises:
        InputFileError: a record whose model cannot be rebuilt (see :func:`record_model`).
    """
    base = record_base(record)
    robot = record_model(record, moving_base=base is not None)
    kinds = record_joint_kinds(robot)
    columns = record_columns(record, robot)
    time = np.asarray(record.time, dtype=float)
    trajectory = JointTrajectory(
        time,
        *(
            np.ascontiguousarray(np.asarray(x, dtype=float)[:, columns])
            for x in (record.q, record.qd, record.qdd)
        ),
    )
    motion = base or BaseMotion.resting(time.size)
    split = torque_split(robot, motion, trajectory)
    payload = _held_payload(record, robot)
    if payload is not None and np.any(payload[1]):
        loaded, held = payload
        part = JointTrajectory(
            *(np.ascontiguousarray(getattr(trajectory, name)[held]) for name in _TRAJECTORY)
        )
        at_held = BaseMotion(*(np.ascontiguousarray(getattr(motion, name)[held]) for name in _BASE))
        for term, values in torque_split(loaded, at_held, part).items():
            split[term][held] = values
    tau = np.asarray(record.tau, dtype=float)[:, columns]
    residual = float(np.abs(sum(split.values()) - tau).max()) if tau.size else 0.0
    dt = float(time[1] - time[0]) if time.size > 1 else 0.0
    power = tau * trajectory.qd
    joints = []
    for index, (column, name, kind) in enumerate(
        zip(columns, robot.joint_names, kinds, strict=True)
    ):
        rms_terms = {term: float(_rms(split[term][:, index])) for term in _TERMS}
        total = sum(rms_terms.values()) or 1.0
        joints.append(
            {
                "module": column + 1,
                "joint": name,
                "type": kind,
                "unit": "N*m" if kind == "revolute" else "N",
                "peak_abs": float(np.abs(tau[:, index]).max()),
                "rms": float(_rms(tau[:, index])),
                "rms_terms": rms_terms,
                "shares": {term: value / total for term, value in rms_terms.items()},
                "power_peak_W": float(np.abs(power[:, index]).max()),
                "power_mean_W": float(np.mean(power[:, index])),
                "energy_net_J": float(np.trapezoid(power[:, index], dx=dt)),
                "energy_abs_J": float(np.trapezoid(np.abs(power[:, index]), dx=dt)),
            }
        )
    wrench_peak = np.abs(np.asarray(record.base_wrench, dtype=float)).max(axis=0)
    return {
        "samples": int(time.size),
        "joints": joints,
        "base_wrench_peak": dict(
            zip(("fx", "fy", "fz", "mx", "my", "mz"), wrench_peak.tolist(), strict=True)
        ),
        "split_residual": residual,
    }


def _stored_joint_kinds(record: RunRecord, cache: dict[str, dict[str, str]]) -> dict[str, str]:
    """Joint name → kind of a record's non-empty joints, without dynamics.

    An Aaria record tells them by its table's link types (0: an empty module, left out); any
    other by its model's joint types (one model built per distinct URDF, kept in ``cache``).
    """
    if "senSenDH" in record.tables:
        types = np.asarray(record.tables["senSenDH"])[:, 4]
        return {
            name: _DH_TYPES[int(types[row])]
            for row, name in enumerate(record.joint_names[: types.size])
            if int(types[row]) in _DH_TYPES
        }
    if record.urdf not in cache:
        robot = record_model(record, moving_base=False)
        cache[record.urdf] = dict(zip(robot.joint_names, record_joint_kinds(robot), strict=True))
    return cache[record.urdf]


def dataset_torque_report(path: str | os.PathLike[str], top: int = 5) -> dict[str, Any]:
    """Peak |tau| over a data set, per joint position and type, and the runs with the largest.

    Read from the stored torques of every complete run (its record, of any robot); no dynamics
    is computed.

    Args:
        path: the data set file
        top: how many of the largest-peak runs to list

    Returns:
        ``by_module`` (1-based joint column → type → count, median, 95th percentile and maximum
        of the runs' peak |tau|), ``joints`` (column → joint name, where every run names it
        alike) and ``largest`` (run, module, joint, type, peak), largest first.
    """
    from aaria_pin.files.dataset_reader import DatasetReader

    peaks: dict[tuple[int, str], list[float]] = {}
    names: dict[int, set[str]] = {}
    largest: list[tuple[float, int, int, str, str]] = []
    cache: dict[str, dict[str, str]] = {}
    with DatasetReader(path) as reader:
        complete = getattr(reader, "complete", None)
        for run in range(len(reader)):
            if complete is not None and not complete[run]:
                continue
            record = reader.record(run)
            tau = np.asarray(record.tau, dtype=float)
            for joint, kind in _stored_joint_kinds(record, cache).items():
                column = record.joint(joint)
                peak = float(np.abs(tau[:, column]).max())
                peaks.setdefault((column + 1, kind), []).append(peak)
                names.setdefault(column + 1, set()).add(joint)
                largest.append((peak, run, column + 1, joint, kind))
    by_module: dict[str, dict[str, dict[str, float]]] = {}
    for (module, kind), values in sorted(peaks.items()):
        v = np.array(values)
        by_module.setdefault(str(module), {})[kind] = {
            "runs": int(v.size),
            "median": float(np.median(v)),
            "p95": float(np.percentile(v, 95)),
            "max": float(v.max()),
        }
    largest.sort(key=lambda item: (-item[0], item[1], item[2]))
    return {
        "by_module": by_module,
        "joints": {str(m): next(iter(n)) for m, n in sorted(names.items()) if len(n) == 1},
        "largest": [
            {"run": run, "module": module, "joint": joint, "type": kind, "peak_abs": peak}
            for peak, run, module, joint, kind in largest[:top]
        ],
    }
