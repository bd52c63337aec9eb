"""The base parameters of a regressor: the combinations of standard parameters the data determine.

:func:`base_parameters`: QR with column pivoting of the stacked regressor (columns scaled to unit
norm first, so the rank does not depend on units), rank by a relative tolerance on the diagonal
of R; the first r pivoted columns are independent, the others are their combinations
``W2 = W1·beta``, so the base parameters are ``pi_b = pi_1 + beta·pi_2``: each is named after
its leading standard parameter and written out as the combination.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = ["DEFAULT_TOLERANCE", "BaseParameterSet", "base_parameters", "triangular_factor"]

DEFAULT_TOLERANCE = 1e-9
"""Relative tolerance of the rank: a pivot of the column-scaled regressor's R below this
fraction of the first is taken as zero. The dependencies are structural (they hold for every
state), so with any data the dependent pivots are at 1e-15; the weakest independent ones of the
presets' and the ur5's default sine motions over 10–30 s are at 1e-3."""


@dataclass(frozen=True)
class BaseParameterSet:
    """The numerically determined base parameters of a regressor.

    Attributes:
        standard_names: the p standard parameters (columns of the regressor)
        independent: the r pivoted columns that are independent, in pivot order
        combination: r × p matrix K, ``pi_base = K @ pi_standard``; ``K[:, independent]`` is the
            identity
        names: each base parameter's name, its leading standard parameter
        expressions: each base parameter as a combination of standard ones, in words
            (``"Izz_link2 + 0.18·m_link3"``)
        pivots: |R_ii| of the column-scaled regressor over the first, in pivot order (p)
        tolerance: the relative tolerance of the rank
    """

    standard_names: tuple[str, ...]
    independent: tuple[int, ...]
    combination: Array
    names: tuple[str, ...]
    expressions: tuple[str, ...]
    pivots: Array
    tolerance: float

    @property
    def rank(self) -> int:
        """r, the number of base parameters."""
        return len(self.independent)

    def identifiable(self, functional: Array, tolerance: float = 1e-8) -> bool:
        """Whether ``functional @ pi`` (rows of a (k, p) or (p,) array) is determined by the data.

        It is when every row lies in the row space of the regressor, i.e. equals
        ``K.T @ row[independent]``, within ``tolerance`` relative to the row's norm.
        """
        rows = np.atleast_2d(functional)
        implied = rows[:, list(self.independent)] @ self.combination
        scale = np.maximum(np.linalg.norm(rows, axis=1), 1e-300)
        return bool(np.all(np.linalg.norm(rows - implied, axis=1) <= tolerance * scale))


def _expression(names: tuple[str, ...], row: Array, leading: int) -> str:
    terms = [names[leading]]
    for c in np.flatnonzero(np.abs(row) > 1e-10):
        if c == leading:
            continue
        value = float(row[c])
        sign = "-" if value < 0 else "+"
        terms.append(f"{sign} {abs(value):.6g}·{names[c]}")
    return " ".join(terms)


def triangular_factor(A: Array) -> Array:
    """R of ``A = Q·R`` (min(rows, columns) × columns), Q never formed.

    One Householder pass (LAPACK ``geqrf`` through scipy's ``mode="raw"``); numpy's
    ``qr(mode="r")`` took three times as long on a 57,612 × 71 matrix.
    """
    import scipy.linalg

    if A.shape[0] <= A.shape[1]:
        return np.asarray(scipy.linalg.qr(A, mode="r")[0])
    raw = scipy.linalg.qr(A, mode="raw", overwrite_a=False)[0][0]
    return np.triu(raw[: A.shape[1]])


def base_parameters(
    regressor: Array, names: tuple[str, ...], *, tolerance: float = DEFAULT_TOLERANCE
) -> BaseParameterSet:
    """The base parameter set of a stacked regressor by QR with column pivoting.

    Args:
        regressor: the stacked regressor, rows × p (samples × signals flattened)
        names: the p standard parameter names
        tolerance: relative rank tolerance on the pivots of the column-scaled regressor

    Returns:
        The base parameters.

    Raises:
        ParameterError: names that do not match the columns, or a tolerance outside (0, 1).
    """
    import scipy.linalg

    W = np.asarray(regressor, dtype=float)
    p = W.shape[1]
    if len(names) != p:
        raise ParameterError(parameter="names", value=len(names), allowed=f"{p} names")
    if not 0 < tolerance < 1:
        raise ParameterError(parameter="tolerance", value=tolerance, allowed="0 < tolerance < 1")
    norms = np.linalg.norm(W, axis=0)
    scale = np.where(norms > 0, norms, 1.0)
    R = triangular_factor(W / scale)  # W = Q·R: the same column dependencies, p × p
    _, R_p, order = scipy.linalg.qr(R, mode="economic", pivoting=True)
    pivots = np.abs(np.diag(R_p))
    pivots = pivots / pivots[0] if pivots.size and pivots[0] > 0 else pivots
    rank = int(np.count_nonzero(pivots > tolerance))
    first, rest = order[:rank], order[rank:]
    beta_scaled = scipy.linalg.solve_triangular(R_p[:rank, :rank], R_p[:rank, rank:])
    beta = beta_scaled * np.divide.outer(1.0 / scale[first], 1.0 / scale[rest])
    K = np.zeros((rank, p))
    K[np.arange(rank), first] = 1.0
    K[:, rest] = beta
    base_names = tuple(names[c] for c in first)
    expressions = tuple(_expression(names, K[k], int(first[k])) for k in range(rank))
    return BaseParameterSet(
        tuple(names),
        tuple(int(c) for c in first),
        K,
        base_names,
        expressions,
        np.pad(pivots, (0, p - pivots.size)),
        tolerance,
    )
