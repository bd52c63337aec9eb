"""Each joint's torque per ampere ``k_t·N`` checked against the base wrench.

Motor currents give the joint torques only through ``k_t·N``
(:mod:`~aaria_pin.apps.identify.inertial_torques`), and a joint row ``κ·i = Y·π + F·φ`` alone
does not fix ``κ``: scaling ``κ``, the bodies and the friction together fits as well. The base
wrench (a load cell under the mount, in newtons, no ``k_t`` in it) does fix the bodies, and so
each joint's ``κ``. With ``τ̂ = κ_given·i`` the torques fitted and the true ``κ = c·κ_given``,
joint ``j``'s rows are ``τ̂ = (Y·π + F·φ)/c + o``, ``o`` the joint's constant current offset
times ``κ_given`` (a drive's zero: without it a constant offset would read as a scale), the
base wrench's rows ``w = W·π``: :func:`torque_scale` fits ``1/c`` and ``o`` of every joint with
the bodies (Gauss-Newton; the noise is in the measurements alone), and its σ is the sandwich of
each signal's own residual variance. A scale ``c`` off 1 by more than three of its σ and 1 %
says the ``torque_constant`` or ``gear_ratio`` given is wrong, in one line (:func:`scale_line`);
a joint whose σ is above 1 % is "not checked". The friction must be fitted (the currents hold
it): without it ``c`` would take it up, and nothing is checked. Its σ, false alarms and the
detection of a 3 % wrong ``k_t`` over 60 ur5 runs: ``python benchmarks/bench_torque_scale.py``
(docs/guide/identify-dynamics.md).
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
    factors: Sequence[Array], first: int, independent: Sequence[int], samples: int
) -> tuple[Array, Array]:
    """Each joint's ``c`` (true ``k_t·N`` over the given) and its σ, from the signals' factors.

    Joint ``j``'s rows are ``y = g·(W·β) + o + ε`` (``g = 1/c``: the torque the currents give
    over the true one; ``o`` its constant current offset times ``k_t·N``; the friction columns
    in ``W`` are scaled by ``g`` with the bodies, which only renames their coefficients); the
    base wrench's rows are ``y = W·β + ε``, no ``g`` in them. This bilinear least squares is
    solved by Gauss-Newton from ``g = 1`` on each signal's ``XᵀX`` (``X = [W | 1 | y]``), the
    noise being in ``y`` alone (no measured torque as a regressor: unbiased, also on a joint
    whose torque is mostly its own friction). Its covariance is the sandwich of the signals'
    own residual variances (the base wrench's and each joint's noise differ), so σ holds when
    the weights are wrong.

    Args:
        factors: each signal's triangular factor ``R`` of its weighted ``[W | 1… | y]`` (one
            constant column per joint after ``W``, each nonzero on its joint's rows only),
            the base wrench's signals first; ``y`` the last column
        first: the number of base wrench signals (the joints' first signal)
        independent: the columns of ``W`` of the base parameters
        samples: the rows per signal

    Returns:
        ``c`` per joint and its standard deviation (NaN where the data do not determine it).
    """
    k = len(factors) - first
    width = factors[0].shape[1]
    p = width - 1 - k  # W's columns
    m = len(independent)
    grams = []  # per signal: XᵀX = RᵀR of [W_ind | 1 (its joint's; the wrench's: y, unused) | y]
    for s, f in enumerate(factors):
        X = f[:, [*independent, p + s - first if s >= first else width - 1, width - 1]]
        grams.append(X.T @ X)
    n_theta = m + 2 * k  # β, then g per joint, then the offset per joint
    nan = np.full(k, np.nan)
    theta = np.zeros(n_theta)
    theta[m : m + k] = 1.0
    for iteration in range(50):
        JJ, Jr, _ = _normal(grams, theta, first, m, k)
        if iteration == 0:  # β and the offsets with g = 1 (linear): a start where g matters
            free = np.r_[0:m, m + k : n_theta]
            JJ, Jr = JJ[np.ix_(free, free)], Jr[free]
        else:
            free = np.arange(n_theta)
        scale = np.sqrt(np.maximum(np.diag(JJ), np.finfo(float).tiny))
        H = JJ / np.outer(scale, scale)
        eigenvalues = np.linalg.eigvalsh(H)
        if not eigenvalues[0] > 1e-10 * eigenvalues[-1]:
            return nan, nan.copy()  # the load cell does not fix the bodies every joint sees
        step = -np.linalg.solve(H, Jr / scale) / scale
        theta[free] += step
        if iteration and bool(np.all(np.abs(step) <= 1e-12 + 1e-10 * np.abs(theta))):
            break
    JJ, _, parts = _normal(grams, theta, first, m, k)
    inverse = np.linalg.inv(JJ)
    middle = np.zeros_like(JJ)
    dof = max(samples - n_theta / len(factors), 1.0)  # each signal's share of the parameters
    for JsJs, residual in parts:
        middle += JsJs * residual / dof  # the signal's own residual variance
    covariance = inverse @ middle @ inverse
    g = theta[m : m + k]
    g_std = np.sqrt(np.maximum(np.diag(covariance)[m : m + k], 0.0))
    return 1.0 / g, g_std / g**2


def _normal(
    grams: list[Array], theta: Array, first: int, m: int, k: int
) -> tuple[Array, Array, list[tuple[Array, float]]]:
    """Gauss-Newton's ``JᵀJ`` and ``Jᵀr`` at ``theta``, and each signal's ``JₛᵀJₛ`` and ``rₛᵀrₛ``.

    Args:
        grams: each signal's Gram of ``[W_ind | 1 | y]``
        theta: ``β``, ``g`` per joint, the offset per joint
        first: the base wrench's signals
        m: the base parameters
        k: the joints
    """
    n = len(theta)
    beta = theta[:m]
    JJ, Jr = np.zeros((n, n)), np.zeros(n)
    parts = []
    for s, G in enumerate(grams):
        # the residual r = y − X·v and its Jacobian J = X·M (columns of X: W_ind, 1, y)
        M = np.zeros((m + 2, n))
        v = np.zeros(m + 2)
        if s < first:
            M[:m, :m] = np.eye(m)
            v[:m] = beta
        else:
            j = s - first
            g = theta[m + j]
            M[:m, :m] = g * np.eye(m)
            M[:m, m + j] = beta
            M[m, m + k + j] = 1.0
            v[:m], v[m] = g * beta, theta[m + k + j]
        v[m + 1] = -1.0  # r = −X·v with y's coefficient −1
        Gv = G @ v
        JsJs = M.T @ G @ M
        JJ += JsJs
        Jr += M.T @ Gv  # Jᵀ(y − Xv) = −MᵀG v with v holding −1 at y: r = −X·v
        parts.append((JsJs, float(v @ Gv)))
    return JJ, Jr, parts


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
    """One line on the ``k_t·N`` given: the joints the base wrench calls wrong, or agrees on.

    A joint whose σ is above :data:`SCALE_TOLERANCE` (or not determined) and that is not
    called wrong is named "not checked": the data cannot tell a data sheet's error there.

    Args:
        rows: ``{"joint", "scale", "std"}`` per joint (as :func:`scale_off`)
    """
    off = scale_off(rows)
    unchecked = [
        row["joint"]
        for row in rows
        if row not in off and (row["std"] is None or row["std"] > SCALE_TOLERANCE)
    ]
    if off:
        shown = ", ".join(f"{row['joint']} {row['scale']:.4g} ± {row['std']:.2g}" for row in off)
        return (
            f"torque constant × gear ratio is off: the base wrench gives {shown} times the one "
            "given; allowed: within 1 % (set torque_constant and gear_ratio first: the friction "
            "was fitted with these)"
        )
    agree = [row for row in rows if row["joint"] not in unchecked]
    if not agree:
        return "torque constant × gear ratio: not checked, the base wrench does not determine it"
    stds = [row["std"] for row in agree]
    line = (
        f"torque constant × gear ratio: the base wrench agrees with the one given on "
        f"{', '.join(row['joint'] for row in agree)} (largest σ {100 * max(stds):.2g} %)"
    )
    if unchecked:
        line += f"; not checked (σ above {100 * SCALE_TOLERANCE:g} %): {', '.join(unchecked)}"
    return line
