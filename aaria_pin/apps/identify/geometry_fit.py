"""The nonlinear fit of the kinematic model and what it leaves undetermined.

Levenberg–Marquardt of the weighted predicted minus measured IMU signals, with a faint pull
towards the start and a steep penalty on negative lengths (:class:`WeightedFit`); the Jacobian's
null space at the solution named in words (:func:`deficiencies`), a move along it that
makes every length non-negative (:func:`non_negative_lengths`), and a walk along it to the
smallest lengths (:meth:`WeightedFit.shorten`, :func:`shortest_lengths`) for a table whose
lengths cancel.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from aaria_pin.apps.identify.geometry_bias import BiasModel
from aaria_pin.apps.identify.geometry_model import (
    ArmLayout,
    KinematicData,
    base_sensitivity,
    predict_signals,
    weighted_jacobian,
)
from aaria_pin.apps.identify.geometry_result import Deficiency
from aaria_pin.core.se3 import Array

__all__ = [
    "WeightedFit",
    "deficiencies",
    "levenberg_marquardt",
    "non_negative_lengths",
    "sandwich_sigmas",
    "shortest_lengths",
]

_DEFICIENT = 1e-5  # singular value ratio below which a direction is not determined


_RELATIVE_DECREASE = 1e-6  # the fit stops when an iteration gains less than this share


_PRIOR = 0.1  # [1/m, 1/rad] weight of the pull towards the start (in noise units)


_LONGEST_MOVE = 1.0  # [m] along a null direction, to make lengths valid


_PENALTY = 1e6  # [1/m] weight of a negative length


_SHORTEN_STEP = 0.25  # [m] the longest length change of one step towards the shortest lengths


_SHORTEN_STEPS = 40  # steps at most (10 m of lengths)


_SHORTEN_ITERATIONS = 20  # Levenberg–Marquardt iterations back onto the equivalent tables


def levenberg_marquardt(
    residual: Callable[[Array], Array],
    jacobian: Callable[[Array], Array],
    x0: Array,
    max_iterations: int,
) -> tuple[Array, Array, Array, int]:
    """Levenberg–Marquardt on the normal equations (Marquardt's diagonal scaling).

    Our own rather than ``scipy.optimize.least_squares``: both of its methods factor the whole
    (T·S·6) × p Jacobian at every iteration (MINPACK's QR, or an SVD with bounds), 4.7 s of a
    6.8 s fit of ``aaria-fig2`` from 500 samples (cProfile); the normal equations are one BLAS
    product ``JᵀJ`` and a p × p solve. Null directions of the fit (parallel axes) are harmless:
    the damping keeps the system definite, and steps along them do not change the cost.

    Returns:
        The solution, its residual vector, the Jacobian there, and the iterations done.
    """
    x = x0.copy()
    r = residual(x)
    cost = float(r @ r)
    damping = 1e-3
    J = jacobian(x)
    iterations = 0
    while iterations < max_iterations:
        iterations += 1
        A = J.T @ J
        g = J.T @ r
        diagonal = np.maximum(np.diag(A), 1e-12 * max(float(np.max(np.diag(A))), 1e-300))
        accepted = False
        while damping < 1e12:
            try:
                step = -np.linalg.solve(A + damping * np.diag(diagonal), g)
            except np.linalg.LinAlgError:
                damping *= 10.0
                continue
            trial = x + step
            r_trial = residual(trial)
            cost_trial = float(r_trial @ r_trial)
            if cost_trial < cost:
                accepted = True
                break
            damping *= 4.0
        if not accepted:
            break
        decrease = cost - cost_trial
        x, r, cost = trial, r_trial, cost_trial
        damping = max(damping / 3.0, 1e-9)
        small_step = np.linalg.norm(step) <= 1e-12 * (1.0 + np.linalg.norm(x))
        if decrease <= _RELATIVE_DECREASE * cost or small_step or cost <= 1e-20 * r.size:
            break
        J = jacobian(x)
    return x, r, jacobian(x), iterations


def non_negative_lengths(x: Array, basis: Array, lengths: Sequence[int]) -> Array:
    """Move along the fit's null directions (same signals) until no length is negative.

    Along each null direction the lengths stay non-negative over an interval of steps; the
    step taken is 0 when it is inside, else the interval's middle (or its nearer end plus
    a margin of 1 mm when open on one side).
    """
    x = x.copy()
    for direction in _rref_rows(basis):
        low, high = -np.inf, np.inf
        for i in lengths:
            if abs(direction[i]) < 1e-9:
                continue
            bound = -x[i] / direction[i]
            if direction[i] > 0:
                low = max(low, bound)
            else:
                high = min(high, bound)
        if low <= 0.0 <= high or low > high:
            continue
        if np.isfinite(low) and np.isfinite(high):
            step = (low + high) / 2.0
        else:
            step = low + 1e-3 if np.isfinite(low) else high - 1e-3
        if np.max(np.abs(step * direction[list(lengths)])) <= _LONGEST_MOVE:
            x += step * direction
    return x


def shortest_lengths(x: Array, basis: Array, lengths: Sequence[int]) -> Array:
    """Move along the fit's null directions to the smallest non-negative lengths.

    The step ``s`` minimises ``Σ (x_L + B_L·s)²`` over the lengths ``L`` with every length
    non-negative (SLSQP; a few unknowns). An all-prismatic arm of ``aaria dataset --seed 2027
    --motion fourier --dtype float64 --no-noise`` (run 6) ended with ``a1 = 4.3 m`` and
    ``a4 = 5.3 m`` along its three null directions (the tool tip 6e-6 m right).

    Args:
        x: the parameter vector
        basis: the null directions (rows, parameter units; :func:`deficiencies`)
        lengths: indices of the parameters that are lengths

    Returns:
        The moved parameter vector (``x`` itself when there is no null direction).
    """
    if basis.size == 0:
        return x
    from scipy.optimize import minimize

    idx = list(lengths)
    start, along = x[idx], basis[:, idx].T

    def cost(s: Array) -> float:
        moved = start + along @ s
        return 0.5 * float(moved @ moved)

    def gradient(s: Array) -> Array:
        return np.asarray(along.T @ (start + along @ s))

    solution = minimize(
        cost,
        np.zeros(basis.shape[0]),
        jac=gradient,
        method="SLSQP",
        constraints=[{"type": "ineq", "fun": lambda s: start + along @ s, "jac": lambda s: along}],
    )
    return np.asarray(x + basis.T @ solution.x)


def _rref_rows(basis: Array, tolerance: float = 1e-3) -> Array:
    """Reduced row echelon form of a null-space basis (rows), pivots taken left to right.

    Entries below ``tolerance`` times their row's largest are dropped first, and again after.
    """
    rows = basis.copy()
    if rows.size:
        rows[np.abs(rows) < tolerance * np.max(np.abs(rows), axis=1, keepdims=True)] = 0.0
    pivot_row = 0
    for column in range(rows.shape[1]):
        if pivot_row == rows.shape[0]:
            break
        best = pivot_row + int(np.argmax(np.abs(rows[pivot_row:, column])))
        if abs(rows[best, column]) < tolerance * max(
            float(np.max(np.abs(rows[pivot_row:]))), 1e-300
        ):
            continue
        rows[[pivot_row, best]] = rows[[best, pivot_row]]
        rows[pivot_row] /= rows[pivot_row, column]
        for other in range(rows.shape[0]):
            if other != pivot_row:
                rows[other] -= rows[other, column] * rows[pivot_row]
        pivot_row += 1
    rows = rows[:pivot_row]
    if rows.size:
        rows[np.abs(rows) < tolerance * np.max(np.abs(rows), axis=1, keepdims=True)] = 0.0
    return rows


def _describe(names: Sequence[str], coefficients: Sequence[float]) -> str:
    if len(names) == 1:
        return f"{names[0]} is not determined by the data"
    if len(names) == 2 and abs(abs(coefficients[1]) - 1.0) < 1e-3:
        first, second = names
        if coefficients[1] < 0:
            return f"{first} and {second} add up (only {first} + {second} is determined)"
        return f"only {first} - {second} is determined"
    terms = " + ".join(f"{c:.3g}·{n}" for n, c in zip(names, coefficients, strict=True))
    return "only combinations orthogonal to " + terms + " are determined"


def deficiencies(
    jacobian: Array, names: Sequence[str], n_dh: int
) -> tuple[tuple[Deficiency, ...], Array, Array, Array]:
    """Null directions of the fit, named; the parameters' standard deviations (unit σ²).

    Returns:
        The deficiencies, the standard deviations (NaN: not determined), the null directions
        (rows, parameter units) and the pseudo-inverse of ``JᵀJ`` on the determined
        directions (parameter units).
    """
    scale = np.linalg.norm(jacobian, axis=0)
    scale[scale == 0] = 1.0
    normal = (jacobian.T @ jacobian) / np.outer(scale, scale)
    eigenvalues, vectors = np.linalg.eigh(normal)
    order = np.argsort(eigenvalues)[::-1]
    singular = np.sqrt(np.clip(eigenvalues[order], 0.0, None))
    Vt = vectors[:, order].T
    null = singular < _DEFICIENT * singular[0]
    kept = ~null
    covariance = (Vt[kept].T / singular[kept] ** 2) @ Vt[kept]
    sigmas = np.sqrt(np.diag(covariance)) / scale
    covariance = covariance / np.outer(scale, scale)
    basis = Vt[null] / scale  # null directions in parameter units
    undetermined = np.zeros(len(names), dtype=bool)
    if basis.size:
        unit_basis = Vt[null]
        undetermined = np.linalg.norm(unit_basis, axis=0) > 0.1
    sigmas = np.where(undetermined, np.nan, sigmas)
    deficiencies = []
    # pivots from the right: the tool length a7 (in every arm's a_last + a7) pivots first, so
    # it leaves the other rows
    for row in _rref_rows(basis[:, ::-1])[:, ::-1]:
        dh = [(names[i], row[i]) for i in range(n_dh) if abs(row[i]) > 1e-6]
        if not dh:
            mounts = sorted(
                {names[i].split(".")[0] for i in range(len(names)) if abs(row[i]) > 1e-6}
            )
            dh = [(f"mount of {m}", 1.0) for m in mounts[:1]]
        lead = dh[0][1]
        coefficients = tuple(float(c / lead) for _, c in dh)
        labels = tuple(n for n, _ in dh)
        deficiencies.append(Deficiency(labels, coefficients, _describe(labels, coefficients)))
    return tuple(deficiencies), sigmas, basis, covariance


def sandwich_sigmas(
    covariance: Array, jacobian: Array, residual: Array, per_sample: int, window: int
) -> Array:
    """Standard deviations that hold when the residual is not white: the sandwich estimate.

    ``C·(Σ_t g_t)(Σ_t g_t)ᵀ·C`` with ``C = (JᵀJ)⁺`` and ``g_t = J_tᵀ r_t`` the score of
    sample ``t`` (all its rows); the middle's expectation is estimated by overlapping batch
    means over ``window`` samples (a Bartlett-kernel long-run covariance: residuals correlated
    over up to a window, the base IMU's filtered noise, are counted as they are; each signal's
    own variance enters through its residual, not through its nominal noise level).

    Args:
        covariance: ``(JᵀJ)⁺``, n × n (parameter units)
        jacobian: the weighted Jacobian, (T·k) × n, rows by sample
        residual: the weighted residual, T·k
        per_sample: the rows of one sample, k
        window: the batch length [samples]
    """
    n = covariance.shape[0]
    scores = np.einsum(
        "tk,tkn->tn",
        residual.reshape(-1, per_sample),
        jacobian.reshape(-1, per_sample, n),
    )
    count = scores.shape[0]
    window = int(min(max(window, 1), max(count // 4, 1)))
    sums = np.cumsum(np.vstack([np.zeros((1, n)), scores]), axis=0)
    batches = sums[window:] - sums[:-window]
    middle = (batches.T @ batches) * count / (window * batches.shape[0])
    return np.sqrt(np.clip(np.diag(covariance @ middle @ covariance), 0.0, None))


@dataclass(frozen=True)
class WeightedFit:
    """The weighted least-squares problem of one run: predicted minus measured IMU signals.

    A faint pull towards an anchor (:data:`_PRIOR` σ per metre or radian) fixes what the data
    leave open (the null directions of parallel axes), nothing against the data's own
    curvature; a steep penalty on negative lengths walks the fit along a family of equivalent
    tables (a prismatic module's theta against the lengths after it) to a valid one.

    Attributes:
        layout: the arm's modules and IMUs
        data: the base motion and joint motions over the run
        measured: the measured signals of :attr:`ArmLayout.imus`, T × S × 6
        weights: the weight of each signal, 6 (1 / its noise level)
        lengths: indices of the parameters that must not be negative
        time: the sample times [s] (needed with ``bias_spacings``)
        bias_spacings: the bias splines' knot spacing of the gyroscopes and accelerometers
            [s] (:func:`~aaria_pin.apps.identify.geometry_bias.knot_spacing`), or None: no
            bias model (noise-free records)
    """

    layout: ArmLayout
    data: KinematicData
    measured: Array
    weights: Array
    lengths: Sequence[int]
    time: Array | None = None
    bias_spacings: tuple[float, float] | None = None

    def _signal_residual(
        self, index: Array, at: Array, biases: bool = True
    ) -> tuple[Callable[[Array], Array], Callable[[Array], Array], KinematicData]:
        """The weighted signal residuals on ``index``, biases projected off if modelled.

        The base IMU's bias columns depend on the arm's rotations; they are taken at ``at``
        (the fit's start: the rotations the walk found move little in the final fit).

        Returns:
            ``z`` → the flat residual; the projection of a Jacobian (T·S·6 × n); the data at
            ``index``.
        """
        layout, weights = self.layout, self.weights
        part, part_measured = self.data.subsample(index), self.measured[index]
        if not biases or self.bias_spacings is None or self.time is None:

            def plain(z: Array) -> Array:
                return ((predict_signals(z, layout, part)[0] - part_measured) * weights).ravel()

            return plain, lambda jac: jac, part
        span = (float(self.time[0]), float(self.time[-1]))
        model = BiasModel.at(self.time[index], span, self.bias_spacings)
        base = model.base_space(base_sensitivity(at, layout, part), weights)
        shape = (index.size, len(layout.imus), 6)

        def projected(z: Array) -> Array:
            weighted = (predict_signals(z, layout, part)[0] - part_measured) * weights
            return model.project(weighted, base)

        def project(jac: Array) -> Array:
            return model.project(jac.reshape(*shape, -1), base)

        return projected, project, part

    def fit(
        self, x: Array, anchor: Array, index: Array, iterations: int, biases: bool = True
    ) -> tuple[Array, Array, Array, int]:
        """Levenberg–Marquardt from ``x`` on the samples ``index``, pulled towards ``anchor``.

        With :attr:`bias_spacings` and ``biases``, each IMU channel's bias (and the base
        IMU's) is a spline of time projected off the residual and its Jacobian
        (:class:`BiasModel`); the walks from the starts, on few samples, go without.

        Returns:
            The solution, its weighted signal residuals, their Jacobian (prior and penalty rows
            left out) and the iterations done.
        """
        layout, lengths, weights = self.layout, list(self.lengths), self.weights
        signal, project, part = self._signal_residual(index, x, biases)
        identity = _PRIOR * np.eye(layout.n_params)
        extra = layout.n_params + len(lengths)

        def residual(z: Array) -> Array:
            return np.concatenate(
                [signal(z), _PRIOR * (z - anchor), _PENALTY * np.minimum(z[lengths], 0.0)]
            )

        def jacobian(z: Array) -> Array:
            penalty = np.zeros((len(lengths), layout.n_params))
            penalty[np.arange(len(lengths)), lengths] = _PENALTY * (z[lengths] < 0.0)
            jac = project(weighted_jacobian(z, layout, part, weights))
            return np.vstack([jac, identity, penalty])

        x, fun, jac, done = levenberg_marquardt(residual, jacobian, x, iterations)
        return x, fun[:-extra], jac[:-extra], done

    def shorten(self, x: Array, basis: Array, names: Sequence[str], index: Array) -> Array:
        """Walk along the fit's null directions, in short steps, to the smallest lengths.

        A null direction is a symmetry to first order only: a long straight move leaves the
        family of equivalent tables. Each step goes at most :data:`_SHORTEN_STEP` towards
        :func:`shortest_lengths`, is fitted back onto the family (a few iterations on the
        samples ``index``, without biases) and takes the null directions there. On run 6 of
        ``aaria dataset -n 7 --seed 2027 --motion fourier --dtype float64 --no-noise`` (all
        prismatic; lengths 4.3 and 5.3 m) 12 steps reach 1.8 and 2.8 m, the tool tip 5e-12 m
        right; one straight move and a polish did not get back to the fit's cost.

        Args:
            x: the fit's solution
            basis: its null directions (rows, parameter units; :func:`deficiencies`)
            names: the parameter names (:func:`deficiencies`)
            index: the samples of the steps' fits (few: the walk's)

        Returns:
            The parameter vector at the walk's end.
        """
        lengths = list(self.lengths)
        for _ in range(_SHORTEN_STEPS):
            move = shortest_lengths(x, basis, lengths) - x
            longest = float(np.max(np.abs(move[lengths]), initial=0.0))
            if longest <= 1e-6:
                break
            x = x + move * min(1.0, _SHORTEN_STEP / longest)
            x, _, jac, _ = self.fit(x, x, index, _SHORTEN_ITERATIONS, biases=False)
            basis = deficiencies(jac, names, self.layout.n_dh)[2]
        return x

    def cost(self, x: Array, index: Array) -> float:
        """The weighted squared signal residual of ``x`` on the samples ``index``."""
        flat = self._signal_residual(index, x)[0](x)
        return float(flat @ flat)
