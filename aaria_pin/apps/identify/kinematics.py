"""Identify an Aaria arm's kinematic model from its IMU signals and joint encoders.

:func:`identify_kinematics` takes a DH run's record and uses only what a real set-up has: the
sample times, the joint encoder columns ``q``, the IMU signals, which link each IMU is on
(``imu_mounts[i].parent``), and nothing of the DH table, the IMU mounting poses, the tool pose or
the base pose. It estimates

1. the structure: each module empty (its encoder does not move and no IMU sits on its link),
   revolute or prismatic (:func:`~aaria_pin.apps.identify._kin_init.detect_kind`);
2. a start in closed form (joint axes from gyroscope differences, lengths by linear least
   squares; :func:`~aaria_pin.apps.identify._kin_init.initial_parameters`);
3. the extended DH table (per module ``alpha, a`` and ``d`` or ``theta``, the tool length) and
   each link IMU's mounting pose, by nonlinear least squares
   (Levenberg–Marquardt) of predicted minus measured IMU signals over the run, on the exact
   model (:func:`~aaria_pin.apps.identify._kin_model.predict_signals`, a whole-run
   forward pass of rates and specific forces), each signal weighted by 1 / its noise level
   (the record's noise parameters, else ADIS16485's). A fit that ends above the noise floor
   is a local minimum: other starts (each prismatic theta forced to each quarter turn, the
   closed-form start from more samples) are walked, the best few fitted, the smallest
   residual kept, stopping at the floor. On noisy records the base IMU's signals, inputs of
   the model, are smoothed and differentiated with windows the data choose (:func:`_smoothed`);
4. each parameter's standard deviation from the Jacobian at the solution, the residual RMS per
   IMU, the parameter combinations the data cannot determine (the Jacobian's null space, named
   in words: "d2 and d3 add up (only d2 + d3 is determined)"), and, when the record holds the
   truth, the errors: link types, the tool tip's position over the run from an independent
   forward kinematics (Pinocchio, :func:`~aaria_pin.core.kinematics.trajectory_signals`) of the
   estimated and the true table, and the joint axes' angles.

What the set-up defines rather than measures: the **base IMU's frame is the base frame** and the
**tool IMU's frame is the tool-tip frame** (as Aaria mounts them: ``imu_base`` at the base origin,
``imu_tool`` at the tool tip, both unrotated). A real arm has no other physical marker of either
frame, so these two mounts are not estimated (identity); the link IMUs' mounts are. The base
may move: its angular velocity and the specific force at its origin are the base IMU's signals,
its angular acceleration their spline derivative; the base pose is never used. Joint velocities
and accelerations are the derivatives of a quintic spline through the encoder values.

DH tables are not unique (the same arm has several): compare tool-tip trajectories and joint
axes, not table entries. A revolute module's ``theta`` and a prismatic module's rail length
``d`` do not act on the kinematics; the table gives 0 and the shortest rail the encoder's range
fits in. The base row (row 8) is unused by the kinematics (zeros); the tool row is
``[0, a7, 0, 0, 1]``.
"""

from __future__ import annotations

import time as _time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from aaria_pin.apps.identify._kin_init import (
    detect_kind,
    initial_parameters,
)
from aaria_pin.apps.identify._kin_model import (
    ArmLayout,
    KinematicData,
    json_number,
    predict_signals,
    rotation_from_vector,
    weighted_jacobian,
    wrap_angle,
)
from aaria_pin.core.imu_noise import ADIS16485
from aaria_pin.core.record import ImuMount, RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError, TableError

__all__ = [
    "Deficiency",
    "KinematicIdentification",
    "TruthErrors",
    "identify_kinematics",
]

