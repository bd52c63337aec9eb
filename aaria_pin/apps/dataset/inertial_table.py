"""The standard inertial parameters of a data set's run: the table ``inertial_parameters``.

Every run of a data set made by this version stores the standard inertial parameters of the
robot it moved, as the per-run table ``inertial_parameters`` (float64, ``(n + 1) × 10``, n the
record's joint columns: ``7 × 10`` for an Aaria arm). Row i < n is the body that the record's
joint i moves, its ten parameters in Pinocchio's ``Inertia.toDynamicParameters`` order
``[m, m·cx, m·cy, m·cz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz]`` (mass [kg], first moments [kg·m],
inertia about the joint frame's origin in its axes [kg·m²]; the order of
:data:`aaria_pin.apps.identify.inertial_regressor.INERTIAL_PARAMETERS`); the row of a joint the
run lacks (an Aaria arm's empty module) is zeros. Pinocchio merges the links fixed to a joint's
body into it (Pinocchio's URDF reader): an empty module's link and the tool are in the row of
the joint before them. Row n is the base body: the root link and the links fixed to it, which
the model's free-flyer root joint carries (a data set's models have one, at rest on a fixed
base: the base wrench is its reaction); zeros for a model without one.

So the torques are linear in the table: ``tau[t] = Y(q, v, a)[t, 6:] @ pi``, with ``Y``
Pinocchio's ``computeJointTorqueRegressor`` and ``pi`` the table's rows in model order (base row
first), and the base wrench is ``Y[t, :6] @ pi`` turned into world-aligned axes (the tests
check both against the stored ``tau`` and ``base_wrench``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from aaria_pin.core.se3 import Array

if TYPE_CHECKING:
    from aaria_pin.core.run import RunRobot

__all__ = ["INERTIAL_TABLE", "PARAMETERS_PER_BODY", "inertial_shape", "inertial_table"]

INERTIAL_TABLE = "inertial_parameters"
"""The name of the per-run table of standard inertial parameters."""
PARAMETERS_PER_BODY = 10
"""Standard inertial parameters of one body."""


def inertial_shape(joints: int) -> tuple[int, int]:
    """The table's shape for a record of ``joints`` joint columns: one row each, and the base."""
    return (joints + 1, PARAMETERS_PER_BODY)


def inertial_table(robot: RunRobot) -> Array:
    """The standard inertial parameters of a run's robot, by record joint column, then the base.

    Args:
        robot: the run's robot (its model, its record columns)

    Returns:
        ``(n + 1) × 10`` float64 (see the module docstring).
    """
    model = robot.model.model
    joints = len(robot.joint_names)
    table = np.zeros(inertial_shape(joints))
    first = 2 if robot.model.moving_base else 1
    columns = list(range(joints)) if robot.columns is None else robot.columns
    bodies = range(first, model.njoints)
    for column, joint in zip(columns, bodies, strict=True):
        table[column] = np.asarray(model.inertias[joint].toDynamicParameters())
    if robot.model.moving_base:
        table[joints] = np.asarray(model.inertias[1].toDynamicParameters())
    return table
