"""The errors of an identified table against the truth a simulated record holds.

The tool tip's position over the run and the joint axes come from an independent forward
kinematics (Pinocchio, :func:`~aaria_pin.core.kinematics.trajectory_signals`) of the estimated
and the true table: DH tables are not unique (the same arm has several), so trajectories and
axes are compared, not table entries.
"""

from __future__ import annotations

import numpy as np

from aaria_pin.apps.identify.geometry_result import TruthErrors
from aaria_pin.core.record import RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.errors import TableError

__all__ = ["truth_errors"]


def _tool_and_axes(table: Array, q: Array) -> tuple[Array, dict[int, Array]]:
    """Tool-tip positions and joint axes in the base frame by Pinocchio (independent of the fit)."""
    from aaria_pin.aaria.dh_robot import build_dh_robot
    from aaria_pin.core.kinematics import trajectory_signals
    from aaria_pin.core.trajectory import BaseMotion, JointTrajectory

    robot = build_dh_robot(table)
    model = robot.model()
    columns = [m - 1 for m in robot.chain.modules]
    values = np.ascontiguousarray(q[:, columns])
    zeros = np.zeros_like(values)
    frames = ["tool_tip", *(f"link{m}" for m in robot.chain.modules)]
    n = q.shape[0]
    _, poses = trajectory_signals(
        model,
        BaseMotion.resting(n),
        JointTrajectory(np.arange(n, dtype=float), values, zeros, zeros),
        (),
        frames,
    )
    axes = {m: poses[:, 1 + k, :3, 2] for k, m in enumerate(robot.chain.modules)}
    return poses[:, 0, :3, 3], axes


def truth_errors(record: RunRecord, table: Array) -> TruthErrors | None:
    """The errors of an estimated table against the record's true one (``senSenDH``).

    Args:
        record: the run, its true table in ``tables["senSenDH"]``
        table: the estimated 8 × 5 table

    Returns:
        The errors, or None when the record holds no true table.
    """
    true_table = record.tables.get("senSenDH")
    if true_table is None or np.shape(true_table) != (8, 5):
        return None
    true_table = np.asarray(true_table, dtype=float)
    true_types = tuple(int(t) for t in true_table[:6, 4])
    right = tuple(int(table[m, 4]) == true_types[m] for m in range(6))
    try:
        tip_est, axes_est = _tool_and_axes(table, record.q)
    except TableError:  # a length left negative: no arm to compare
        return TruthErrors(true_types, right, float("nan"), float("nan"), {})
    tip_true, axes_true = _tool_and_axes(true_table, record.q)
    error = np.linalg.norm(tip_est - tip_true, axis=1)
    angles = {
        m: float(np.max(np.arccos(np.clip(np.sum(axes_est[m] * axes_true[m], axis=1), -1, 1))))
        for m in axes_est
        if m in axes_true
    }
    return TruthErrors(
        true_types,
        right,
        float(np.sqrt(np.mean(error**2))),
        float(np.max(error)),
        angles,
    )
