"""Uniform B-splines as sparse design matrices: the continuous-time signals of a rigid-body fit.

A signal ``y(t) = Σ_j c_j·B_j(t)`` on uniform knots ``start + k·interval`` is linear in its
coefficients, so its values (and derivatives) at any instants are ``N @ c`` with ``N`` a sparse
(instants × coefficients) matrix, four entries a row for the cubic spline, two for the linear
one. :func:`spline_basis` builds ``N``; :mod:`~aaria_pin.apps.identify.rigid_fit` fits the body's
angular velocity and specific force (cubic) and the IMU biases (linear, or constant) with them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from aaria_pin.core.se3 import Array

if TYPE_CHECKING:
    from scipy import sparse

__all__ = ["coefficient_count", "fit_spline", "spline_basis"]


def coefficient_count(duration: float, interval: float, degree: int) -> int:
    """The coefficients of a degree-``degree`` spline spanning ``duration`` [s] on ``interval``.

    A span shorter than ``interval`` (a bias held constant over the run) gives one linear
    coefficient, i.e. a constant (degree 1 only).
    """
    segments = max(1, int(np.ceil(duration / interval - 1e-9)))
    if degree == 1 and interval >= duration:
        return 1
    return segments + degree


def _cubic_weights(u: Array, derivative: int) -> Array:
    """The four uniform cubic B-spline weights at fractions ``u`` of a segment, (n, 4)."""
    if derivative == 0:
        columns = [(1 - u) ** 3, 3 * u**3 - 6 * u**2 + 4, -3 * u**3 + 3 * u**2 + 3 * u + 1, u**3]
        return np.stack(columns, axis=1) / 6.0
    if derivative == 1:
        columns = [-((1 - u) ** 2), 3 * u**2 - 4 * u, -3 * u**2 + 2 * u + 1, u**2]
        return np.stack(columns, axis=1) / 2.0
    return np.stack([1 - u, 3 * u - 2, 1 - 3 * u, u], axis=1)


def spline_basis(
    times: Array, start: float, interval: float, count: int, degree: int, derivative: int = 0
) -> sparse.csr_matrix:
    """The design matrix of a uniform B-spline at ``times``: ``N[i, j] = d^k B_j(t_i)/dt^k``.

    Args:
        times: (n,) instants [s], within ``[start, start + (count - degree)·interval]`` (those
            outside are held to the first or last segment: the spline extrapolated)
        start: the first knot of the span [s]
        interval: the knot spacing [s]
        count: the number of coefficients (:func:`coefficient_count`)
        degree: 3 (cubic: values and derivatives 0–2) or 1 (linear: values; one coefficient
            is a constant)
        derivative: the derivative ``k`` (cubic only)

    Returns:
        A sparse (n, count) matrix.
    """
    from scipy import sparse

    t = np.asarray(times, dtype=np.float64)
    n = t.size
    if degree == 1 and count == 1:
        return sparse.csr_matrix(np.ones((n, 1)))
    segments = count - degree
    position = (t - start) / interval
    segment = np.clip(np.floor(position), 0, segments - 1).astype(np.int64)
    u = position - segment
    if degree == 1:
        weights = np.stack([1 - u, u], axis=1)
    else:
        weights = _cubic_weights(u, derivative) / interval**derivative
    width = degree + 1
    rows = np.repeat(np.arange(n), width)
    cols = (segment[:, None] + np.arange(width)[None, :]).ravel()
    return sparse.csr_matrix((weights.ravel(), (rows, cols)), shape=(n, count))


def fit_spline(times: Array, values: Array, start: float, interval: float, count: int) -> Array:
    """The least-squares cubic B-spline through samples: its coefficients, one column each.

    Args:
        times: (n,) instants [s]
        values: (n, c) samples
        start: the first knot [s]
        interval: the knot spacing [s]
        count: the coefficients (:func:`coefficient_count`)

    Returns:
        (count, c) coefficients (a vanishing ridge keeps a knot without samples at 0).
    """
    from scipy import sparse
    from scipy.sparse.linalg import splu

    basis = spline_basis(times, start, interval, count, 3)
    normals = (basis.T @ basis + 1e-9 * sparse.identity(count)).tocsc()
    return np.asarray(splu(normals).solve(np.asarray(basis.T @ values)))
