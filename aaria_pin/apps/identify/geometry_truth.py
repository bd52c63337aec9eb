"""The errors of an identified table against the truth a simulated record holds.

The tool tip's position over the run and the joint axes come from an independent forward
kinematics (Pinocchio, :func:`~aaria_pin.core.kinematics.trajectory_signals`) of the estimated
and the true table: DH tables are not unique (the same arm has several), so trajectories and
axes are compared, not table entries.
"""

from __future__ import annotations

import numpy as np

from aaria_pin.apps.identify.geometry_model import ArmLayout
from aaria_pin.apps.identify.geometry_result import TruthErrors
from aaria_pin.core.record import RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.errors import TableError

__all__ = ["sigma_coverage", "truth_errors"]

_WITHIN = 2.0  # [σ] a parameter's estimate this close to the truth is covered


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


def sigma_coverage(
    true_table: Array, layout: ArmLayout, estimates: Array, sigmas: Array
) -> dict[str, tuple[int, int]]:
    """Per DH parameter kind, the determined parameters within 2σ of the truth, and their count.

    The true value of a module's ``alpha``, ``d`` (revolute) or ``theta`` (prismatic) and ``a``
    is the true table's entry, of ``a7`` its tool row's length; angles are compared modulo a
    turn. Parameters the data do not determine (σ NaN) are left out. (Where the true table is
    another of the arm's equivalent tables than the estimate's, e.g. a revolute module with a
    true ``theta``, an entry can differ by the equivalence, not by the noise: counted as is.)

    Args:
        true_table: the true 8 × 5 table
        layout: the arm's modules
        estimates: the parameter vector
        sigmas: its standard deviations
    """
    truth = np.empty(layout.n_dh)
    kinds: list[str] = []
    for index, (module, kind) in enumerate(zip(layout.modules, layout.kinds, strict=True)):
        row = true_table[module - 1]
        second = ("d", row[3]) if kind == "revolute" else ("theta", row[2])
        truth[3 * index : 3 * index + 3] = [row[0], second[1], row[1]]
        kinds += ["alpha", second[0], "a"]
    truth[-1] = true_table[6, 1]
    kinds.append("a7")
    error = estimates[: layout.n_dh] - truth
    angular = np.array([k in ("alpha", "theta") for k in kinds])
    error[angular] = (error[angular] + np.pi) % (2 * np.pi) - np.pi
    counted = np.isfinite(sigmas[: layout.n_dh])
    within = np.abs(error) <= _WITHIN * np.where(counted, sigmas[: layout.n_dh], 0.0)
    coverage: dict[str, tuple[int, int]] = {}
    for kind in ("alpha", "d", "theta", "a", "a7"):
        chosen = counted & np.array([k == kind for k in kinds])
        if chosen.any():
            coverage[kind] = (int(np.sum(within & chosen)), int(np.sum(chosen)))
    return coverage


def truth_errors(
    record: RunRecord, table: Array, fitted: tuple[ArmLayout, Array, Array] | None = None
) -> TruthErrors | None:
    """The errors of an estimated table against the record's true one (``senSenDH``).

    Args:
        record: the run, its true table in ``tables["senSenDH"]``
        table: the estimated 8 × 5 table
        fitted: the layout, the parameter vector and its σ, for :func:`sigma_coverage`

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
    coverage = {} if fitted is None else sigma_coverage(true_table, *fitted)
    return TruthErrors(
        true_types,
        right,
        float(np.sqrt(np.mean(error**2))),
        float(np.max(error)),
        angles,
        coverage,
    )
