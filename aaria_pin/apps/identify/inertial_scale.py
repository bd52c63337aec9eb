"""Each joint's torque per ampere ``k_t·N`` checked against the base wrench.

Motor currents give the joint torques only through ``k_t·N``
(:mod:`~aaria_pin.apps.identify.inertial_torques`), and a joint row ``κ·i = Y·π + F·φ`` alone
does not fix ``κ``: scaling ``κ``, the bodies and the friction together fits as well. The base
wrench (a load cell under the mount, in newtons, no ``k_t`` in it) does fix the bodies, and so
each joint's ``κ``. With ``τ̂ = κ_given·i`` the torques fitted, the true ``κ = c·κ_given`` gives
``c·τ̂ = Y·π + F·φ``, that is ``τ̂ = Y·π + F·φ + (1 − c)·τ̂``: one more column per joint (its own
measured torque, on its own rows) whose coefficient ``d = 1 − c`` is estimated with the
inertial parameters, by least squares corrected for the noise that column shares with the
measurements (:func:`torque_scale`). A scale ``c`` off 1 by more than three of its σ and 1 %
says the ``torque_constant`` or ``gear_ratio`` given is wrong, in one line
(:func:`scale_line`). On ur5 and aaria-fig2 (30 s, default current sensors) σ is 0.01–0.03 %
on the arms' joints and 0.2–33 % on ur5's wrists, whose torque is mostly their own friction
and armature (docs/guide/identify-dynamics.md).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from aaria_pin.core.se3 import Array

__all__ = ["SCALE_TOLERANCE", "scale_line", "scale_off", "torque_scale"]

SCALE_TOLERANCE = 0.01
"""Relative error of ``k_t·N`` under which a scale is never called wrong (a data sheet's ±1 %)."""


def torque_scale(
    R: Array, independent: Sequence[int], scale_columns: Sequence[int], noise: Array, dof: int
) -> tuple[Array, Array]:
    """Each joint's ``c`` (true ``k_t·N`` over the given) and its σ, from a fit's factor.

    The column ``T`` holds the noise that ``y`` holds: plain least squares would fit that
    noise with ``d`` (towards ``c = 0`` on a joint whose torque the friction and armature
    explain almost alone: a wrist). The normal equations are corrected by the noise's known
    sum of squares (``samples·σ²`` off ``TᵀT`` and ``Tᵀy``; the corrected least squares of
    errors in variables), which leaves ``c`` unbiased and its σ honest.

    Args:
        R: the triangular factor of the weighted ``[W | T | y]`` (``T`` each joint's measured
            torque on its own rows), its last column ``y``
        independent: the columns of ``W`` of the base parameters
        scale_columns: the columns of ``T``, one per joint
        noise: each ``T`` column's noise, 1σ per sample, in the weighted units, times
            √samples (the noise's root sum of squares)
        dof: the fit's degrees of freedom (rows − parameters)

    Returns:
        ``c`` per joint and its standard deviation (NaN where the data do not determine it).
    """
    columns = [*independent, *scale_columns]
    A = R[:, columns]
    norms = np.linalg.norm(A, axis=0)
    unit = np.where(norms > 0, norms, 1.0)
    A = A / unit
    k = len(scale_columns)
    G = A.T @ A
    b = A.T @ R[:, -1]
    own = (noise / unit[-k:]) ** 2  # the noise's sum of squares, in T's unit columns
    G[-k:, -k:] -= np.diag(own)
    b[-k:] -= noise**2 / unit[-k:]
    nan = np.full(k, np.nan)
    eigenvalues = np.linalg.eigvalsh(G)
    if eigenvalues[0] <= 1e-10 * eigenvalues[-1]:
        return nan, nan.copy()  # the load cell does not fix the bodies every joint sees
    inverse = np.linalg.inv(G)
    solution = inverse @ b
    residual = A @ solution - R[:, -1]
    variance = float(residual @ residual) / max(dof - k, 1)
    spread = np.diag(inverse)[-k:]
    # the column's own noise adds (σ²·N)·2σ²/(what of T the rest does not explain) to the
    # estimate's variance (the noise's square in TᵀT): large where T is mostly noise
    std = np.sqrt(variance * spread * (1 + 2 * own * spread)) / unit[-k:]
    return 1.0 - solution[-k:] / unit[-k:], std


def scale_off(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The joints whose ``k_t·N`` the base wrench calls wrong: ``|c − 1|`` above 3σ and 1 %.

    Args:
        rows: ``{"joint", "scale", "std"}`` per joint (:func:`torque_scale`'s, as reported;
            ``std`` None: not determined)
    """
    return [
        row
        for row in rows
        if row["std"] is not None and abs(row["scale"] - 1) > max(3 * row["std"], SCALE_TOLERANCE)
    ]


def scale_line(rows: list[dict[str, Any]]) -> str:
    """One line on the ``k_t·N`` given: which joints' the base wrench calls wrong, or none.

    Args:
        rows: ``{"joint", "scale", "std"}`` per joint (as :func:`scale_off`)
    """
    off = scale_off(rows)
    if off:
        shown = ", ".join(f"{row['joint']} {row['scale']:.4g} ± {row['std']:.2g}" for row in off)
        return (
            f"torque constant × gear ratio is off: the base wrench gives {shown} times the one "
            "given; allowed: within 1 % (check torque_constant and gear_ratio)"
        )
    stds = [row["std"] for row in rows if row["std"] is not None]
    if not stds:
        return "torque constant × gear ratio: not determined by the base wrench"
    return (
        "torque constant × gear ratio: the base wrench agrees with the one given on every joint "
        f"(largest σ {100 * max(stds):.2g} %)"
    )
