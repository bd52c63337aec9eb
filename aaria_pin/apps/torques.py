"""Torque-level analysis of any run: peaks, RMS, the gravity / Coriolis / inertial split, power.

Any :class:`~aaria_pin.core.record.RunRecord` (a DH arm, a URDF robot, the wrist, the
pick-place arm; from a run file of any version or from a data set) is analysed the same way:

- the model, the base motion and the joints come from the record
  (:mod:`aaria_pin.apps.record_model`): the model from its URDF text (or a 0.1.0 run's DH
  table), the base from its base table (else at rest where ``base_pose`` puts it), the joints
  matched by name, so an empty Aaria module (a zero column) is left out;
- a pick-place run's samples where the hand holds the cylinder are split on the model with the
  cylinder on the hand, as they were computed (:mod:`aaria_pin.apps.arm.payload`).

The split comes from three batched RNEA passes over the whole trajectory, on the full model
with its moving base: gravity ``g(q)`` (RNEA at zero velocity and acceleration), Coriolis and
centrifugal ``C(q, v)·v`` (RNEA at zero acceleration, less gravity) and inertial ``M(q)·a`` (the
full RNEA less the zero-acceleration one), so the three add up to the RNEA torque at every
sample.

A run with actuators (:mod:`aaria_pin.core.actuator`: the tables ``tau_armature``,
``tau_friction`` and ``tau_motor = tau + tau_armature + tau_friction``) also gets the motor's
split (:func:`motor_torques`): per joint the peak and RMS of the rigid-body, armature, friction
and motor torques, and the motor's torque limit with whether ``tau_motor`` exceeds it.
"""

from __future__ import annotations

import os
from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin.apps.record_model import (
    record_base,
    record_columns,
    record_joint_kinds,
    record_model,
)
from aaria_pin.core.record import RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory

if TYPE_CHECKING:  # Pinocchio loads only where a model is used
    from aaria_pin.core.model import RobotModel

__all__ = [
    "MOTOR_PARTS",
    "MotorTorques",
    "dataset_torque_report",
    "motor_torques",
    "record_torque_report",
    "run_torque_report",
    "torque_split",
    "torque_text",
]

_TERMS = ("gravity", "coriolis", "inertial")

_DH_TYPES = {1: "revolute", 2: "prismatic"}
"""Link type (column 5 of an Aaria table) → joint kind; 0 is an empty module."""

MOTOR_PARTS = {"rigid": "tau", "armature": "tau_armature", "friction": "tau_friction",
               "motor": "tau_motor"}  # fmt: skip
"""The parts of a joint's motor torque and the record's table of each (``tau`` the series)."""

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
    from dataclasses import replace

    from aaria_pin.apps.arm.payload import payload_inertia, with_payload
    from aaria_pin.apps.arm.stored_task import stored_task
    from aaria_pin.errors import AariaError, InputFileError

    task = stored_task(record)
    if task is None:
        return None
    start, end = task.held
    try:
        payload = payload_inertia(task.dims, task.cylinder)
        loaded = with_payload(robot.model, payload, task.payload_joint)
    except AariaError as exc:  # a stored payload joint the model does not have
        raise InputFileError(
            f"the run's pick-place attributes cannot be used ({exc})", parameter="record"
        ) from None
    time = np.asarray(record.time, dtype=float)
    return replace(robot, model=loaded), (time >= start) & (time < end)


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


@dataclass(frozen=True)
class MotorTorques:
    """One joint's motor torque split: ``motor = rigid + armature + friction`` [N·m or N].

    Attributes:
        joint: the joint's name
        peak: the peak |value| of each part of :data:`MOTOR_PARTS`
        rms: the RMS of each part
        limit: the motor's torque limit (:func:`~aaria_pin.core.actuator.torque_limits`), None
            when it has none
        exceeded: the peak motor torque is above the limit
    """

    joint: str
    peak: dict[str, float]
    rms: dict[str, float]
    limit: float | None
    exceeded: bool


