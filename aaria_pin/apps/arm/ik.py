"""Planar two-link IK of the arm (the report's vector method) and its no-swing-through rule.

Seen from above, the upper arm is the vector **a** (length A) from the pillar's axis to the
elbow and the forearm the vector **b** (length B) from the elbow to the wrist; a target **x**
is reached when ``a + b = x``, ``|a| = A``, ``|b| = B`` (report, section 4.2.8). The elbow lies
on both circles |a| = A and |x - a| = B: its component along **x** is
``p = (r² + A² - B²) / (2r)`` and across it ``±h``, ``h = √(A² - p²)``; the two signs are the
two mirrored solutions (mirrored about **x**). The angles are ``α = atan2(a_y, a_x)`` (shoulder,
from the world x axis) and ``β = atan2(b_y, b_x) - α`` (elbow, relative to the upper arm),
wrapped into [-π, π]. The branch with the elbow clockwise of **x** has β ≥ 0 ("left", the
forearm turned counter-clockwise from the upper arm), its mirror image β ≤ 0 ("right").

Targets are reachable on the closed annulus ``|A - B| ≤ r ≤ A + B``; on its rims the two
branches meet (β = 0 outside, β = ±π inside, the forearm folded back over the upper arm).

**No swing through the pillar** (report, section 4.2.9): the forearm points at the pillar when
β = ±π, so it must never turn through ±π. It may turn at most ``π - β0`` counter-clockwise and
``π + β0`` clockwise from its current angle β0: the direction is the one that keeps it on its
side, i.e. the move is ``β1 - β0`` with both in [-π, π], never wrapped. (The report's MATLAB
code has ``angles(2) = 360 - angles(2)`` where ``angles(2) - 360`` is meant in the β0 > 0
case; for goals in (-180°, 180°], the only ones its IK gives, that line is never reached.) The
shoulder turns about the pillar itself and takes the shorter way.
"""

from __future__ import annotations

from typing import Literal, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = [
    "ANNULUS_TOLERANCE",
    "BRANCHES",
    "PlanarAngles",
    "elbow_move",
    "plan_planar_move",
    "planar_fk",
    "planar_ik",
    "shoulder_move",
    "wrap",
]

ANNULUS_TOLERANCE = 1e-9
"""How far [m] outside the annulus a target may lie and still be taken as on its rim."""

BRANCHES = ("left", "right")
"""IK branches: the forearm turned counter-clockwise (β ≥ 0) or clockwise (β ≤ 0)."""


class PlanarAngles(NamedTuple):
    """Shoulder and elbow angles.

    Attributes:
        alpha: shoulder angle from the world x axis [rad]
        beta: elbow angle, the forearm relative to the upper arm [rad], in [-π, π]
    """

    alpha: Array
    beta: Array


def wrap(angle: ArrayLike) -> Array:
    """Angles wrapped into [-π, π) [rad]."""
    return np.asarray((np.asarray(angle, dtype=float) + np.pi) % (2.0 * np.pi) - np.pi)


def _lengths(a: float, b: float) -> None:
    if not (np.isfinite(a) and np.isfinite(b) and a > 0 and b > 0):
        raise ParameterError(
            f"link lengths A = {a!r} m, B = {b!r} m; allowed: finite and > 0",
            parameter="a" if not (np.isfinite(a) and a > 0) else "b",
            value=(a, b),
        )


def planar_fk(alpha: ArrayLike, beta: ArrayLike, a: float, b: float) -> Array:
    """The wrist's position in the plane, ``a + b`` (..., 2) [m].

    Args:
        alpha: shoulder angles [rad]
        beta: elbow angles [rad]
        a: upper arm length A [m]
        b: forearm length B [m]
    """
    al = np.asarray(alpha, dtype=float)
    ab = al + np.asarray(beta, dtype=float)
    return np.stack([a * np.cos(al) + b * np.cos(ab), a * np.sin(al) + b * np.sin(ab)], axis=-1)


