"""The joint least-squares fit of two IMUs on one rigid body (Gauss–Newton on sparse normals).

Unknowns: the body's angular velocity ``w(t)`` and A's specific force ``s(t)``, both in A's
frame, as cubic B-splines (:mod:`~aaria_pin.apps.identify.rigid_spline`); B's rotation ``R``
(``v_A = R·v_B``), B's origin ``r`` in A's frame [m], B's time offset ``δ`` [s] (B's sample
stamped ``t`` is A's instant ``τ = t + δ``); the gyroscope biases of A and B and B's
accelerometer bias relative to A's, as linear B-splines of time (one coefficient: constant).
The measurements, each divided by its block's noise σ::

    A gyro   ω_A(t) = w(t) + b_gA(t)
    A accel  f_A(t) = s(t)                      (A's accelerometer bias is in s)
    B gyro   ω_B(t) = Rᵀ·w(τ) + b_gB(t)
    B accel  f_B(t) = Rᵀ·(s + ẇ×r + w×(w×r))(τ) + b_aB(t)

:func:`gauss_newton` minimises the sum of squares (rotation updated as ``R·exp([Δφ]×)``) with
a vanishing Levenberg damping (``1e-9·diag``) that keeps a direction the data do not determine
(the position along the only axis the body turned about) from breaking the solve; the
covariance of the global parameters is the inverse of the normals' block, solved for them.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from aaria_pin.apps.identify.rigid_spline import spline_basis
from aaria_pin.core.se3 import Array

if TYPE_CHECKING:
    from scipy import sparse
    from scipy.sparse import linalg as sparse_linalg

__all__ = [
    "GLOBALS",
    "FitLayout",
    "FitState",
    "PairData",
    "blockwise",
    "gauss_newton",
    "lever_matrices",
    "linearise",
    "skew_rows",
]

GLOBALS = ("rotation", "position", "time_offset")
"""The global parameters (after the two splines): 3 rotation, 3 position [m], 1 offset [s]."""

DAMPING = 1e-9
"""The Levenberg damping relative to the normals' diagonal."""


@dataclass(frozen=True)
class PairData:
    """Two IMUs' measurements (B's restricted to instants inside A's span).

    Attributes:
        time_a: (nA,) A's stamps [s]
        signals_a: (nA, 6) A's ``[wx wy wz fx fy fz]`` [rad/s, m/s²]
        time_b: (nB,) B's stamps [s]
        signals_b: (nB, 6) B's
    """

    time_a: Array
    signals_a: Array
    time_b: Array
    signals_b: Array


@dataclass(frozen=True)
class FitLayout:
    """The splines' knots: the signals' (cubic) and the biases' (linear, or constant).

    Attributes:
        start: the first knot, A's first stamp [s]
        interval: the signals' knot spacing [s]
        count: the signals' coefficients per axis
        bias_interval: the biases' knot spacing [s]
        bias_count: the biases' coefficients per axis (1: constant)
    """

    start: float
    interval: float
    count: int
    bias_interval: float
    bias_count: int


@dataclass(frozen=True)
class FitState:
    """A point of the fit. Splines' coefficients are (count, 3), biases' (bias_count, 3)."""

    omega: Array
    force: Array
    rotation: Array
    position: Array
    offset: float
    gyro_bias_a: Array
    gyro_bias_b: Array
    accel_bias_b: Array

    def vector_update(self, step: Array, layout: FitLayout) -> FitState:
        """The state moved by a step of the parameter vector (rotation multiplicatively)."""
        from scipy.spatial.transform import Rotation

        k, kb = 3 * layout.count, 3 * layout.bias_count
        parts = np.split(step, np.cumsum([k, k, 3, 3, 1, kb, kb]))
        shaped = [p.reshape(3, -1).T for p in (parts[0], parts[1], parts[5], parts[6], parts[7])]
        turn = Rotation.from_rotvec(parts[2]).as_matrix()
        return replace(
            self,
            omega=self.omega + shaped[0],
            force=self.force + shaped[1],
            rotation=self.rotation @ turn,
            position=self.position + parts[3],
            offset=self.offset + float(parts[4][0]),
            gyro_bias_a=self.gyro_bias_a + shaped[2],
            gyro_bias_b=self.gyro_bias_b + shaped[3],
            accel_bias_b=self.accel_bias_b + shaped[4],
        )


def skew_rows(v: Array) -> Array:
    """``[v]×`` of rows, (n, 3) → (n, 3, 3)."""
    z = np.zeros(v.shape[0])
    x, y, w = v[:, 0], v[:, 1], v[:, 2]
    return np.stack([z, -w, y, w, z, -x, -y, x, z], axis=1).reshape(-1, 3, 3)


