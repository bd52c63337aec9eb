"""The model a run record was computed on: any record, any robot, any file version.

A :class:`~aaria_pin.core.record.RunRecord` holds what its model is made from. The torque
analysis (:mod:`aaria_pin.apps.torques`) and the viewers (:mod:`aaria_pin.viz`) rebuild it here:

- :func:`record_model`: from the record's URDF text (every record of version 2); for a 0.1.0
  record without one, from its ``senSenDH`` table (an Aaria DH run) or the report's wrist;
- :func:`record_base`: the base's motion, from the record's base table (:data:`BASE_TABLES`),
  else at rest where ``base_pose`` puts it; :func:`record_base_motion` the same, from the table
  only and checked against the stored ``base_pose``;
- :func:`record_columns`, :func:`record_joint_kinds`: the joints matched by name (an empty
  Aaria module's zero column is left out) and their kinds;
- :func:`record_mjcf`, :func:`replay_in_mujoco`: the record's robot as a MuJoCo model
  (:mod:`aaria_pin.core.export`) with what the record supplies (URDF, IMU mounts, gravity,
  rate, tool frame, whether and how its base moved), and its motion replayed there.

It lives in the applications layer because a 0.1.0 record may need the Aaria layer (its DH
table) or the wrist application to be rebuilt.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from aaria_pin.core.arguments import checked
from aaria_pin.core.record import RunRecord
from aaria_pin.core.trajectory import BaseMotion
from aaria_pin.core.urdf_parse import parse_urdf
from aaria_pin.errors import InputFileError, ModelError, ParameterError, UrdfError

if TYPE_CHECKING:  # Pinocchio loads only where a model is used
    from aaria_pin.core.export.mjcf_emit import BalanceInertia
    from aaria_pin.core.model import RobotModel
    from aaria_pin.core.se3 import Array

__all__ = [
    "BASE_TABLES",
    "record_base",
    "record_base_motion",
    "record_columns",
    "record_joint_kinds",
    "record_mjcf",
    "record_model",
    "record_moving_base",
    "replay_in_mujoco",
]

BASE_TABLES = ("senSenB", "base_table")
"""Names of a record's base oscillation table (Aaria, URDF robot), in the order looked up."""


def _urdf_links(urdf: str) -> list[str]:
    """The link names of a URDF document, in document order (empty if it does not parse)."""
    try:
        return list(parse_urdf(urdf).link_names)
    except UrdfError:
        return []


def _frame(wanted: object, default: str, links: list[str], first: bool) -> str:
    """A frame the record names, else the default if it is a link, else the first/last link."""
    if isinstance(wanted, str) and wanted:
        return wanted
    if default in links or not links:
        return default
    return links[0] if first else links[-1]


def _base_table(record: RunRecord) -> str | None:
    """The name of the record's base oscillation table (:data:`BASE_TABLES` order), or None."""
    return next((name for name in BASE_TABLES if name in record.tables), None)


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
    metadata = record.metadata
    if record.urdf:
        links = _urdf_links(record.urdf)
        base = _frame(metadata.base_frame, "base", links, first=True)
        tool = _frame(metadata.tool_frame, "tool_tip", links, first=False)
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
            raise InputFileError(
                f"the run's URDF cannot be used: {exc}", parameter="record"
            ) from None
    if metadata.kind == "wrist" and "senSenDH" not in record.tables:
        from aaria_pin.apps.wrist.run import report_wrist  # a wrist run of 0.1.0: no URDF

        return report_wrist().model(moving_base=moving_base)
    if "senSenDH" not in record.tables:
        raise InputFileError(
            "the run has no URDF and no senSenDH table; allowed: a run that stores its model",
            parameter="record",
        )
    from aaria_pin.aaria.dh_robot import BodyDimensions, build_dh_robot

    dims_attr = metadata.extra.get("body_dimensions")
    try:
        dims = BodyDimensions(**dims_attr) if isinstance(dims_attr, dict) else None
    except (TypeError, ValueError, ParameterError) as exc:
        raise InputFileError(
            f"the run's body_dimensions cannot be used ({exc})", parameter="record"
        ) from None
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
    name = _base_table(record)
    if name is not None:
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
                f"joint {name!r} is a {joint.shortname()}; allowed: revolute and prismatic joints",
                parameter="record",
            )
        kinds.append(kind)
    return tuple(kinds)


def record_columns(record: RunRecord, robot: RobotModel) -> list[int]:
    """The record's column of each of the model's joints, matched by name."""
    missing = [name for name in robot.joint_names if name not in record.joint_names]
    if missing:
        raise InputFileError(
            f"joint {missing[0]!r} of the run's model has no column in the run; allowed: "
            + ", ".join(record.joint_names),
            parameter="record",
        )
    return [record.joint(name) for name in robot.joint_names]