def planar_ik(x: ArrayLike, y: ArrayLike, a: float, b: float) -> tuple[PlanarAngles, PlanarAngles]:
    """Both mirrored solutions of ``a + b = (x, y)``, ``|a| = A``, ``|b| = B``.

    Args:
        x: target x [m] (any shape, broadcast with y)
        y: target y [m]
        a: upper arm length A [m]
        b: forearm length B [m]

    Returns:
        The "left" solution (β ≥ 0) and the "right" one (β ≤ 0); on the outer rim both have
        β = 0, on the inner rim β = +π and -π.

    Raises:
        ParameterError: a length that is not > 0, a target that is not finite, or one outside
            the annulus ``|A - B| ≤ r ≤ A + B`` (named in the message), beyond
            :data:`ANNULUS_TOLERANCE`.
    """
    _lengths(a, b)
    X, Y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    if not (np.all(np.isfinite(X)) and np.all(np.isfinite(Y))):
        raise ParameterError(
            "IK target holds NaN or inf; allowed: finite coordinates [m]",
            parameter="x" if not np.all(np.isfinite(X)) else "y",
        )
    r = np.hypot(X, Y)
    inner, outer = abs(a - b), a + b
    bad = (r < inner - ANNULUS_TOLERANCE) | (r > outer + ANNULUS_TOLERANCE) | (r == 0.0)
    if np.any(bad):
        k = np.argwhere(np.atleast_1d(bad))[0]
        xb, yb, rb = (float(np.atleast_1d(v)[tuple(k)]) for v in (X, Y, r))
        raise ParameterError(
            f"target ({xb:.6g}, {yb:.6g}) m at r = {rb:.6g} m is outside the reachable annulus"
            f" {inner:.6g} m <= r <= {outer:.6g} m (|A - B| to A + B, A = {a:g} m,"
            f" B = {b:g} m)",
            parameter="x",
            value=(xb, yb),
        )
    rc = np.clip(r, inner, outer)
    ux, uy = X / r, Y / r  # unit vector towards the target
    p = (rc * rc + a * a - b * b) / (2.0 * rc)
    h = np.sqrt(np.clip(a * a - p * p, 0.0, None))
    solutions = []
    for sign in (-1.0, 1.0):  # elbow clockwise of x (forearm turns left), then counter-clockwise
        ax = p * ux - sign * h * uy
        ay = p * uy + sign * h * ux
        alpha = np.arctan2(ay, ax)
        beta = wrap(np.arctan2(Y - ay, X - ax) - alpha)
        # On the rims the two coincide: put β = 0 and β = ±π on the branch's own side.
        beta = np.where(np.abs(beta) >= np.pi - 1e-12, -sign * np.pi, beta)
        beta = -sign * np.abs(beta)
        solutions.append(PlanarAngles(np.asarray(alpha), np.asarray(beta)))
    return solutions[0], solutions[1]


def shoulder_move(alpha0: ArrayLike, alpha1: ArrayLike) -> Array:
    """The shoulder's turn from α0 towards α1 the shorter way, in [-π, π) [rad]."""
    return wrap(np.asarray(alpha1, dtype=float) - np.asarray(alpha0, dtype=float))


def elbow_move(beta0: ArrayLike, beta1: ArrayLike) -> Array:
    """The elbow's turn from β0 to β1 that never swings the forearm through the pillar.

    Both angles are taken in [-π, π] (β = ±π is the forearm pointing at the pillar); the turn is
    ``β1 - β0``, so the forearm sweeps only angles between them and never crosses ±π: at most
    ``π - β0`` counter-clockwise and ``π + β0`` clockwise (report, section 4.2.9).

    Args:
        beta0: current elbow angles [rad], in [-π, π]
        beta1: goal elbow angles [rad], in [-π, π]

    Returns:
        The turn [rad], in (-2π, 2π); ``β0 + turn`` is β1 or, for β1 = ±π, the one on β0's side.

    Raises:
        ParameterError: an angle outside [-π, π] (it would already be past the pillar).
    """
    b0, b1 = np.asarray(beta0, dtype=float), np.asarray(beta1, dtype=float)
    for name, value in (("current", b0), ("goal", b1)):
        if not np.all(np.abs(value) <= np.pi + 1e-12):
            raise ParameterError(
                f"{name} elbow angle {np.max(np.abs(value)):.6g} rad; allowed: [-pi, pi]"
                " (beyond, the forearm has swung through the pillar)",
                parameter="beta0" if name == "current" else "beta1",
            )
    # A goal of ±π is one pose (the forearm folded over the upper arm): reach it on the side
    # the forearm is on, without a full turn.
    b1 = np.where((np.abs(b1) >= np.pi) & (b0 != 0), np.copysign(np.pi, b0), b1)
    return np.asarray(b1 - b0)


def plan_planar_move(
    alpha0: float,
    beta0: float,
    x: float,
    y: float,
    a: float,
    b: float,
    branch: Literal["left", "right", "nearest"] = "nearest",
) -> PlanarAngles:
    """Goal shoulder and elbow angles for a move to (x, y), continuous from (α0, β0).

    The returned angles are the start plus the turns of :func:`shoulder_move` and
    :func:`elbow_move`, so a joint-space interpolation between start and goal obeys the
    no-swing-through rule.

    Args:
        alpha0: current shoulder angle [rad] (any value: the shoulder turns freely)
        beta0: current elbow angle [rad], in [-π, π]
        x: target x [m]
        y: target y [m]
        a: upper arm length A [m]
        b: forearm length B [m]
        branch: ``"left"`` (β ≥ 0), ``"right"`` (β ≤ 0) or ``"nearest"`` (the one with the
            smaller largest joint turn)

    Returns:
        Goal angles (α may lie outside [-π, π)).
    """
    if branch not in (*BRANCHES, "nearest"):
        raise ParameterError(
            f"IK branch {branch!r}; allowed: left, right, nearest", parameter="branch", value=branch
        )
    left, right = planar_ik(x, y, a, b)
    options = {"left": left, "right": right}
    moves = {
        name: (float(shoulder_move(alpha0, s.alpha)), float(elbow_move(beta0, s.beta)))
        for name, s in options.items()
    }
    chosen: str = branch
    if branch == "nearest":
        chosen = min(BRANCHES, key=lambda n: (max(abs(moves[n][0]), abs(moves[n][1])), n))
    d_alpha, d_beta = moves[chosen]
    return PlanarAngles(np.asarray(alpha0 + d_alpha), np.asarray(beta0 + d_beta))