BASE_PARENT = "base"
TOOL_PARENT = "tool_tip"
_MOVING = 1e-9  # [rad or m] an encoder whose range is below this does not move
_DEFICIENT = 1e-5  # singular value ratio below which a direction is not determined
_INIT_SAMPLES = 400
_WINDOWS = (0.25, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0)  # [s] smoothing windows tried on noisy base signals
_AGREE = 2.0  # a longer window agrees when within this many of the shorter one's noise σ
_FIT_SAMPLES = 4000  # noisy fits gain from every sample (8.3 mm at 1000 samples, 1.2 mm at 6001)
_RELATIVE_DECREASE = 1e-6  # the fit stops when an iteration gains less than this share
_NEGATIVE_START = 1e-3  # [m] a start length below minus this is invalid
_THETA_GRID = (0.0, np.pi / 2, np.pi, -np.pi / 2)
_WALK_SAMPLES = 120
_PRIOR = 0.1  # [1/m, 1/rad] weight of the pull towards the start (in noise units)
_ROUND_UP = 1e-3  # [m] a length this close below 0 is 0
_LONGEST_MOVE = 1.0  # [m] along a null direction, to make lengths valid
_PENALTY = 1e6  # [1/m] weight of a negative length
_MIN_SAMPLES = 20
_AT_FLOOR = 1.1  # a fit whose weighted RMS is within this factor of the noise floor is done
_EXACT_FLOOR = 1e-3  # the noise floor of a noise-free record (its fits end near 1e-8)
_REFITS = 3  # other starts fitted on every sample, after their walks


@dataclass(frozen=True)
class Deficiency:
    """A combination of parameters the data cannot determine (a null direction of the fit).

    Attributes:
        parameters: the DH parameters in it
        coefficients: their coefficients in the null direction (the first is 1)
        description: the combination in words
    """

    parameters: tuple[str, ...]
    coefficients: tuple[float, ...]
    description: str


@dataclass(frozen=True)
class TruthErrors:
    """Errors of an identification against the truth a simulated record holds.

    Attributes:
        link_types_true: the true link type per module (0, 1, 2)
        link_types_right: whether each module's estimated link type is the true one
        tool_tip_rms: RMS of the tool tip's position error over the run, base frame [m]
        tool_tip_max: its largest value [m]
        axis_angle_max: per module present in both, the largest angle between the estimated
            and the true joint axis over the run [rad]
    """

    link_types_true: tuple[int, ...]
    link_types_right: tuple[bool, ...]
    tool_tip_rms: float
    tool_tip_max: float
    axis_angle_max: dict[int, float]


@dataclass(frozen=True)
class KinematicIdentification:
    """The identified kinematic model of an Aaria arm.

    Attributes:
        table: the estimated 8 × 5 extended DH table ``[alpha, a, theta, d, link type]``
        link_types: the estimated link type of each module (0 empty, 1 revolute, 2 prismatic)
        mounts: every IMU's estimated mount, in record order (base and tool: identity, as
            defined; empty slots: zero pose, parent ``""``)
        parameter_names: the fitted parameters (``alpha2``, ``d2``, ``a2``, ``a7``,
            ``imu_link2_a.rx`` … ``.z``: rotation vector [rad] and position [m] in the link's
            post-joint frame)
        estimates: their values [rad, m]
        sigmas: their standard deviations from the fit (NaN: not determined by the data)
        residual_rms: per predicted IMU, the RMS of the gyroscope [rad/s] and accelerometer
            [m/s²] residuals over the whole run
        deficiencies: the parameter combinations the data cannot determine
        truth: errors against the truth the record holds, or None
        fit: how the fit went (samples used, function evaluations, seconds, start's RMS)
    """

    table: Array
    link_types: tuple[int, ...]
    mounts: tuple[ImuMount, ...]
    parameter_names: tuple[str, ...]
    estimates: Array
    sigmas: Array
    residual_rms: dict[str, dict[str, float]]
    deficiencies: tuple[Deficiency, ...]
    truth: TruthErrors | None
    fit: dict[str, Any]

    def to_json(self) -> dict[str, Any]:
        """A JSON-ready dict of everything (arrays as lists, NaN as None)."""
        out: dict[str, Any] = {
            "table": self.table.tolist(),
            "link_types": list(self.link_types),
            "parameters": [
                {"name": name, "estimate": float(value), "sigma": json_number(sigma)}
                for name, value, sigma in zip(
                    self.parameter_names, self.estimates, self.sigmas, strict=True
                )
            ],
            "mounts": [
                {
                    "name": m.name,
                    "parent": m.parent,
                    "T_parent_imu": np.asarray(m.T_parent_imu).tolist(),
                }
                for m in self.mounts
            ],
            "residual_rms": self.residual_rms,
            "deficiencies": [
                {
                    "parameters": list(d.parameters),
                    "coefficients": list(d.coefficients),
                    "description": d.description,
                }
                for d in self.deficiencies
            ],
            "fit": self.fit,
            "truth": None,
        }
        if self.truth is not None:
            t = self.truth
            out["truth"] = {
                "link_types_true": list(t.link_types_true),
                "link_types_right": list(t.link_types_right),
                "tool_tip_rms_m": json_number(t.tool_tip_rms),
                "tool_tip_max_m": json_number(t.tool_tip_max),
                "axis_angle_max_rad": {str(k): v for k, v in t.axis_angle_max.items()},
            }
        return out


