"""The Aaria oscillation tables: joint (``senSenJ``) and base (``senSenB``) sine motions.

The base table and the column names are the core's (:mod:`aaria_pin.core.oscillation`), used by
every robot; the 8 × 5 joint table by module is the Aaria layer's.

Joint table, 8 × 5 ``[amplitude (rad), prismatic amplitude (m), bias, frequency (rad/s),
phase (rad)]``: module i follows ``q_i(t) = A·sin(w·t + phase) + bias`` with A the amplitude of a
revolute module or the prismatic amplitude of a prismatic one; rows 7 and 8 are unused. Every
module must stay within its range (``bias ± |A|``): a prismatic joint within ``[-d/2, +d/2]``
of its rail, a revolute joint within ``[-2π, 2π]``.

Base table, 2 × 4 ``[amplitude, bias, frequency (rad/s), phase]``: row 1 moves the base along
world x, y and z (the same sine on each, m), row 2 turns it through gimbal angles (the same sine
on each, rad) with ``R_base = Rx(ax)·Ry(ay)·Rz(az)``. A 6 × 4 table gives one row per axis
(x, y, z, ax, ay, az).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.aaria.dh import KinematicChain
from aaria_pin.core.oscillation import (
    BASE_COLUMNS,
    JOINT_COLUMNS,
    base_motion,
    default_base_table,
    row_span,
    validate_base_table,
)
from aaria_pin.core.se3 import Array
from aaria_pin.core.tables import finite_table
from aaria_pin.core.trajectory import JointTrajectory, sine_motion
from aaria_pin.errors import TableError

__all__ = [
    "BASE_COLUMNS",
    "JOINT_COLUMNS",
    "base_motion",
    "default_base_table",
    "default_joint_table",
    "joint_trajectory",
    "validate_base_table",
    "validate_joint_table",
]


def validate_joint_table(table: ArrayLike, chain: KinematicChain) -> Array:
    """Check a joint oscillation table against a chain's joints and ranges.

    Args:
        table: 8 × 5 joint oscillation table
        chain: the Aaria chain it drives

    Returns:
        The table as a float array (a copy).

    Raises:
        TableError: wrong shape, a non-finite value, a negative frequency, or a module whose
            motion leaves its range.
    """
    what = "joint oscillation table"
    arr = finite_table(table, JOINT_COLUMNS, what, rows=(8,))
    for joint in chain.joints:
        row = joint.module - 1
        if arr[row, 3] < 0:
            raise TableError(
                f"{what}: row {row + 1}, column 4 (frequency) is {arr[row, 3]:g} "
                "rad/s; allowed: >= 0",
                parameter="joint_table",
            )
        span = row_span(arr[row], joint.kind)
        if span.leaves(joint.lower, joint.upper):
            raise TableError(
                f"{what}: row {row + 1} ({joint.kind} module {joint.module}) moves over "
                f"[{span.low:.4g}, {span.high:.4g}] {span.unit}; allowed: within its range "
                f"[{joint.lower:.4g}, {joint.upper:.4g}] {span.unit}",
                parameter="joint_table",
            )
    return arr


def joint_trajectory(table: ArrayLike, chain: KinematicChain, time: Array) -> JointTrajectory:
    """Joint motions of a chain's modules from a joint oscillation table.

    Args:
        table: 8 × 5 joint oscillation table
        chain: the Aaria chain
        time: sample times [s]

    Returns:
        The trajectory, one column per actuated joint (module order).
    """
    arr = validate_joint_table(table, chain)
    rows = np.array([joint.module - 1 for joint in chain.joints])
    prismatic = np.array([joint.kind == "prismatic" for joint in chain.joints])
    amplitude = np.where(prismatic, arr[rows, 1], arr[rows, 0])
    q, qd, qdd = sine_motion(amplitude, arr[rows, 2], arr[rows, 3], arr[rows, 4], time)
    return JointTrajectory(time, q, qd, qdd)


def default_joint_table(chain: KinematicChain) -> Array:
    """A joint oscillation table that moves every module well within its range.

    Revolute module i: amplitude 0.6 rad; prismatic module i: prismatic amplitude 40 % of its
    rail length (so it spans 80 % of its range); no bias; frequency ``0.8 + 0.3·i`` rad/s;
    phase ``0.5·i`` rad. Rows of empty modules, the tool and the base stay zero.
    """
    table = np.zeros((8, 5))
    for joint in chain.joints:
        i = joint.module
        revolute = joint.kind == "revolute"
        amplitude = 0.6 if revolute else 0.0
        prismatic_amplitude = 0.0 if revolute else 0.4 * (joint.upper - joint.lower)
        table[i - 1] = [amplitude, prismatic_amplitude, 0.0, 0.8 + 0.3 * i, 0.5 * i]
    return table