def motor_torques(
    record: RunRecord, robot: RobotModel | None = None
) -> tuple[MotorTorques, ...] | None:
    """Each joint's motor torque split, in the model's joint order (None: a run without it).

    Args:
        record: the run; its tables ``tau_armature``, ``tau_friction``, ``tau_motor`` and its
            ``actuator`` attribute (the limits; default :class:`ActuatorModel`'s)
        robot: the run's model, for its effort limits (default
            :func:`~aaria_pin.apps.record_model.record_model`)

    Returns:
        A :class:`MotorTorques` per joint of the model, or None when the run lacks a table.

    Raises:
        InputFileError: a record whose model cannot be rebuilt.
    """
    from aaria_pin.core.actuator import model_effort_limits, torque_limits
    from aaria_pin.core.joint_sensors import ActuatorModel, model_from_attributes

    if any(table not in record.tables for table in list(MOTOR_PARTS.values())[1:]):
        return None
    robot = record_model(record, moving_base=False) if robot is None else robot
    columns = record_columns(record, robot)
    actuator = model_from_attributes(ActuatorModel, record.attributes.get("actuator") or {})
    effort = model_effort_limits(robot, columns, len(record.joint_names))
    limits = torque_limits(actuator, effort)[columns]
    parts = {
        part: np.asarray(record.tau if table == "tau" else record.tables[table], dtype=float)
        for part, table in MOTOR_PARTS.items()
    }
    peaks = {part: np.abs(values[:, columns]).max(axis=0) for part, values in parts.items()}
    rms = {part: _rms(values[:, columns]) for part, values in parts.items()}
    return tuple(
        MotorTorques(
            joint=name,
            peak={part: float(peaks[part][k]) for part in MOTOR_PARTS},
            rms={part: float(rms[part][k]) for part in MOTOR_PARTS},
            limit=float(limits[k]) if np.isfinite(limits[k]) else None,
            exceeded=bool(peaks["motor"][k] > limits[k]),
        )
        for k, name in enumerate(robot.joint_names)
    )


def record_torque_report(record: RunRecord) -> dict[str, Any]:
    """Per joint torque statistics of any run, and the base wrench peaks.

    The model, the base motion and the joints come from the record (module docstring).

    Returns:
        A plain dictionary: ``joints`` (one entry per joint of the model, in model order:
        ``module`` its 1-based column in the record (the Aaria module of a DH run), ``joint``
        its name, type, unit, peak |tau|, RMS, RMS of each term of the split and its share of
        their sum, peak |tau·qd| and mean mechanical power, net and absolute mechanical
        energy), ``base_wrench_peak`` (per component), ``split_residual`` (largest
        ``|g + C·v + M·a - tau|``), ``samples``. A run with actuators: each joint's
        ``motor``, its :class:`MotorTorques` as a dictionary (:func:`motor_torques`).

    Raises:
        InputFileError: a record whose model cannot be rebuilt
            (:func:`~aaria_pin.apps.record_model.record_model`).
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
                "unit": "N" if kind == "prismatic" else "N*m",
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
    for joint, motor in zip(joints, motor_torques(record, robot) or (), strict=False):
        joint["motor"] = asdict(motor)
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
    from aaria_pin.files.dataset.reader import DatasetReader

    peaks: dict[tuple[int, str], list[float]] = {}
    names: dict[int, set[str]] = {}
    largest: list[tuple[float, int, int, str, str]] = []
    cache: dict[str, dict[str, str]] = {}
    with DatasetReader(path) as reader:
        for run in map(int, np.flatnonzero(reader.complete)):
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


def _unit(kind: str) -> str:
    """The unit of a joint's effort: a force [N] for a prismatic joint, else a torque [N*m]."""
    return "N" if kind == "prismatic" else "N*m"