def _derivatives(time: Array, values: Array, order: int) -> list[Array]:
    """The first ``order`` derivatives of sampled values by a quintic interpolating spline."""
    from scipy.interpolate import make_interp_spline

    spline = make_interp_spline(time, values, k=5 if time.size > 5 else time.size - 1, axis=0)
    return [spline.derivative(k)(time) for k in range(1, order + 1)]


def _smoothed(time: Array, values: Array, level: float, deriv: int) -> Array:
    """Noisy samples smoothed (``deriv`` 0) or differentiated (1), the window chosen by the data.

    A Savitzky–Golay cubic per column over the longest of the windows :data:`_WINDOWS` whose
    estimate agrees with every shorter window's within :data:`_AGREE` times the shorter one's
    noise (Lepski's rule: the noise of each window's estimate is known from the white noise
    ``level`` and the filter's coefficients; a longer window is taken until it starts to bend
    the motion). Against the noise-free derivative of random arm 16's base gyroscope (ADIS16485
    noise, 30 s at 200 Hz, true RMS 0.10, 0.0095, 0.0040 rad/s²): one fixed 0.5 s window left
    2.0e-3 rad/s² RMS on each axis, a smoothing spline with the noise's smoothness
    (``s = n·level²``) 1.5e-3, 4.4e-4, 6.4e-4, this rule 1.1e-3, 3.4e-4, 2.8e-4; that arm's
    tool tip went from 0.42 m to 8 cm (the base's small rotations carry the lengths its
    joints' own motion does not show: what is left is the noise's limit, not the filter's).

    Args:
        time: sample times [s]
        values: T × C samples
        level: the white noise's per-sample standard deviation [units of values]
        deriv: 0 (smoothed values) or 1 (their time derivative)

    Returns:
        T × C, smoothed values or derivatives [units (per second)].
    """
    from scipy.signal import savgol_coeffs, savgol_filter

    step = float(np.median(np.diff(time)))
    samples = values.shape[0]
    longest = samples if samples % 2 else samples - 1
    sizes = sorted({min(max(5, 2 * round(w / step / 2) + 1), longest) for w in _WINDOWS})
    if sizes[0] < 5:
        if deriv == 0:
            return values.copy()
        (derivative,) = _derivatives(time, values, 1)
        return derivative
    estimates = [
        np.asarray(savgol_filter(values, n, 3, deriv=deriv, delta=step, axis=0)) for n in sizes
    ]
    noise = [
        level * float(np.linalg.norm(savgol_coeffs(n, 3, deriv=deriv, delta=step))) for n in sizes
    ]
    out = np.empty_like(values, dtype=float)
    for column in range(values.shape[1]):
        chosen = 0
        for k in range(1, len(sizes)):
            agree = all(
                np.sqrt(np.mean((estimates[k][:, column] - estimates[j][:, column]) ** 2))
                <= _AGREE * noise[j]
                for j in range(k)
            )
            if not agree:
                break
            chosen = k
        out[:, column] = estimates[chosen][:, column]
    return out