def lever_matrices(w: Array, w1: Array) -> Array:
    """``[α]× + [ω]×[ω]×`` per sample, (n, 3, 3): the lever arm's acceleration is it @ r."""
    skew = skew_rows(w)
    return np.asarray(skew_rows(w1) + skew @ skew)


def _stacked(per_sample: Array) -> sparse.csr_matrix:
    """Per-sample (n, 3, c) Jacobians as the (3n, c) rows of axis-major residuals."""
    from scipy import sparse

    return sparse.csr_matrix(np.transpose(per_sample, (1, 0, 2)).reshape(-1, per_sample.shape[2]))


def blockwise(matrices: Array, basis: sparse.csr_matrix) -> sparse.csr_matrix:
    """Rows ``a``, columns ``b`` blocks ``diag(matrices[:, a, b]) @ basis``."""
    from scipy import sparse

    return sparse.bmat(
        [[sparse.diags(matrices[:, a, b]) @ basis for b in range(3)] for a in range(3)],
        format="csr",
    )


def _flat(rows: Array) -> Array:
    """(n, 3) residuals as the axis-major (3n,) vector."""
    return rows.T.ravel()


def linearise(
    data: PairData, layout: FitLayout, state: FitState, sigma: Array
) -> tuple[Array, sparse.csr_matrix]:
    """The weighted residuals at ``state`` and their Jacobian in the parameter vector.

    The vector: ω spline (axis-major), s spline, rotation step (3), position (3), offset (1),
    A's gyro bias, B's gyro bias, B's accelerometer bias (axis-major each).

    Args:
        data: the measurements
        layout: the knots
        state: the point
        sigma: the four blocks' noise (A gyro, A accel, B gyro, B accel) [rad/s, m/s²]

    Returns:
        The residuals (A gyro, A accel, B gyro, B accel; each axis-major) and the Jacobian.
    """
    from scipy import sparse

    eye = sparse.identity(3, format="csr")
    basis_a = spline_basis(data.time_a, layout.start, layout.interval, layout.count, 3)
    bias_a = spline_basis(data.time_a, layout.start, layout.bias_interval, layout.bias_count, 1)
    bias_b = spline_basis(data.time_b, layout.start, layout.bias_interval, layout.bias_count, 1)
    tau = data.time_b + state.offset
    n0, n1, n2 = (
        spline_basis(tau, layout.start, layout.interval, layout.count, 3, d) for d in range(3)
    )
    rot, r = state.rotation, state.position
    w, w1, w2 = n0 @ state.omega, n1 @ state.omega, n2 @ state.omega
    s, s1 = n0 @ state.force, n1 @ state.force
    lever = np.cross(w1, r) + np.cross(w, np.cross(w, r))
    in_a = s + lever
    residuals = [
        (basis_a @ state.omega + bias_a @ state.gyro_bias_a - data.signals_a[:, :3]) / sigma[0],
        (basis_a @ state.force - data.signals_a[:, 3:]) / sigma[1],
        (w @ rot + bias_b @ state.gyro_bias_b - data.signals_b[:, :3]) / sigma[2],
        (in_a @ rot + bias_b @ state.accel_bias_b - data.signals_b[:, 3:]) / sigma[3],
    ]
    nb = data.time_b.size
    rt = rot.T
    # ∂[w×(w×r)]/∂w = w·rᵀ + (w·r)·I - 2·r·wᵀ, then Rᵀ of it
    d_lever = (
        w[:, :, None] * r[None, None, :]
        + np.einsum("n,ij->nij", w @ r, np.eye(3))
        - 2.0 * r[None, :, None] * w[:, None, :]
    )
    skew_w, skew_r = skew_rows(w), skew_rows(r[None])[0]
    d_offset_a = s1 + np.cross(w2, r) + np.cross(w1, np.cross(w, r)) + np.cross(w, np.cross(w1, r))
    blocks = [
        [sparse.kron(eye, basis_a), None, None, None, None, sparse.kron(eye, bias_a), None, None],
        [None, sparse.kron(eye, basis_a), None, None, None, None, None, None],
        [
            sparse.kron(rt, n0),
            None,
            _stacked(skew_rows(w @ rot)),
            None,
            sparse.csr_matrix(_flat(w1 @ rot)[:, None]),
            None,
            sparse.kron(eye, bias_b),
            None,
        ],
        [
            blockwise(np.broadcast_to(-rt @ skew_r, (nb, 3, 3)), n1)
            + blockwise(rt[None] @ d_lever, n0),
            sparse.kron(rt, n0),
            _stacked(skew_rows(in_a @ rot)),
            _stacked(rt[None] @ (skew_rows(w1) + skew_w @ skew_w)),
            sparse.csr_matrix(_flat(d_offset_a @ rot)[:, None]),
            None,
            None,
            sparse.kron(eye, bias_b),
        ],
    ]
    weights = np.concatenate(
        [
            np.full(3 * n, 1.0 / sg)
            for n, sg in zip((data.time_a.size, data.time_a.size, nb, nb), sigma, strict=True)
        ]
    )
    jacobian = sparse.diags(weights) @ sparse.bmat(blocks, format="csr")
    return np.concatenate([_flat(e) for e in residuals]), jacobian.tocsr()


