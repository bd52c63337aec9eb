"""The URDF robot kind: a loaded URDF robot as the run engine's robot.

:func:`urdf_robot_run` checks a robot's joint and base tables and gives the
:class:`UrdfRobotRun` adapter the engine (:func:`~aaria_pin.core.run.engine.simulate`) runs;
:mod:`aaria_pin.core.urdf_run` keeps the producers that take a URDF text and its tables.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.core.arguments import checked
from aaria_pin.core.model import RobotModel
from aaria_pin.core.oscillation import base_motion, default_base_table, validate_base_table
from aaria_pin.core.record import ColumnView, ImuMount
from aaria_pin.core.sampled_motion import JointColumns
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory
from aaria_pin.core.urdf_robot import (
    UrdfRobot,
    default_urdf_joint_table,
    effort_excess,
    mimic_followers,
    urdf_joint_trajectory,
    validate_urdf_joint_table,
)

__all__ = ["UrdfRobotRun", "UrdfRunSpec", "urdf_joint_columns", "urdf_robot_run"]


@dataclass(frozen=True)
class UrdfRobotRun:
    """A URDF robot as the run engine's robot (:class:`~aaria_pin.core.run.RunRobot`).

    Made by :func:`urdf_robot_run`. The record's columns are the actuated joints in model
    order; its IMUs the robot's layout; it keeps the URDF text, ``joint_table`` and (on a
    moving base) ``base_table``, and the attributes ``effort_exceeded`` (from the peak torques
    so far), ``moving_base``, ``source`` and, where given, ``urdf_dir``.

    Attributes:
        loaded: the robot (:func:`~aaria_pin.core.urdf_robot.load_urdf_robot`)
        joint_table: n × 5 joint oscillation table, checked
        base_table: base oscillation table, checked (None: a fixed base, at rest)
        source: where the URDF came from (a robot name or a file)
        urdf_dir: the URDF's folder as the attribute ``urdf_dir`` (None: no attribute)
    """

    loaded: UrdfRobot
    joint_table: Array
    base_table: Array | None
    source: str = ""
    urdf_dir: str | None = None
    kind: ClassVar[str] = "urdf"
    columns: ClassVar[None] = None
    imu_slots: ClassVar[None] = None
    n_slots: ClassVar[None] = None
    torque_name: ClassVar[str] = "torques"

    @property
    def model(self) -> RobotModel:
        """The robot's Pinocchio model."""
        return self.loaded.robot

    @property
    def joint_names(self) -> tuple[str, ...]:
        """The actuated joints, model order."""
        return tuple(self.loaded.robot.joint_names)

    @property
    def limits(self) -> tuple[Array, Array]:
        """The URDF position limits (±inf for a mimic joint) [rad or m]."""
        joints = self.loaded.joints
        lower = [-np.inf if j.mimic is not None else j.lower for j in joints]
        upper = [np.inf if j.mimic is not None else j.upper for j in joints]
        return np.array(lower, dtype=float), np.array(upper, dtype=float)

    @property
    def imu_frames(self) -> list[str]:
        """The frames of the robot's IMUs."""
        return list(self.loaded.robot.sensor_frames)

    @property
    def imu_mounts(self) -> tuple[ImuMount, ...]:
        """The robot's IMU layout."""
        return self.loaded.imu_mounts

    @property
    def urdf(self) -> str:
        """The URDF text."""
        return self.loaded.urdf

    @property
    def tables(self) -> dict[str, Array]:
        """``joint_table`` and, on a moving base, ``base_table``."""
        tables = {"joint_table": self.joint_table}
        if self.base_table is not None:
            tables["base_table"] = self.base_table
        return tables

    @property
    def views(self) -> dict[str, ColumnView]:
        """None."""
        return {}

    def sines(self, times: Array) -> JointTrajectory:
        """The joint table's sines at ``times`` (mimic joints follow their leaders)."""
        return urdf_joint_trajectory(self.joint_table, self.loaded, times)

    def base(self, times: Array) -> BaseMotion:
        """The base table's motion, or at rest on a fixed base."""
        if self.base_table is None:
            return BaseMotion.resting(times.size)
        return base_motion(self.base_table, times)

    def record_columns(self, values: Array) -> Array:
        """The columns as they are (C-ordered)."""
        return np.ascontiguousarray(values)

    def attributes(self, peaks: Array) -> dict[str, Any]:
        """``robot``, ``source``, ``moving_base``, frames, ``effort_exceeded``, ``urdf_dir``."""
        robot = self.loaded.robot
        excess = effort_excess(self.loaded, peaks[None])
        attributes: dict[str, Any] = {
            "robot": self.loaded.summary.name,
            "source": self.source,
            "moving_base": self.base_table is not None,
            "base_frame": robot.base_frame,
            "tool_frame": robot.tool_frame,
            "effort_exceeded": {name: list(values) for name, values in excess.items()},
        }
        if self.urdf_dir is not None:
            attributes["urdf_dir"] = self.urdf_dir
        return attributes


@checked
@dataclass(frozen=True)
class UrdfRunSpec:
    """The inputs of a URDF robot's run beside the robot (what :func:`urdf_robot_run` takes).

    Attributes:
        joint_table: n × 5 joint oscillation table, one row per actuated joint in model order
            (None: :func:`~aaria_pin.core.urdf_robot.default_urdf_joint_table`)
        base_table: 2 × 4 or 6 × 4 base oscillation table (None: a gentle motion; not stored
            on a fixed base, refused with ``moving_base`` False)
        moving_base: False holds a free-flyer robot's base at rest at the origin (its base
            wrench is then the fixed mount's load); None: moving if the model has a free-flyer
        source: where the URDF came from, stored as an attribute
        urdf_dir: the URDF's folder, stored as the attribute ``urdf_dir`` (None: not stored)
    """

    joint_table: ArrayLike | None = None
    base_table: ArrayLike | None = None
    moving_base: bool | None = None
    source: str | None = None
    urdf_dir: str | None = None


@checked
def urdf_robot_run(loaded: UrdfRobot, spec: UrdfRunSpec | None = None) -> UrdfRobotRun:
    """A loaded URDF robot as the run engine's robot, its tables checked.

    Raises:
        TableError, ParameterError: a bad joint or base table.
        OptionConflictError: a base table given with ``moving_base`` False (it would be
            ignored).
    """
    from aaria_pin.core.conflicts import OptionConflictError

    spec = UrdfRunSpec() if spec is None else spec
    if spec.moving_base is False and spec.base_table is not None:
        raise OptionConflictError(
            parameter="base_table", other="moving_base", given_with=True, other_value="False"
        )
    robot = loaded.robot
    moving = robot.moving_base if spec.moving_base is None else spec.moving_base
    moving = moving and robot.moving_base
    table = (
        default_urdf_joint_table(loaded)
        if spec.joint_table is None
        else np.array(spec.joint_table, float)
    )
    validate_urdf_joint_table(table, loaded)  # errors before any work
    base_arr = None
    if moving:
        base_arr = (
            default_base_table()
            if spec.base_table is None
            else validate_base_table(spec.base_table)
        )
    source = spec.source if spec.source is not None else ""
    return UrdfRobotRun(loaded, table, base_arr, source, spec.urdf_dir)


def urdf_joint_columns(loaded: UrdfRobot) -> JointColumns:
    """A URDF robot's motion columns: its joints; a mimic joint follows its leader."""
    names = tuple(joint.name for joint in loaded.joints)
    given = tuple(j for j, joint in enumerate(loaded.joints) if joint.mimic is None)
    return JointColumns(names, given, mimic_followers(loaded.joints))