def _layout(record: RunRecord) -> tuple[ArmLayout, int, tuple[int, ...]]:
    """The arm's structure from the encoders and the IMUs' parents: layout, base IMU, types."""
    parents = [mount.parent for mount in record.imu_mounts]
    for needed in (BASE_PARENT, TOOL_PARENT):
        if needed not in parents:
            raise ParameterError(
                f"record has no IMU on {needed!r}; allowed: a DH run with base and tool IMUs",
                parameter="record",
                value=needed,
                allowed="base and tool IMUs",
            )
    base, tool = parents.index(BASE_PARENT), parents.index(TOOL_PARENT)
    if record.q.shape[1] != 6:
        raise ParameterError(
            f"record has {record.q.shape[1]} joint columns; allowed: 6 (a DH run by module)",
            parameter="record",
            value=record.q.shape[1],
            allowed="6 joint columns",
        )
    modules, link_imus = [], []
    for module in range(1, 7):
        on_link = tuple(i for i, p in enumerate(parents) if p == f"link{module}")
        moving = float(np.ptp(record.q[:, module - 1])) > _MOVING
        if not moving and not on_link:
            continue
        if not on_link or not moving:
            problem = "moves but no IMU is on its link" if moving else "has IMUs but never moves"
            raise ParameterError(
                f"module {module} {problem}; allowed: a moving joint with an IMU on its link, "
                "or an empty module",
                parameter="record",
                value=f"module {module}",
                allowed="a moving joint with an IMU on its link, or an empty module",
            )
        modules.append(module)
        link_imus.append(on_link)
    if not modules:
        raise ParameterError(
            "no module moves; allowed: at least one moving joint",
            parameter="record",
            allowed="at least one moving joint",
        )
    return ArmLayout(tuple(modules), ("",) * len(modules), tuple(link_imus), tool), base, ()


def _kinds(record: RunRecord, layout: ArmLayout, base: int, qd: Array) -> tuple[str, ...]:
    kinds = []
    for index, group in enumerate(layout.link_imus):
        parent = base if index == 0 else layout.link_imus[index - 1][0]
        kind, _ = detect_kind(record.imu[:, group[0], :3], record.imu[:, parent, :3], qd[:, index])
        kinds.append(kind)
    return tuple(kinds)


def _weights(rate: float, noise_parameters: Any = None) -> Array:
    """1 / each signal's per-sample noise level at the record's rate (gyroscope, accelerometer).

    The level is the white noise's ``density·√(rate/2)`` and the quantisation's ``lsb/√12``
    added in quadrature, from the record's ``noise_parameters`` (the noise it was simulated
    with) or else ADIS16485's: on noise-free records only the ratio of the two matters. (The
    first version converted the gyroscope's density, already in rad/s/√Hz, from degrees again:
    the gyroscopes weighed 57 times too much, the accelerometers that carry the lengths too
    little; with ADIS16485 noise 10 of 20 random arms were within 1 cm.)
    """
    parameters = noise_parameters if isinstance(noise_parameters, dict) else {}
    levels = []
    for sensor, units, model in (
        ("gyro", "rad_s", ADIS16485.gyro),
        ("accel", "m_s2", ADIS16485.accel),
    ):
        density = float(
            parameters.get(f"{sensor}_noise_density_{units}_sqrtHz", model.noise_density)
        )
        lsb = float(parameters.get(f"{sensor}_lsb_{units}", model.lsb))
        level = np.hypot(density * np.sqrt(rate / 2.0), lsb / np.sqrt(12.0))
        levels += [1.0 / level] * 3
    return np.array(levels)


def _table(layout: ArmLayout, x: Array, q: Array) -> Array:
    """The 8 × 5 table of a parameter vector (lengths within a millimetre below 0 set to 0)."""
    x = x.copy()
    lengths = _length_indices(layout)
    x[lengths] = np.where((x[lengths] < 0) & (x[lengths] > -_ROUND_UP), 0.0, x[lengths])
    table = np.zeros((8, 5))
    for index, (module, kind) in enumerate(zip(layout.modules, layout.kinds, strict=True)):
        alpha, second, a = x[3 * index : 3 * index + 3]
        if kind == "revolute":
            table[module - 1] = [wrap_angle(alpha), a, 0.0, second, 1]
        else:
            rail = 2.0 * float(np.max(np.abs(q[:, index]))) * (1 + 1e-9)
            table[module - 1] = [wrap_angle(alpha), a, wrap_angle(second), rail, 2]
    table[6] = [0.0, x[layout.n_dh - 1], 0.0, 0.0, 1]
    return table


