"""Structure detection and the closed-form start of the kinematic identification.

Structure: a module is empty when its encoder does not move and no IMU sits on its link; its
joint is revolute when the squared angular rates of an IMU on its link and an IMU on the body
before it differ by ``qd²`` plus a term linear in ``qd``
(``|w_C|² - |w_P|² = 2·qd·(w_P·j) + qd²`` for a revolute joint of unit axis ``j``, and zero for
a prismatic one, whatever the IMUs' mounting: the norms do not depend on the axes).

Start: module by module, the joint axis of a revolute module in the frame before it follows in
closed form from the same relation (linear least squares for ``j``), which gives its ``alpha``
(and the ``theta`` of a prismatic module just before it); angles the gyroscopes cannot give
(a prismatic module's ``alpha``, a ``theta`` before a parallel axis) are tried on a grid of
quarter turns. For each candidate the IMU mounting rotations follow by orthogonal Procrustes
(Kabsch) on angular rates and specific forces, and the lengths (``d``, ``a``, the IMU
positions), of which the signals are an affine function once the rotations are known, by linear
least squares; the candidate with the smallest residual is kept (a negative ``a`` counts
against it).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping, Sequence

import numpy as np

from aaria_pin.aaria.dh import R_WORLD_DH
from aaria_pin.apps.identify.geometry_model import (
    ArmLayout,
    KinematicData,
    mount_signal,
    predict_signals,
    wrap_angle,
)
from aaria_pin.core.se3 import Array

__all__ = [
    "INIT_SAMPLES",
    "detect_kind",
    "initial_parameters",
    "kabsch",
    "other_starts",
    "rotation_vector",
    "start_parameters",
    "table_start",
]

_GRID = (0.0, np.pi / 2, -np.pi / 2, np.pi)
_FORCE_WEIGHT = 0.05  # rad/s per m/s² when specific forces help fix a mounting rotation
_KIND_ERROR = 0.1  # standard error of the qd² coefficient above which the rate test decides
_SPREAD = 0.01  # second over first singular value of the rates: they span two directions
_RCOND = 1e-6  # relative singular value below which a length combination is left at 0
_PASSES = 3  # Procrustes and lengths in turn, when forces fix a rotation
_NEGATIVE_A = -0.02  # [m] a link length below this marks a candidate as the wrong branch
_NEGATIVE_START = 1e-3  # [m] a start length below minus this is invalid
_THETA_GRID = (0.0, np.pi / 2, np.pi, -np.pi / 2)  # prismatic thetas tried as other starts
INIT_SAMPLES = 400
"""Samples of the closed-form start, spread over the run."""


def detect_kind(omega_child: Array, omega_parent: Array, qd: Array) -> tuple[str, float]:
    """Revolute or prismatic, from the angular rates of IMUs on either side of the joint.

    The squared rates' difference is regressed on ``2·qd·omega_parent`` and ``qd²``: the
    coefficient of ``qd²`` is 1 for a revolute joint, 0 for a prismatic one. A prismatic
    joint's ``qd`` is small in its units (m/s): ``qd²`` is then too small to weigh against the
    gyroscopes' noise (run 19 of ``aaria dataset -n 40 --seed 2033``, ADIS16485: 7 mm/s, a
    coefficient of 1.07, taken for revolute). When that coefficient's standard error is above
    :data:`_KIND_ERROR`, the rate test decides instead, linear in ``qd``: the child's rates less
    the parent's turned by their best constant rotation (Kabsch) regressed on ``qd`` and a
    constant: the slope is the joint's unit axis for a revolute joint and zero for a prismatic
    one (the two IMUs turn together). On the 327 modules of seeds 2031 and 2033 (ADIS16485) the
    slope is at most 0.008 for a prismatic joint, at least 0.41 for a revolute one.

    Args:
        omega_child: angular velocity of an IMU on the module's link, T × 3 [rad/s]
        omega_parent: angular velocity of an IMU on the body before it, T × 3 [rad/s]
        qd: the joint's velocity from its encoder, T [rad/s or m/s]

    Returns:
        ``"revolute"`` or ``"prismatic"`` and the statistic that decided (the coefficient of
        ``qd²``, or the slope's norm: about 1 for a revolute joint, 0 for a prismatic one).
    """
    difference = np.sum(omega_child**2, axis=1) - np.sum(omega_parent**2, axis=1)
    regressors = np.column_stack([2.0 * qd[:, None] * omega_parent, qd**2])
    solution, *_ = np.linalg.lstsq(regressors, difference, rcond=None)
    coefficient = float(solution[3])
    residual = difference - regressors @ solution
    dof = max(qd.size - 4, 1)
    normal = regressors.T @ regressors
    try:
        variance = float(np.linalg.inv(normal)[3, 3]) * float(residual @ residual) / dof
    except np.linalg.LinAlgError:
        variance = np.inf
    if np.sqrt(max(variance, 0.0)) > _KIND_ERROR:
        relative = omega_child - omega_parent @ kabsch(omega_child, omega_parent)
        columns = np.column_stack([np.ones_like(qd), qd])
        slope = np.linalg.lstsq(columns, relative, rcond=None)[0][1]
        coefficient = float(np.linalg.norm(slope))
    return ("revolute" if coefficient > 0.5 else "prismatic"), coefficient


def kabsch(measured: Array, model: Array) -> Array:
    """The rotation R that best maps model row vectors onto measured ones (``measured ≈ model·R``).

    Args:
        measured: N × 3 vectors in the sensor's axes
        model: N × 3 vectors in the frame's axes

    Returns:
        R, 3 × 3, the sensor's axes in the frame (its mounting rotation).
    """
    U, _, Vt = np.linalg.svd(model.T @ measured)
    D = np.diag([1.0, 1.0, np.sign(np.linalg.det(U @ Vt)) or 1.0])
    return U @ D @ Vt


def rotation_vector(R: Array) -> Array:
    """The rotation vector (axis times angle [rad]) of a rotation matrix."""
    angle = float(np.arccos(np.clip((np.trace(R) - 1.0) / 2.0, -1.0, 1.0)))
    axis = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    if angle < 1e-9:
        return axis / 2.0
    if np.pi - angle < 1e-6:
        # near a half turn: the axis from the symmetric part
        k = np.sqrt(np.clip((np.diag(R) + 1.0) / 2.0, 0.0, None))
        i = int(np.argmax(k))
        k[:] = (R[i] + R[:, i]) / 2.0 / max(k[i], 1e-12)
        k[i] = np.sqrt(max((R[i, i] + 1.0) / 2.0, 0.0))
        return k / np.linalg.norm(k) * angle
    return axis * angle / (2.0 * np.sin(angle))


class _Fitter:
    """Residuals of a subset of IMUs as a function of the parameter vector (weighted)."""

    def __init__(
        self, layout: ArmLayout, data: KinematicData, measured: Array, weights: Array
    ) -> None:
        self.layout, self.data, self.measured, self.weights = layout, data, measured, weights

    def residual(self, x: Array, slots: Sequence[int]) -> Array:
        predicted, _ = predict_signals(x, self.layout, self.data)
        s = list(slots)
        return ((predicted[:, s] - self.measured[:, s]) * self.weights).ravel()

    def states(self, x: Array) -> list[tuple[Array, Array, Array]]:
        return predict_signals(x, self.layout, self.data)[1]

    def solve_lengths(self, x: Array, unknowns: Sequence[int], slots: Sequence[int]) -> float:
        """Set the length parameters ``unknowns`` by linear least squares; return the cost.

        The signals are affine in the lengths once the rotations are set, so each column is a
        difference of two predictions; a mount position's column needs only its IMU's few
        operations on its frame's state, not a pass of the chain.
        """
        layout = self.layout
        idx = list(unknowns)
        x[idx] = 0.0
        predicted, states = predict_signals(x, layout, self.data)
        s = list(slots)
        r0 = ((predicted[:, s] - self.measured[:, s]) * self.weights).ravel()
        columns = np.zeros((r0.size, len(idx)))
        n = self.data.q.shape[0]
        for column, i in enumerate(idx):
            if i < layout.n_dh:
                x[i] = 1.0
                moved = predict_signals(x, layout, self.data)[0][:, s]
                columns[:, column] = ((moved - predicted[:, s]) * self.weights).ravel()
                x[i] = 0.0
                continue
            module, slot, start = self._mount_of(i)
            if slot not in s:
                continue
            mount = x[start : start + 6].copy()
            mount[i - start] = 1.0
            change = (mount_signal(states[module], mount) - predicted[:, slot]) * self.weights
            block = np.zeros((n, len(s), 6))
            block[:, s.index(slot)] = change
            columns[:, column] = block.ravel()
        solution = np.linalg.lstsq(columns, -r0, rcond=_RCOND)[0]
        x[idx] = solution
        residual = r0 + columns @ solution
        return float(residual @ residual)

    def _mount_of(self, parameter: int) -> tuple[int, int, int]:
        """The module, output slot and first parameter of the mount a parameter belongs to."""
        layout = self.layout
        for index, group in enumerate(layout.link_imus):
            for position, imu in enumerate(group):
                start = layout.mount_offset(index, position)
                if start <= parameter < start + 6:
                    return index, layout.imus.index(imu), start
        raise IndexError(parameter)


def _mount_rotations(
    fitter: _Fitter, x: Array, module_index: int, states: list[tuple[Array, Array, Array]]
) -> bool:
    """Set the mounting rotations of a module's link IMUs by Procrustes (Kabsch).

    Angular rates alone when they span more than one direction (exact whatever the lengths);
    else specific forces join them (gravity dominates them, but the lever arms, not known yet,
    bias them: the caller solves the lengths and comes back).

    Returns:
        Whether specific forces were used.
    """
    layout = fitter.layout
    w, _, f = states[module_index]
    spread = np.linalg.svd(w, compute_uv=False)
    rates_only = spread[1] > _SPREAD * spread[0]
    model = w if rates_only else np.vstack([w, _FORCE_WEIGHT * f])
    for position, imu in enumerate(layout.link_imus[module_index]):
        slot = layout.imus.index(imu)
        measured = fitter.measured[:, slot, :3]
        if not rates_only:
            measured = np.vstack([measured, _FORCE_WEIGHT * fitter.measured[:, slot, 3:]])
        offset = layout.mount_offset(module_index, position)
        x[offset : offset + 3] = rotation_vector(kabsch(measured, model))
    return not rates_only


def _link_slots(layout: ArmLayout, module_index: int) -> list[int]:
    return [layout.imus.index(imu) for imu in layout.link_imus[module_index]]


def _length_unknowns(layout: ArmLayout, module_index: int) -> list[int]:
    """The length parameters of a module: d (revolute) and a, then its IMUs' positions."""
    base = 3 * module_index
    unknowns = [base + 1] if layout.kinds[module_index] == "revolute" else []
    unknowns.append(base + 2)
    for position in range(len(layout.link_imus[module_index])):
        offset = layout.mount_offset(module_index, position)
        unknowns += [offset + 3, offset + 4, offset + 5]
    return unknowns


def _candidates(
    fitter: _Fitter,
    x: Array,
    index: int,
    measured_child: Array | None,
    forced: Mapping[int, float],
) -> list[tuple[float | None, float | None]]:
    """Candidate ``(theta of the previous module, alpha of this one)`` pairs for step ``index``.

    A theta given in ``forced`` (by module index) is the only one tried.
    """
    pairs = _open_candidates(fitter, x, index, measured_child)
    if index - 1 not in forced:
        return pairs
    theta = forced[index - 1]
    kept: list[tuple[float | None, float | None]] = [
        (t, a) for t, a in pairs if t is not None and abs(wrap_angle(t - theta)) < 1e-6
    ]
    alphas: Sequence[float | None] = _GRID if index < len(fitter.layout.kinds) else (None,)
    fallback: list[tuple[float | None, float | None]] = [(theta, alpha) for alpha in alphas]
    return kept or fallback


def _open_candidates(
    fitter: _Fitter, x: Array, index: int, measured_child: Array | None
) -> list[tuple[float | None, float | None]]:
    """The candidate pairs of step ``index`` when no theta is forced."""
    layout, data = fitter.layout, fitter.data
    previous_prismatic = index > 0 and layout.kinds[index - 1] == "prismatic"
    thetas: Sequence[float | None] = _GRID if previous_prismatic else (None,)
    if index == len(layout.kinds):  # the tool: only the previous theta is open
        return [(theta, None) for theta in thetas]
    if layout.kinds[index] == "prismatic" or measured_child is None:
        return [(theta, alpha) for theta in thetas for alpha in _GRID]
    # revolute: the axis in the frame before the module, in closed form
    trial = x.copy()
    if previous_prismatic:
        trial[3 * (index - 1) + 1] = 0.0
    omega = fitter.states(trial)[index - 1][0] if index > 0 else data.omega_base @ R_WORLD_DH
    qd = data.qd[:, index]
    difference = np.sum(measured_child**2, axis=1) - np.sum(omega**2, axis=1) - qd**2
    regressors = 2.0 * qd[:, None] * omega
    axis, *_ = np.linalg.lstsq(regressors, difference, rcond=None)
    fit = regressors @ axis - difference
    scale = float(np.sqrt(np.mean(difference**2))) or 1.0
    good = np.sqrt(np.mean(fit**2)) < 0.1 * scale and 0.8 < np.linalg.norm(axis) < 1.2
    out: list[tuple[float | None, float | None]] = []
    if good:
        jx, jy, jz = axis / np.linalg.norm(axis)
        if previous_prismatic:
            s = float(np.hypot(jx, jy))
            if s > 0.3:
                theta = float(np.arctan2(jx, -jy))
                out += [
                    (theta, float(np.arctan2(s, jz))),
                    (theta + np.pi, float(np.arctan2(-s, jz))),
                ]
            else:
                out += [(theta, 0.0 if jz > 0 else np.pi) for theta in _GRID]
        else:
            out.append((None, float(np.arctan2(-jy, jz))))
    else:
        out += [(theta, alpha) for theta in thetas for alpha in _GRID]
    return out


def initial_parameters(
    layout: ArmLayout,
    data: KinematicData,
    measured: Array,
    weights: Array,
    forced: Mapping[int, float] | None = None,
) -> tuple[Array, float]:
    """The start of the fit: module by module, closed-form axes and least-squares lengths.

    Args:
        layout: the arm's modules and IMUs (from the structure detection)
        data: the base motion and joint motions (a subsample of the run is enough)
        measured: the measured signals of :attr:`ArmLayout.imus`, T × S × 6
        weights: the weight of each signal, 6 (1 / its noise level)
        forced: the theta of some prismatic modules (by module index), the only one tried

    Returns:
        The parameter vector (:meth:`ArmLayout.parameter_names`) and its weighted squared
        residual over every IMU.
    """
    fitter = _Fitter(layout, data, measured, weights)
    x = np.zeros(layout.n_params)
    n = len(layout.kinds)
    for index in range(n + 1):
        child_slots = _link_slots(layout, index) if index < n else [0]
        measured_child = measured[:, child_slots[0], :3] if child_slots else None
        best: tuple[tuple[bool, float], Array] | None = None
        for theta, alpha in _candidates(fitter, x, index, measured_child, forced or {}):
            trial = x.copy()
            if theta is not None:
                trial[3 * (index - 1) + 1] = theta
            if alpha is not None:
                trial[3 * index] = alpha
            unknowns: list[int] = []
            slots: list[int] = []
            modules = [m for m in (index - 1, index) if 0 <= m < n]
            for module in modules:
                unknowns += _length_unknowns(layout, module)
                slots += _link_slots(layout, module)
            if index == n:
                unknowns.append(layout.n_dh - 1)
                slots.append(0)
            for _ in range(_PASSES):
                states = fitter.states(trial)
                forces = [_mount_rotations(fitter, trial, m, states) for m in modules]
                cost = fitter.solve_lengths(trial, unknowns, slots)
                if not any(forces):
                    break
            negative = index > 0 and trial[3 * (index - 1) + 2] < _NEGATIVE_A
            key = (negative, cost)
            if best is None or key < best[0]:
                best = (key, trial)
        assert best is not None
        x = best[1]
    residual = fitter.residual(x, range(len(layout.imus)))
    return x, float(residual @ residual)


def _quarter_turns(
    layout: ArmLayout, data: KinematicData, measured: Array, weights: Array
) -> Iterator[list[tuple[Array, float]]]:
    """Per prismatic module (lazily), its starts with theta forced to each quarter turn.

    Each is :func:`initial_parameters` with that theta forced, and its cost.
    """
    for index, kind in enumerate(layout.kinds):
        if kind == "prismatic":
            yield [
                initial_parameters(layout, data, measured, weights, forced={index: theta})
                for theta in _THETA_GRID
            ]


def start_parameters(
    layout: ArmLayout, data: KinematicData, measured: Array, weights: Array, lengths: Sequence[int]
) -> Array:
    """The closed-form start; if it has a negative length, the best start with one forced theta.

    Equivalent tables form families the start's greedy choice of a prismatic module's theta
    can land in on the wrong side (a negative d further on); one forced quarter turn of one
    prismatic theta at a time usually reaches the valid side, where the fit need not walk.

    Args:
        layout: the arm's modules and IMUs
        data: the base motion and joint motions (a subsample of the run)
        measured: the measured signals of :attr:`ArmLayout.imus`, T × S × 6
        weights: the weight of each signal, 6
        lengths: indices of the parameters that are lengths (must not be negative)

    Returns:
        The start's parameter vector.
    """
    x, cost = initial_parameters(layout, data, measured, weights)
    negative = int(np.sum(x[lengths] < -_NEGATIVE_START))
    if not negative:
        return x
    best = ((negative, cost), x)
    ceiling = 10.0 * cost + measured.size  # an equivalent start fits as well as the first
    for trials in _quarter_turns(layout, data, measured, weights):
        for trial, trial_cost in trials:
            key = (int(np.sum(trial[lengths] < -_NEGATIVE_START)), trial_cost)
            if trial_cost <= ceiling and key < best[0]:
                best = (key, trial)
        if best[0][0] == 0:
            break
    return best[1]


def other_starts(
    layout: ArmLayout,
    data: KinematicData,
    measured: Array,
    weights: Array,
    spread: Callable[[int], Array],
    first: Array,
) -> list[Array]:
    """Starts other than the first, each once.

    Each prismatic module's theta forced to each quarter turn (the gyroscopes cannot give it),
    and the closed-form start from four times the samples (noise sways its greedy choices).

    Args:
        layout: the arm's modules and IMUs
        data: the base motion and joint motions over the run
        measured: the measured signals of :attr:`ArmLayout.imus`, T × S × 6
        weights: the weight of each signal, 6
        spread: sample count → that many sample indices spread evenly over the run
        first: the first start (left out)

    Returns:
        The other starts' parameter vectors.
    """
    starts: list[Array] = []
    index = spread(INIT_SAMPLES)
    part, part_measured = data.subsample(index), measured[index]
    for trials in _quarter_turns(layout, part, part_measured, weights):
        starts += [trial for trial, _ in trials]
    more = spread(4 * INIT_SAMPLES)
    trial, _ = initial_parameters(layout, data.subsample(more), measured[more], weights)
    starts.append(trial)
    return [z for z in starts if not any(np.allclose(z, y) for y in [first, *starts[:0]])]


def table_start(
    layout: ArmLayout, data: KinematicData, measured: Array, weights: Array, table: Array
) -> tuple[Array, float]:
    """A start from a given table: its angles and lengths, the IMU mounts fitted to them.

    Each module's ``alpha``, ``d`` (revolute) or ``theta`` (prismatic) and ``a`` and the tool
    length are the table's; the table holds no IMU mount, so each link IMU's rotation follows
    by Procrustes and its position by linear least squares on the table's frames, as in
    :func:`initial_parameters` (the chain's frames do not depend on the mounts: one pass).

    Args:
        layout: the arm's modules and IMUs, its kinds the table's
        data: the base motion and joint motions (a subsample of the run is enough)
        measured: the measured signals of :attr:`ArmLayout.imus`, T × S × 6
        weights: the weight of each signal, 6
        table: an 8 × 5 Aaria table (checked)

    Returns:
        The parameter vector and its weighted squared residual over every IMU.
    """
    fitter = _Fitter(layout, data, measured, weights)
    x = np.zeros(layout.n_params)
    for index, (module, kind) in enumerate(zip(layout.modules, layout.kinds, strict=True)):
        alpha, a, theta, d = table[module - 1, :4]
        x[3 * index : 3 * index + 3] = [alpha, d if kind == "revolute" else theta, a]
    x[layout.n_dh - 1] = table[6, 1]
    states = fitter.states(x)
    for index in range(len(layout.modules)):
        _mount_rotations(fitter, x, index, states)
        unknowns = [u for u in _length_unknowns(layout, index) if u >= layout.n_dh]
        fitter.solve_lengths(x, unknowns, _link_slots(layout, index))
    residual = fitter.residual(x, range(len(layout.imus)))
    return x, float(residual @ residual)