def torque_text(report: dict[str, Any], one_run: bool = True) -> str:
    """A torque report as the table ``aaria torques`` prints.

    Args:
        report: :func:`record_torque_report`'s (``one_run``) or :func:`dataset_torque_report`'s
        one_run: which of the two ``report`` is

    Returns:
        One run: a line per joint (peak, RMS, RMS of each term, energy) and the base wrench's
        peaks; a data set: a line per module and joint type (peaks' median, p95, max) and the
        largest peaks.
    """
    if not one_run:
        names = report.get("joints", {})
        lines = [
            f"module {module}"
            + (f" ({names[module]})" if module in names else "")
            + f" {kind:<10} runs {s['runs']:>6}  peak |tau| median {s['median']:.4g} {_unit(kind)}"
            f"  p95 {s['p95']:.4g} {_unit(kind)}  max {s['max']:.4g} {_unit(kind)}"
            for module, kinds in report["by_module"].items()
            for kind, s in kinds.items()
        ]
        largest = (
            f"run {x['run']} module {x['module']} ({x['type']}) {x['peak_abs']:.4g} "
            f"{_unit(x['type'])}"
            for x in report["largest"]
        )
        return "\n".join([*lines, "largest peaks: " + "; ".join(largest)])
    width = max([5, *(len(joint["joint"]) for joint in report["joints"])])
    lines = [
        f"{'module':<7} {'joint':<{width}} {'type':<10} {'peak |tau|':>12} {'rms':>10} "
        f"{'rms gravity':>11} {'rms coriolis':>12} {'rms inertial':>12} {'energy net':>11}"
        f" {'energy abs':>11}"
    ]
    for joint in report["joints"]:
        terms = joint["rms_terms"]
        lines.append(
            f"{joint['module']:<7} {joint['joint']:<{width}} {joint['type']:<10}"
            f" {joint['peak_abs']:>8.4g} {joint['unit']:<3}"
            f" {joint['rms']:>10.4g} {terms['gravity']:>11.4g} {terms['coriolis']:>12.4g}"
            f" {terms['inertial']:>12.4g} {joint['energy_net_J']:>9.4g} J"
            f" {joint['energy_abs_J']:>9.4g} J"
        )
    peaks = report["base_wrench_peak"].items()
    units = ", ".join(f"{k} {v:.4g} {'N' if k.startswith('f') else 'N*m'}" for k, v in peaks)
    return "\n".join([*lines, "base wrench peaks: " + units, *_motor_lines(report, width)])


def _motor_lines(report: dict[str, Any], width: int) -> list[str]:
    """The motor split's table (:func:`motor_torques`); none for a run without actuators."""
    joints = [joint for joint in report["joints"] if "motor" in joint]
    if not joints:
        return []
    heads = "".join(f" {'peak ' + part:>13} {'rms ' + part:>12}" for part in MOTOR_PARTS)
    lines = [
        "motor torque = rigid (tau) + armature + friction:",
        f"{'module':<7} {'joint':<{width}}{heads} {'limit':>10}",
    ]
    for joint in joints:
        motor = joint["motor"]
        values = "".join(
            f" {motor['peak'][part]:>13.4g} {motor['rms'][part]:>12.4g}" for part in MOTOR_PARTS
        )
        limit = "none" if motor["limit"] is None else f"{motor['limit']:.4g}"
        flag = "  EXCEEDED" if motor["exceeded"] else ""
        lines.append(
            f"{joint['module']:<7} {joint['joint']:<{width}}{values} {limit:>10}"
            f" {joint['unit']}{flag}"
        )
    return lines


def run_torque_report(
    path: str | os.PathLike[str], run: int | None = None
) -> tuple[dict[str, Any], bool]:
    """The torque report of a file: a run file's, a data set's summary, or one data set run's.

    Args:
        path: a run file (any robot, any version) or a data set
        run: the run of a data set to analyse (None: the summary of every run); only for a
            data set

    Returns:
        The report and whether it is one run's (:func:`record_torque_report`) rather than a
        data set's summary (:func:`dataset_torque_report`).

    Raises:
        ParameterError: ``run`` given for a run file.
        InputFileError: an unreadable file, or a run whose model cannot be rebuilt.
    """
    from aaria_pin.files.detection import is_dataset_file

    if run is None and is_dataset_file(path):
        return dataset_torque_report(path), False
    from aaria_pin.files.source import open_record

    return record_torque_report(open_record(path, run)), True