def _mounts(record: RunRecord, layout: ArmLayout, x: Array) -> tuple[ImuMount, ...]:
    poses: dict[int, Array] = {}
    for index, group in enumerate(layout.link_imus):
        for position, imu in enumerate(group):
            offset = layout.mount_offset(index, position)
            T = np.eye(4)
            T[:3, :3] = rotation_from_vector(x[offset : offset + 3])
            T[:3, 3] = x[offset + 3 : offset + 6]
            poses[imu] = T
    out = []
    for i, mount in enumerate(record.imu_mounts):
        if mount.parent in (BASE_PARENT, TOOL_PARENT):
            out.append(ImuMount(mount.name, mount.parent, np.eye(4)))
        elif i in poses:
            out.append(ImuMount(mount.name, mount.parent, poses[i]))
        else:
            out.append(ImuMount(mount.name, "", np.zeros((4, 4))))
    return tuple(out)


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


def _deficiencies(
    jacobian: Array, names: Sequence[str], n_dh: int
) -> tuple[tuple[Deficiency, ...], Array, Array]:
    """Null directions of the fit, named; and the parameters' standard deviations (unit σ²)."""
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
    return tuple(deficiencies), sigmas, basis


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


def _truth_errors(record: RunRecord, table: Array) -> TruthErrors | None:
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
    return TruthErrors(
        true_types,
        right,
        float(np.sqrt(np.mean(error**2))),
        float(np.max(error)),
        angles,
    )