def record_base_motion(record: RunRecord) -> BaseMotion:
    """The base motion of a run from its base oscillation table (:data:`BASE_TABLES`).

    Raises:
        ParameterError: the record has no base table, or its table does not give the stored
            ``base_pose`` (to 1e-9 m and 1e-9 of a rotation matrix entry).
    """
    from aaria_pin.core.oscillation import base_motion

    name = _base_table(record)
    if name is None:
        raise ParameterError(
            "run has no base oscillation table; allowed: a run with one of "
            + ", ".join(BASE_TABLES)
            + ", or a base motion given",
            parameter="base",
            value=None,
        )
    base = base_motion(record.tables[name], record.time)
    if not np.allclose(base.T_world_base(), record.base_pose, rtol=0.0, atol=1e-9):
        raise ParameterError(
            f"run's {name} does not give its stored base_pose; allowed: the run's own table",
            parameter="base",
            value=name,
        )
    return base


def record_moving_base(record: RunRecord) -> bool:
    """Whether a run's base moved.

    Its ``moving_base`` attribute; without one, a DH run moves, another if its base leaves the
    identity pose.
    """
    metadata = record.metadata
    if metadata.moving_base is not None:
        return metadata.moving_base
    if metadata.kind == "dh":
        return True
    return not np.array_equal(record.base_pose, np.broadcast_to(np.eye(4), record.base_pose.shape))


@checked
def record_mjcf(
    record: RunRecord,
    *,
    moving_base: bool | None = None,
    rate: float | None = None,
    balance_inertia: BalanceInertia = False,
) -> tuple[str, tuple[str, ...]]:
    """The MJCF of a run's robot: its URDF, IMU mounts, gravity, rate, tool frame, actuators.

    A record without its URDF (a DH or wrist run of 0.1.0) is re-made from its inputs first
    (:func:`aaria_pin.apps.remake.remake_record`) for the URDF of its robot.

    Args:
        record: the run (any kind)
        moving_base: the base chain or a fixed base (default :func:`record_moving_base`)
        rate: sample rate [Hz] (default the run's)
        balance_inertia: as :func:`~aaria_pin.core.export.mjcf_emit.emit_mjcf`

    Returns:
        As :func:`~aaria_pin.core.export.mjcf_emit.emit_mjcf`.

    Raises:
        InputFileError: a run without a URDF that cannot be re-made.
        ModelError: as :func:`~aaria_pin.core.export.mjcf_emit.emit_mjcf`.
    """
    from aaria_pin.core.export.mjcf_emit import emit_mjcf
    from aaria_pin.core.joint_sensors import ActuatorModel, model_from_attributes
    from aaria_pin.core.model import GRAVITY

    urdf = record.urdf
    if not urdf:
        from aaria_pin.apps.remake import remake_record

        urdf = remake_record(record).urdf
    metadata = record.metadata
    actuator = record.attributes.get("actuator")
    return emit_mjcf(
        urdf,
        record.imu_mounts,
        moving_base=record_moving_base(record) if moving_base is None else moving_base,
        gravity=metadata.extra.get("gravity", GRAVITY),
        rate=metadata.rate if rate is None else rate,
        urdf_dir=metadata.urdf_dir or None,
        tool_frame=metadata.tool_frame or None,
        balance_inertia=balance_inertia,
        actuator=model_from_attributes(ActuatorModel, actuator) if actuator else None,
        joint_names=record.joint_names,
    )


@checked
def replay_in_mujoco(
    record: RunRecord, xml: str, base: BaseMotion | None = None
) -> tuple[Array, Array]:
    """MuJoCo's IMU readings and joint torques along a run's motion.

    :func:`~aaria_pin.core.export.mjcf_replay.replay_motion` with the run's base motion
    (default :func:`record_base_motion`, read only when the MJCF has the moving base chain).

    Args:
        record: the run (its joints must be joints of the MJCF, its IMUs sites with sensors)
        xml: the MJCF of the run's robot (:func:`record_mjcf`)
        base: the base motion on a moving base (default :func:`record_base_motion`)

    Returns:
        As :func:`~aaria_pin.core.export.mjcf_replay.replay_motion`.

    Raises:
        ModelError: the MJCF lacks a joint or a sensor of the run.
        ParameterError: a moving base whose motion the run's table does not give.
    """
    from aaria_pin.core.export.mjcf_replay import replay_motion

    motion: BaseMotion | Callable[[], BaseMotion] = (
        (lambda: record_base_motion(record)) if base is None else base
    )
    return replay_motion(record, xml, motion)