def _factor(normals: sparse.csc_matrix, layout: FitLayout) -> sparse_linalg.SuperLU:
    """The LU factors of the normals in time-major order (a band with a dense border)."""
    from scipy.sparse import linalg as sparse_linalg

    order = _time_major(layout, normals.shape[0])
    permuted = normals[order][:, order].tocsc()
    return sparse_linalg.splu(
        permuted, permc_spec="NATURAL", diag_pivot_thresh=0.0, options={"SymmetricMode": True}
    )


def _time_major(layout: FitLayout, size: int) -> Array:
    """The unknowns reordered coefficient by coefficient of time, the globals last.

    The splines' unknowns are stored channel by channel (ω x, y, z, s x, y, z); interleaved by
    time their normals are a band of width 6·4, so the factors fill in only inside the band and
    the dense border of the few global parameters (50× faster than a fill-reducing order).
    """
    k = layout.count
    splines = (np.arange(6)[None, :] * k + np.arange(k)[:, None]).ravel()
    return np.concatenate([splines, np.arange(6 * k, size)])


def _solve(normals: sparse.csc_matrix, layout: FitLayout, rhs: Array) -> Array:
    """``normals⁻¹ @ rhs`` (a vector or columns)."""
    order = _time_major(layout, normals.shape[0])
    solved = _factor(normals, layout).solve(np.ascontiguousarray(rhs[order]))
    out = np.empty_like(solved)
    out[order] = solved
    return out


@dataclass(frozen=True)
class FitOutcome:
    """Where Gauss–Newton ended.

    Attributes:
        state: the last point
        residuals: its weighted residuals
        covariance: the global parameters' covariance (rotation 3 [rad], position 3 [m],
            offset 1 [s], then the three biases' coefficients), in σ² units of the weights
        iterations: the steps taken
        converged: the last step changed the cost by less than 1e-9 of it
    """

    state: FitState
    residuals: Array
    covariance: Array
    iterations: int
    converged: bool


def gauss_newton(
    data: PairData, layout: FitLayout, start: FitState, sigma: Array, max_iterations: int = 30
) -> FitOutcome:
    """Minimise the weighted residuals of :func:`linearise` from ``start``.

    Args:
        data: the measurements
        layout: the knots
        start: the first point
        sigma: the four blocks' noise [rad/s, m/s²]
        max_iterations: the most Gauss–Newton steps

    Returns:
        The outcome, with the covariance of the global parameters at the last point.
    """
    from scipy import sparse

    state = start
    residuals, jacobian = linearise(data, layout, state, sigma)
    cost = float(residuals @ residuals)
    damping, converged, iterations = DAMPING, False, 0
    for iterations in range(1, max_iterations + 1):  # noqa: B007
        normals = (jacobian.T @ jacobian).tocsc()
        gradient = jacobian.T @ residuals
        scaled = normals + sparse.diags(damping * normals.diagonal())
        step = -_solve(scaled.tocsc(), layout, gradient)
        trial = state.vector_update(step, layout)
        trial_residuals, trial_jacobian = linearise(data, layout, trial, sigma)
        trial_cost = float(trial_residuals @ trial_residuals)
        if trial_cost > cost and damping < 1e3:
            damping *= 100.0
            continue
        change = cost - trial_cost
        state, residuals, jacobian, cost = trial, trial_residuals, trial_jacobian, trial_cost
        damping = max(DAMPING, damping / 100.0)
        if abs(change) <= 1e-9 * cost:
            converged = True
            break
    normals = (jacobian.T @ jacobian).tocsc()
    normals = normals + sparse.diags(DAMPING * normals.diagonal())
    first = 6 * layout.count
    size = normals.shape[0] - first
    unit = np.zeros((normals.shape[0], size))
    unit[first:] = np.eye(size)
    solved = _solve(normals.tocsc(), layout, unit)
    return FitOutcome(state, residuals, solved[first:], iterations, converged)
