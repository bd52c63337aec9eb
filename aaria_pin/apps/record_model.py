"""The model a run record was computed on: any record, any robot, any file version.

A :class:`~aaria_pin.core.record.RunRecord` holds what its model is made from. The torque
analysis (:mod:`aaria_pin.apps.torques`) and the viewers (:mod:`aaria_pin.viz`) rebuild it here:

- :func:`record_model`: from the record's URDF text (every record of version 2); for a 0.1.0
  record without one, from its ``senSenDH`` table (an Aaria DH run) or the report's wrist;
- :func:`record_base`: the base's motion, from the record's base table (``senSenB`` or
  ``base_table``), else at rest where ``base_pose`` puts it;
- :func:`record_columns`, :func:`record_joint_kinds`: the joints matched by name (an empty
  Aaria module's zero column is left out) and their kinds.

It lives in the applications layer because a 0.1.0 record may need the Aaria layer (its DH
table) or the wrist application to be rebuilt.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from typing import TYPE_CHECKING

import numpy as np

from aaria_pin.core.record import RunRecord
from aaria_pin.core.trajectory import BaseMotion
from aaria_pin.errors import InputFileError, ModelError, ParameterError

if TYPE_CHECKING:  # Pinocchio loads only where a model is used
    from aaria_pin.core.model import RobotModel

__all__ = ["BASE_TABLES", "record_base", "record_columns", "record_joint_kinds", "record_model"]

BASE_TABLES = ("senSenB", "base_table")
"""Names of a record's base oscillation table (Aaria, URDF robot), in the order looked up."""


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


def record_columns(record: RunRecord, robot: RobotModel) -> list[int]:
    """The record's column of each of the model's joints, matched by name."""
    missing = [name for name in robot.joint_names if name not in record.joint_names]
    if missing:
        raise InputFileError(
            f"joint {missing[0]!r} of the run's model has no column in the run; allowed: "
            + ", ".join(record.joint_names)
        )
    return [record.joint(name) for name in robot.joint_names]
