"""Physically consistent inertial parameters: every body's pseudo-inertia positive definite.

A body's ten standard parameters ``[m, h, I]`` (``h = m·c``, ``I`` about the body's origin;
:data:`~aaria_pin.apps.identify.inertial_regressor.INERTIAL_PARAMETERS`) are those of a real
mass distribution exactly when its pseudo-inertia (Wensing, Kim & Slotine 2017)::

    J = [[Σ, h], [hᵀ, m]],   Σ = ½·tr(I)·1 − I   (the second moment of the mass)

is positive semidefinite. The log-Cholesky parametrisation (Rucker & Wensing 2022) writes every
positive-definite ``J`` as ``U·Uᵀ`` with ten unconstrained numbers ``θ = [α, d1, d2, d3, s12,
s23, s13, t1, t2, t3]``::

    U = e^α · [[e^d1, s12, s13, t1], [0, e^d2, s23, t2], [0, 0, e^d3, t3], [0, 0, 0, 1]]

so the least squares over ``θ`` (and the friction and armature, bounded below by 0) is a
smooth unconstrained problem whose every iterate is a physical body. :func:`consistent_fit`
solves it on the triangular factor ``R`` of the weighted ``[W | y]`` (the same objective as the
whole regressor), from the ordinary least squares projected onto the consistent set, with an
analytic Jacobian. Directions the data do not determine are held near the start by a tiny
damping term.
"""

from __future__ import annotations

import numpy as np

from aaria_pin.core.se3 import Array

__all__ = [
    "consistent_fit",
    "log_cholesky",
    "log_cholesky_of",
    "project_consistent",
    "pseudo_inertia",
    "standard_from_pseudo",
]

DAMPING = 1e-7
"""Weight of the pull towards the start, relative to the norm of the measurements' column."""

_SYMMETRIC = ((0, 0), (0, 1), (1, 1), (0, 2), (1, 2), (2, 2))  # Ixx Ixy Iyy Ixz Iyz Izz


def pseudo_inertia(standard: Array) -> Array:
    """The pseudo-inertias of bodies' standard parameters, (B, 10) → (B, 4, 4)."""
    pi = np.atleast_2d(standard)
    inertia = np.zeros((pi.shape[0], 3, 3))
    for k, (i, j) in enumerate(_SYMMETRIC):
        inertia[:, i, j] = inertia[:, j, i] = pi[:, 4 + k]
    J = np.zeros((pi.shape[0], 4, 4))
    trace = np.trace(inertia, axis1=1, axis2=2)
    J[:, :3, :3] = 0.5 * trace[:, None, None] * np.eye(3) - inertia
    J[:, :3, 3] = J[:, 3, :3] = pi[:, 1:4]
    J[:, 3, 3] = pi[:, 0]
    return J


def standard_from_pseudo(J: Array) -> Array:
    """The standard parameters of pseudo-inertias, (B, 4, 4) → (B, 10) (linear in ``J``)."""
    sigma = J[:, :3, :3]
    inertia = np.trace(sigma, axis1=1, axis2=2)[:, None, None] * np.eye(3) - sigma
    out = np.empty((J.shape[0], 10))
    out[:, 0] = J[:, 3, 3]
    out[:, 1:4] = J[:, :3, 3]
    for k, (i, j) in enumerate(_SYMMETRIC):
        out[:, 4 + k] = inertia[:, i, j]
    return out


_UPPER = ((0, 1), (1, 2), (0, 2))  # s12, s23, s13


def _factor(theta: Array) -> Array:
    """``U`` of log-Cholesky parameters, (B, 10) → (B, 4, 4)."""
    U = np.zeros((theta.shape[0], 4, 4))
    for i in range(3):
        U[:, i, i] = np.exp(theta[:, 1 + i])
        U[:, i, 3] = theta[:, 7 + i]
    for k, (i, j) in enumerate(_UPPER):
        U[:, i, j] = theta[:, 4 + k]
    U[:, 3, 3] = 1.0
    return np.exp(theta[:, 0])[:, None, None] * U


def log_cholesky(theta: Array) -> Array:
    """The pseudo-inertias ``U·Uᵀ`` of log-Cholesky parameters, (B, 10) → (B, 4, 4)."""
    U = _factor(np.atleast_2d(theta))
    return np.einsum("bij,bkj->bik", U, U)