def _levenberg_marquardt(
    residual: Any, jacobian: Any, x0: Array, max_iterations: int
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


def _length_indices(layout: ArmLayout) -> list[int]:
    """Indices of the DH lengths that must not be negative: d (revolute), every a, a7."""
    out = []
    for index, kind in enumerate(layout.kinds):
        if kind == "revolute":
            out.append(3 * index + 1)
        out.append(3 * index + 2)
    out.append(layout.n_dh - 1)
    return out


def _table_lengths(layout: ArmLayout) -> tuple[list[int], list[int]]:
    """Rows and columns of the table's lengths that must not be negative."""
    rows, columns = [6], [1]
    for module, kind in zip(layout.modules, layout.kinds, strict=True):
        rows.append(module - 1)
        columns.append(1)
        if kind == "revolute":
            rows.append(module - 1)
            columns.append(3)
    return rows, columns


def _non_negative_lengths(x: Array, basis: Array, lengths: Sequence[int]) -> Array:
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


def _start(layout: ArmLayout, data: KinematicData, measured: Array, weights: Array) -> Array:
    """The closed-form start; if it has a negative length, the best start with one forced theta.

    Equivalent tables form families the start's greedy choice of a prismatic module's theta
    can land in on the wrong side (a negative d further on); one forced quarter turn of one
    prismatic theta at a time usually reaches the valid side, where the fit need not walk.
    """
    lengths = _length_indices(layout)
    x, cost = initial_parameters(layout, data, measured, weights)
    negative = int(np.sum(x[lengths] < -_NEGATIVE_START))
    if not negative:
        return x
    best = ((negative, cost), x)
    ceiling = 10.0 * cost + measured.size  # an equivalent start fits as well as the first
    for index, kind in enumerate(layout.kinds):
        if kind != "prismatic":
            continue
        for theta in _THETA_GRID:
            trial, trial_cost = initial_parameters(
                layout, data, measured, weights, forced={index: theta}
            )
            key = (int(np.sum(trial[lengths] < -_NEGATIVE_START)), trial_cost)
            if trial_cost <= ceiling and key < best[0]:
                best = (key, trial)
        if best[0][0] == 0:
            break
    return best[1]


def _other_starts(
    layout: ArmLayout,
    data: KinematicData,
    measured: Array,
    weights: Array,
    spread: Any,
    first: Array,
) -> list[Array]:
    """Starts other than the first, each once.

    Each prismatic module's theta forced to each quarter turn (the gyroscopes cannot give it),
    and the closed-form start from four times the samples (noise sways its greedy choices).
    """
    starts: list[Array] = []
    index = spread(_INIT_SAMPLES)
    part, part_measured = data.subsample(index), measured[index]
    for module, kind in enumerate(layout.kinds):
        if kind != "prismatic":
            continue
        for theta in _THETA_GRID:
            trial, _ = initial_parameters(
                layout, part, part_measured, weights, forced={module: theta}
            )
            starts.append(trial)
    more = spread(4 * _INIT_SAMPLES)
    trial, _ = initial_parameters(layout, data.subsample(more), measured[more], weights)
    starts.append(trial)
    return [z for z in starts if not any(np.allclose(z, y) for y in [first, *starts[:0]])]


def identify_kinematics(
    record: RunRecord,
    *,
    max_fit_samples: int = _FIT_SAMPLES,
    max_iterations: int = 100,
    with_truth: bool = True,
) -> KinematicIdentification:
    """Identify an Aaria arm's structure, DH table and IMU mounts from a DH run's signals.

    Uses only ``time``, ``q`` (encoders), ``imu`` and each IMU's ``parent`` (module docstring:
    what is measured, what is defined, the steps).

    Args:
        record: a DH run's record (``read_run``, ``DatasetReader(...).record(k)``,
            ``simulate_run``): 6 joint columns by module, a base, a tool and link IMUs
        max_fit_samples: at most this many samples, evenly spread over the run, enter the
            nonlinear fit (residual RMS and truth errors use every sample)
        max_iterations: most Levenberg–Marquardt iterations of the nonlinear fit
        with_truth: compare with the truth the record holds (``senSenDH``), if any

    Returns:
        The identification.

    Raises:
        ParameterError: not a DH run with base and tool IMUs, a moving module without an IMU
            on its link, no moving module, or fewer than 20 samples.
    """
    started = _time.perf_counter()
    if record.n_samples < _MIN_SAMPLES:
        raise ParameterError(
            f"record has {record.n_samples} samples; allowed: at least {_MIN_SAMPLES}",
            parameter="record",
            value=record.n_samples,
            allowed=f"at least {_MIN_SAMPLES} samples",
        )
    layout, base, _ = _layout(record)
    time = np.asarray(record.time, dtype=float)
    columns = [m - 1 for m in layout.modules]
    q = np.asarray(record.q, dtype=float)[:, columns]
    qd, qdd = _derivatives(time, q, 2)
    layout = ArmLayout(
        layout.modules, _kinds(record, layout, base, qd), layout.link_imus, layout.tool_imu
    )
    rate = (time.size - 1) / (time[-1] - time[0])
    weights = _weights(rate, record.attributes.get("noise_parameters"))
    omega_base = np.asarray(record.imu[:, base, :3], dtype=float)
    force_base = np.asarray(record.imu[:, base, 3:], dtype=float)
    if record.attributes.get("noise"):
        # the base IMU's signals are inputs of the model: smoothed (and differentiated) with
        # windows the data choose, from the noise level the weights hold
        omega_dot = _smoothed(time, omega_base, 1.0 / weights[0], 1)
        omega_base = _smoothed(time, omega_base, 1.0 / weights[0], 0)
        force_base = _smoothed(time, force_base, 1.0 / weights[3], 0)
    else:
        (omega_dot,) = _derivatives(time, omega_base, 1)
    data = KinematicData(omega_base, omega_dot, force_base, q, qd, qdd)
    measured = np.asarray(record.imu[:, list(layout.imus)], dtype=float)

    def spread(count: int) -> Array:
        return np.unique(np.linspace(0, time.size - 1, min(count, time.size)).astype(int))

    start = spread(_INIT_SAMPLES)
    start_data, start_measured = data.subsample(start), measured[start]
    # A faint pull towards the start fixes what the data leave open (the null directions of
    # parallel axes): _PRIOR σ per metre or radian, nothing against the data's own curvature.
    # A table's lengths are not negative: where the data leave a family of equivalent tables
    # (a prismatic module's theta against the lengths after it), a steep penalty on negative
    # lengths walks the fit along it to a valid one. The walk takes many short steps and does
    # not need many samples: it runs on the start's few, then the fit ends on more.
    identity = _PRIOR * np.eye(layout.n_params)
    lengths = _length_indices(layout)

    extra = layout.n_params + len(lengths)

    def fit(
        x: Array, anchor: Array, index: Array, iterations: int
    ) -> tuple[Array, Array, Array, int]:
        part, part_measured = data.subsample(index), measured[index]

        def residual(x: Array) -> Array:
            predicted, _ = predict_signals(x, layout, part)
            return np.concatenate(
                [
                    ((predicted - part_measured) * weights).ravel(),
                    _PRIOR * (x - anchor),
                    _PENALTY * np.minimum(x[lengths], 0.0),
                ]
            )

        def jacobian(x: Array) -> Array:
            penalty = np.zeros((len(lengths), layout.n_params))
            penalty[np.arange(len(lengths)), lengths] = _PENALTY * (x[lengths] < 0.0)
            return np.vstack([weighted_jacobian(x, layout, part, weights), identity, penalty])

        x, fun, jac, done = _levenberg_marquardt(residual, jacobian, x, iterations)
        return x, fun[:-extra], jac[:-extra], done

    def rms(values: Array) -> float:
        return float(np.sqrt(np.mean(values**2)))

    walk_index, fit_index = spread(_WALK_SAMPLES), spread(max_fit_samples)
    # the weights are 1 / the noise level: a fit at the noise floor has a weighted RMS near 1
    floor = _AT_FLOOR * (1.0 if record.attributes.get("noise") else _EXACT_FLOOR)
    x0 = _start(layout, start_data, start_measured, weights)
    x, fun, _, walk = fit(x0, x0, walk_index, max_iterations)
    start_rms = rms(fun)
    x, fun, jac, iterations = fit(x, x0, fit_index, max_iterations)
    starts = 1
    if rms(fun) > floor:
        # a local minimum: other starts (the quarter turns of prismatic thetas the gyroscopes
        # cannot give, a start from more samples), each walked on few samples; the best few
        # walks fitted on all, the smallest residual kept, stopping at the noise floor
        walked: list[tuple[float, int, Array, Array, int]] = []
        for other in _other_starts(layout, data, measured, weights, spread, x0):
            z, z_fun, _, z_walk = fit(other, other, walk_index, max_iterations)
            walked.append((rms(z_fun), len(walked), z, other, z_walk))
        for z_rms, _, z, other, z_walk in sorted(walked, key=lambda item: item[:2])[:_REFITS]:
            z, z_fun, z_jac, z_iterations = fit(z, other, fit_index, max_iterations)
            starts += 1
            if rms(z_fun) < rms(fun):
                x, fun, jac, iterations, walk, start_rms, x0 = (
                    z,
                    z_fun,
                    z_jac,
                    z_iterations,
                    z_walk,
                    z_rms,
                    other,
                )
            if rms(fun) <= floor:
                break
    names = layout.parameter_names(record.imu_names)
    deficiencies, sigmas, basis = _deficiencies(jac, names, layout.n_dh)
    moved = _non_negative_lengths(x, basis, lengths)
    if not np.array_equal(moved, x):
        # a null direction is a symmetry to first order only: keep the move if the signals
        # stay as well fitted
        part = data.subsample(fit_index)

        def cost(z: Array) -> float:
            predicted, _ = predict_signals(z, layout, part)
            return float(np.sum(((predicted - measured[fit_index]) * weights) ** 2))

        if cost(moved) <= 1.01 * cost(x) + 1e-9 * fun.size:
            x = moved
    dof = max(fun.size - int(np.isfinite(sigmas).sum()), 1)
    sigmas = sigmas * np.sqrt(float(fun @ fun) / dof)
    predicted, _ = predict_signals(x, layout, data)
    error = predicted - measured
    residual_rms = {
        record.imu_names[imu]: {
            "gyro_rad_s": float(np.sqrt(np.mean(error[:, slot, :3] ** 2))),
            "accel_m_s2": float(np.sqrt(np.mean(error[:, slot, 3:] ** 2))),
        }
        for slot, imu in enumerate(layout.imus)
    }
    table = _table(layout, x, q)
    link_types = tuple(int(t) for t in table[:6, 4])
    truth = _truth_errors(record, table) if with_truth else None
    fit_summary = {
        "samples": int(fit_index.size),
        "iterations": iterations,
        "walk_iterations": walk,
        "starts": starts,
        "walk_rms_weighted": start_rms,
        "end_rms_weighted": float(np.sqrt(np.mean(fun**2))),
        "seconds": _time.perf_counter() - started,
        "valid_table": bool(np.all(table[_table_lengths(layout)] >= 0.0)),
        "defined": "base IMU frame = base frame; tool IMU frame = tool-tip frame",
    }
    return KinematicIdentification(
        table,
        link_types,
        _mounts(record, layout, x),
        names,
        x,
        sigmas,
        residual_rms,
        deficiencies,
        truth,
        fit_summary,
    )