def log_cholesky_of(J: Array) -> Array:
    """The log-Cholesky parameters of positive-definite pseudo-inertias, (B, 4, 4) → (B, 10)."""
    flip = J[:, ::-1, ::-1]  # U·Uᵀ with U upper ⇔ the reversed matrix is L·Lᵀ with L lower
    U = np.linalg.cholesky(flip)[:, ::-1, ::-1]
    scale = U[:, 3, 3]
    V = U / scale[:, None, None]
    theta = np.empty((J.shape[0], 10))
    theta[:, 0] = np.log(scale)
    for i in range(3):
        theta[:, 1 + i] = np.log(V[:, i, i])
        theta[:, 7 + i] = V[:, i, 3]
    for k, (i, j) in enumerate(_UPPER):
        theta[:, 4 + k] = V[:, i, j]
    return theta


def project_consistent(standard: Array, floor: float) -> Array:
    """The nearest positive-definite bodies: each pseudo-inertia's eigenvalues raised to ``floor``.

    Args:
        standard: the bodies' standard parameters, (B, 10)
        floor: the smallest eigenvalue kept, > 0 [kg·m²]

    Returns:
        Their standard parameters, (B, 10), every pseudo-inertia's eigenvalues >= ``floor``.
    """
    values, vectors = np.linalg.eigh(pseudo_inertia(standard))
    J = np.einsum("bij,bj,bkj->bik", vectors, np.maximum(values, floor), vectors)
    return standard_from_pseudo(J)


def _standard_jacobian(theta: Array) -> Array:
    """d(standard)/dθ of each body, (B, 10, 10): row a standard parameter, column a θ."""
    B = theta.shape[0]
    U = _factor(theta)
    scale = np.exp(theta[:, 0])
    dU = np.zeros((B, 10, 4, 4))
    dU[:, 0] = U
    for i in range(3):
        dU[:, 1 + i, i, i] = U[:, i, i]
        dU[:, 7 + i, i, 3] = scale
    for k, (i, j) in enumerate(_UPPER):
        dU[:, 4 + k, i, j] = scale
    dJ = np.einsum("bkij,blj->bkil", dU, U)
    dJ = dJ + np.swapaxes(dJ, 2, 3)
    return standard_from_pseudo(dJ.reshape(B * 10, 4, 4)).reshape(B, 10, 10).transpose(0, 2, 1)


def consistent_fit(R: Array, bodies: int, start: Array, max_evaluations: int = 200) -> Array:
    """The physically consistent least squares of ``R[:, :p]·x ≈ R[:, p]`` (module docstring).

    Args:
        R: the triangular factor of the weighted ``[W | y]``, k × (p + 1); the first
            ``10·bodies`` columns are the bodies' standard parameters, the rest (friction,
            armature) are bounded below by 0
        bodies: the number of bodies B
        start: a start, (p,) (any: it is projected onto the consistent set first)
        max_evaluations: the largest number of residual evaluations

    Returns:
        The estimate, (p,): every body's pseudo-inertia positive definite, the rest >= 0.
    """
    import scipy.optimize

    p = R.shape[1] - 1
    inertial = 10 * bodies
    W, y = R[:, :p], R[:, p]
    bodies_start = start[:inertial].reshape(bodies, 10)
    size = float(np.max(np.abs(np.linalg.eigvalsh(pseudo_inertia(bodies_start))), initial=0.0))
    floor = 1e-6 * size if size > 0 else 1e-3  # no body at all: start from small ones
    theta0 = log_cholesky_of(pseudo_inertia(project_consistent(bodies_start, floor)))
    z0 = np.concatenate([theta0.reshape(-1), np.maximum(start[inertial:], 0.0)])
    damping = DAMPING * max(float(np.linalg.norm(y)), 1e-300)

    def standard(z: Array) -> Array:
        theta = z[:inertial].reshape(bodies, 10)
        return np.concatenate([standard_from_pseudo(log_cholesky(theta)).reshape(-1), z[inertial:]])

    def residual(z: Array) -> Array:
        return np.concatenate([W @ standard(z) - y, damping * (z - z0)])

    def jacobian(z: Array) -> Array:
        blocks = _standard_jacobian(z[:inertial].reshape(bodies, 10))
        out = np.empty((W.shape[0] + p, p))
        for b in range(bodies):
            columns = slice(10 * b, 10 * b + 10)
            out[: W.shape[0], columns] = W[:, columns] @ blocks[b]
        out[: W.shape[0], inertial:] = W[:, inertial:]
        out[W.shape[0] :] = damping * np.eye(p)
        return out

    lower = np.concatenate([np.full(inertial, -np.inf), np.zeros(p - inertial)])
    solution = scipy.optimize.least_squares(
        residual,
        z0,
        jac=jacobian,
        bounds=(lower, np.full(p, np.inf)),
        method="trf",
        ftol=1e-10,
        xtol=1e-10,
        gtol=1e-10,
        max_nfev=max_evaluations,
    )
    return standard(solution.x)
