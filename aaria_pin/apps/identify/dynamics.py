"""Dynamic identification: the inertial base parameters of any robot from a run's torques.

Any :class:`~aaria_pin.core.record.RunRecord` (an Aaria DH arm, a URDF robot; the model is
rebuilt from the record, :mod:`aaria_pin.apps.record_model`) is identified the same way:

1. **Regressor.** The torques are linear in the standard inertial parameters, ten per body
   ``[m, m·cx, m·cy, m·cz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz]`` (inertia about the body's joint
   origin, Pinocchio's ``Inertia.toDynamicParameters`` order): ``tau = Y(q, v, a)·pi``.
   :func:`torque_regressor` computes ``Y`` for the whole trajectory in two compiled passes
   (the frame kinematics, then Newton–Euler per body), the same matrix as Pinocchio's
   ``computeJointTorqueRegressor`` (the tests hold them equal to 1e-9 relative), which has no
   batched form: 2.3 µs a sample against 6.9 µs for one Pinocchio call per sample, 2.3 times
   the batched RNEA (ur5 and ``aaria-fig2`` on a moving base, 30 s at 200 Hz, one core;
   ``benchmarks/bench_identify_dynamics.py``; 7 against 20 µs on a loaded machine). A whole
   identification of such a run takes 0.13 s, most of it the QR.
   On a moving base (or a fixed one whose mount load was recorded) the free-flyer's six rows
   are the base wrench: they see every body, the base link included, so the total moving mass
   and its centre of mass become identifiable.
2. **Base parameters.** :func:`base_parameters`: QR with column pivoting of the stacked
   regressor (columns scaled to unit norm first, so the rank does not depend on units), rank
   by a relative tolerance on the diagonal of R; the first r pivoted columns are independent,
   the others are their combinations ``W2 = W1·beta``, so the base parameters are
   ``pi_b = pi_1 + beta·pi_2``: each is named after its leading standard parameter and
   written out as the combination.
3. **Fit.** Weighted least squares on the training samples (each signal divided by its RMS,
   so a joint with small torques weighs as much as the base force), standard deviations from
   the residual variance, and on the held-out samples (the last ``holdout`` fraction of the
   run) the relative RMS prediction error of each signal.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin.apps.identify._kin_model import json_number
from aaria_pin.apps.record_model import record_base, record_columns, record_model
from aaria_pin.core.record import RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory
from aaria_pin.errors import ParameterError

if TYPE_CHECKING:  # Pinocchio loads only where a model is used
    from aaria_pin.core.model import RobotModel

__all__ = [
    "BASE_WRENCH_SIGNALS",
    "IDENTIFY_CHUNK",
    "INERTIAL_PARAMETERS",
    "BaseParameterSet",
    "DynamicIdentification",
    "base_parameters",
    "identify_dynamics",
    "reference_torque_regressor",
    "standard_parameters",
    "torque_regressor",
]

INERTIAL_PARAMETERS = ("m", "mx", "my", "mz", "Ixx", "Ixy", "Iyy", "Ixz", "Iyz", "Izz")
"""The ten standard parameters of a body, in regressor order: mass [kg], first moments
``m·c`` [kg·m] and the inertia about the body's joint origin [kg·m²]."""

BASE_WRENCH_SIGNALS = ("base_fx", "base_fy", "base_fz", "base_mx", "base_my", "base_mz")
"""The signals of the base wrench rows, base axes about the base origin [N, N·m]."""

IDENTIFY_CHUNK = 2048
"""Samples per piece of :func:`identify_dynamics` (a piece's regressor of a 6-joint robot on a
moving base: 2048 × 12 × 70 numbers, 14 MB)."""

DEFAULT_TOLERANCE = 1e-9
"""Relative tolerance of the rank: a pivot of the column-scaled regressor's R below this
fraction of the first is taken as zero. The dependencies are structural (they hold for every
state), so with any data the dependent pivots are at 1e-15; the weakest independent ones of the
presets' and the ur5's default sine motions over 10–30 s are at 1e-3."""


def _body_frames(robot: RobotModel) -> tuple[list[int], list[str]]:
    """The joints that carry a body, and each body's name.

    The bodies are the root joint's on a moving base and each actuated joint's; a body is named
    after its first link (body frame), else after its joint.
    """
    import pinocchio as pin

    model = robot.model
    joints = list(range(1, model.njoints))
    names = []
    for j in joints:
        links = [
            frame.name
            for frame in model.frames
            if frame.type == pin.FrameType.BODY and frame.parentJoint == j
        ]
        names.append(links[0] if links else str(model.names[j]))
    return joints, names


def standard_parameters(robot: RobotModel) -> tuple[tuple[str, ...], Array]:
    """The standard inertial parameters of a model, ten per body, and their names.

    Returns:
        Names ``<parameter>_<body>`` (``m_link2``, ``Izz_tool``; :data:`INERTIAL_PARAMETERS`)
        and the model's values, (10·B,) [kg, kg·m, kg·m²].
    """
    joints, bodies = _body_frames(robot)
    names = tuple(f"{p}_{body}" for body in bodies for p in INERTIAL_PARAMETERS)
    values = np.concatenate(
        [np.asarray(robot.model.inertias[j].toDynamicParameters()) for j in joints]
    )
    return names, values


def torque_regressor(robot: RobotModel, base: BaseMotion, trajectory: JointTrajectory) -> Array:
    """The joint torque regressor over a whole trajectory, (T, nv, 10·B).

    ``Y[t] @ pi`` is the generalized force of sample t (Pinocchio's RNEA, gravity included) for
    standard parameters ``pi`` (:func:`standard_parameters`); on a moving base the first six
    rows are the base wrench ``[f, n]`` in base axes about the base origin. It equals
    Pinocchio's ``computeJointTorqueRegressor`` (:func:`reference_torque_regressor`).

    The frame kinematics come from one compiled pass
    (:func:`~aaria_pin.core.kinematics.trajectory_signals`: each joint frame's angular velocity,
    proper acceleration and pose), the rest from a second one
    (:mod:`aaria_pin.apps.identify._regressor_kernel`): the angular accelerations by their
    recursion in world axes (``alpha_j = alpha_p + z·qdd + (omega_p × z)·qd`` for a revolute
    joint about z), then each body's wrench about its origin by Newton–Euler,
    ``f = m·a + alpha × h + omega × (omega × h)``, ``n = I·alpha + omega × (I·omega) + h × a``
    (``a`` the origin's acceleration less gravity, ``h = m·c``), linear in the parameters. A
    revolute joint about the world axis z through o takes ``z·(n_w + (p_i - o) × f_w)`` of each
    body i it carries, a prismatic one ``z·f_w``, the free flyer the force and the moment about
    its origin along each base axis.

    Args:
        robot: the model (revolute, prismatic and free-flyer joints)
        base: the base motion (ignored on a fixed base)
        trajectory: joint values over time, columns in model order

    Returns:
        The regressor [N·m or N per unit parameter].
    """
    from dataclasses import replace

    import pinocchio as pin

    from aaria_pin.apps.identify._regressor_kernel import regressor_kernel
    from aaria_pin.core._kinematics_kernel import FREEFLYER, PRISMATIC, REVOLUTE
    from aaria_pin.core.kinematics import joint_kind, trajectory_signals

    model = pin.Model(robot.model)  # a copy with one frame at each joint origin
    frames = []
    for j in range(1, model.njoints):
        frames.append(f"__regressor_origin_{j}")
        frame = pin.Frame(frames[-1], j, 0, pin.SE3.Identity(), pin.FrameType.OP_FRAME)
        model.addFrame(frame, False)
    probe = replace(robot, model=model, sensor_frames=())
    signals, poses = trajectory_signals(probe, base, trajectory, frames, frames)
    codes = {"revolute": REVOLUTE, "prismatic": PRISMATIC, "freeflyer": FREEFLYER}
    n_bodies = model.njoints - 1
    kinds = np.empty(n_bodies, dtype=np.int64)
    axes = np.zeros((n_bodies, 3))
    columns = np.zeros(n_bodies, dtype=np.int64)
    column = 0
    for j in range(1, model.njoints):
        kind, axis = joint_kind(model.joints[j])
        kinds[j - 1], axes[j - 1], columns[j - 1] = codes[kind], axis, column
        column += kind != "freeflyer"
    # every (row, body) pair: the body, the joint that carries it, the axis, moment or force
    pairs: list[tuple[int, int, tuple[float, ...], bool, int]] = []
    unit = np.eye(3)
    for i in range(1, model.njoints):
        k = i
        while k > 0:  # body i is carried by joint i and its ancestors
            first = model.joints[k].idx_v
            if kinds[k - 1] == FREEFLYER:  # force rows along each base axis, then moments
                pairs += [(i - 1, k - 1, tuple(unit[a % 3]), a >= 3, first + a) for a in range(6)]
            else:
                pairs.append((i - 1, k - 1, tuple(axes[k - 1]), kinds[k - 1] == REVOLUTE, first))
            k = model.parents[k]
    body, joint, pair_axis, moment, row = zip(*pairs, strict=True)
    Y = np.zeros((trajectory.q.shape[0], model.nv, 10 * n_bodies))
    regressor_kernel(
        kinds,
        np.array([model.parents[j] - 1 for j in range(1, model.njoints)], dtype=np.int64),
        columns,
        axes,
        *(np.ascontiguousarray(x, dtype=float) for x in (trajectory.qd, trajectory.qdd)),
        np.ascontiguousarray(base.omega_dot, dtype=float),
        np.ascontiguousarray(signals[..., :3]),
        np.ascontiguousarray(signals[..., 3:]),
        np.ascontiguousarray(poses[..., :3, :3]),
        np.ascontiguousarray(poses[..., :3, 3]),
        np.array(body, dtype=np.int64),
        np.array(joint, dtype=np.int64),
        np.array(pair_axis, dtype=float),
        np.array(moment, dtype=np.bool_),
        np.array(row, dtype=np.int64),
        Y,
    )
    return Y


def reference_torque_regressor(
    robot: RobotModel, base: BaseMotion, trajectory: JointTrajectory
) -> Array:
    """:func:`torque_regressor` by Pinocchio, one ``computeJointTorqueRegressor`` per sample.

    The tests' reference: about three times the cost of :func:`torque_regressor`.
    """
    import pinocchio as pin

    from aaria_pin.core.kinematics import full_state

    q, v, a = full_state(robot, base, trajectory)
    data = robot.model.createData()
    return np.stack(
        [
            np.array(pin.computeJointTorqueRegressor(robot.model, data, *x))
            for x in zip(q, v, a, strict=True)
        ]
    )


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


def _triangular_factor(A: Array) -> Array:
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
    R = _triangular_factor(W / scale)  # W = Q·R: the same column dependencies, p × p
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


@dataclass(frozen=True)
class DynamicIdentification:
    """What :func:`identify_dynamics` found.

    Attributes:
        signals: the identified signals: the base wrench (:data:`BASE_WRENCH_SIGNALS`) when it
            was used, then the joints in model order
        base: the base parameter set (names and combinations)
        estimate: the base parameters' least-squares estimate, (r,)
        std: their standard deviations from the fit, (r,)
        model_values: their values in the record's model (the truth for a simulated run), (r,)
        samples_train: samples fitted (the first part of the run)
        samples_holdout: samples held out (the last part)
        holdout_relative_rms: per signal, RMS of the held-out prediction error over the RMS of
            the measured signal (NaN for a signal that is zero throughout)
        holdout_rms: per signal, RMS of the held-out prediction error [N·m, N]
        train_relative_rms: per signal, the same on the training samples
        total_mass: the estimated total moving mass [kg] (NaN when the data cannot determine
            it: a fixed base without the mount's wrench)
        total_mass_model: the model's total mass [kg]
        com_error: RMS and max over the run of the distance between the estimated and the
            model's centre of mass of the whole robot, base frame [m] (empty when not
            determined)
        com_start: estimated and model centre of mass at the first sample, base frame [m]
        extras: anything else reported (rank tolerance, regressor size)
    """

    signals: tuple[str, ...]
    base: BaseParameterSet
    estimate: Array
    std: Array
    model_values: Array
    samples_train: int
    samples_holdout: int
    holdout_relative_rms: Array
    holdout_rms: Array
    train_relative_rms: Array
    total_mass: float
    total_mass_model: float
    com_error: dict[str, float] = field(default_factory=dict)
    com_start: dict[str, list[float]] = field(default_factory=dict)
    extras: dict[str, Any] = field(default_factory=dict)

    @property
    def worst_holdout_relative_rms(self) -> float:
        """The largest held-out relative RMS error over the signals (NaNs skipped)."""
        finite = self.holdout_relative_rms[np.isfinite(self.holdout_relative_rms)]
        return float(finite.max()) if finite.size else float("nan")

    def to_json(self) -> dict[str, Any]:
        """The result as plain JSON types (NaN as None)."""
        return {
            "signals": list(self.signals),
            "n_standard": len(self.base.standard_names),
            "n_base": self.base.rank,
            "rank_tolerance": self.base.tolerance,
            "samples_train": self.samples_train,
            "samples_holdout": self.samples_holdout,
            "holdout_relative_rms": {
                s: json_number(x)
                for s, x in zip(self.signals, self.holdout_relative_rms, strict=True)
            },
            "holdout_rms": {
                s: json_number(x) for s, x in zip(self.signals, self.holdout_rms, strict=True)
            },
            "train_relative_rms": {
                s: json_number(x)
                for s, x in zip(self.signals, self.train_relative_rms, strict=True)
            },
            "worst_holdout_relative_rms": json_number(self.worst_holdout_relative_rms),
            "total_mass": {
                "estimate": json_number(self.total_mass),
                "model": self.total_mass_model,
                "error": json_number(self.total_mass - self.total_mass_model),
            },
            "centre_of_mass": {"error": self.com_error, **self.com_start},
            "base_parameters": [
                {
                    "name": name,
                    "combination": expression,
                    "estimate": float(value),
                    "std": json_number(float(std)),
                    "model": float(truth),
                }
                for name, expression, value, std, truth in zip(
                    self.base.names,
                    self.base.expressions,
                    self.estimate,
                    self.std,
                    self.model_values,
                    strict=True,
                )
            ],
            **self.extras,
        }


def _centre_of_mass_rows(robot: RobotModel, trajectory: JointTrajectory) -> Array:
    """Rows mapping the standard parameters to the robot's first moment, (T, 3, p).

    ``sum_i m_i·p_i``: the whole robot's mass times its centre of mass, about the base origin,
    base axes.
    """
    from aaria_pin.core.kinematics import frame_poses

    joints, _ = _body_frames(robot)
    import pinocchio as pin

    model = pin.Model(robot.model)
    frames = []
    for j in joints:
        name = f"__com_origin_{j}"
        model.addFrame(pin.Frame(name, j, 0, pin.SE3.Identity(), pin.FrameType.OP_FRAME), False)
        frames.append(name)
    from dataclasses import replace

    probe = replace(robot, model=model, sensor_frames=())
    resting = BaseMotion.resting(trajectory.q.shape[0])  # poses in the base frame
    poses = frame_poses(probe, resting, trajectory, frames)
    rows = np.zeros((trajectory.q.shape[0], 3, 10 * len(joints)))
    for b in range(len(joints)):
        rows[:, :, 10 * b] = poses[:, b, :3, 3]
        rows[:, :, 10 * b + 1 : 10 * b + 4] = poses[:, b, :3, :3]
    return rows


def _measured(record: RunRecord, base: BaseMotion, columns: list[int], wrench: bool) -> Array:
    """The measured generalized forces, (T, nv): base wrench in base axes, then the joints."""
    tau = np.asarray(record.tau, dtype=float)[:, columns]
    if not wrench:
        return tau
    w = np.asarray(record.base_wrench, dtype=float)
    force = np.einsum("tji,tj->ti", base.rotation, w[:, :3])  # R_world_baseᵀ · f_world
    moment = np.einsum("tji,tj->ti", base.rotation, w[:, 3:])
    return np.hstack([force, moment, tau])


def _piece(
    base: BaseMotion, trajectory: JointTrajectory, start: int, stop: int
) -> tuple[BaseMotion, JointTrajectory]:
    """Samples ``start:stop`` of a base motion and a trajectory."""
    rows = slice(start, stop)
    return (
        BaseMotion(*(getattr(base, f.name)[rows] for f in fields(BaseMotion))),
        JointTrajectory(*(getattr(trajectory, f.name)[rows] for f in fields(JointTrajectory))),
    )


class _Sums:
    """Running sums of squares per signal, for RMS values over pieces."""

    def __init__(self, n_signals: int) -> None:
        self.error = np.zeros(n_signals)
        self.signal = np.zeros(n_signals)
        self.samples = 0

    def add(self, error: Array, signal: Array) -> None:
        self.error += np.sum(np.square(error), axis=0)
        self.signal += np.sum(np.square(signal), axis=0)
        self.samples += error.shape[0]

    def rms(self) -> tuple[Array, Array]:
        """Relative and absolute RMS error per signal (NaN without samples or signal)."""
        if self.samples == 0:
            nan = np.full(self.error.shape, np.nan)
            return nan, nan.copy()
        error = np.sqrt(self.error / self.samples)
        signal = np.sqrt(self.signal / self.samples)
        with np.errstate(divide="ignore", invalid="ignore"):
            return error / np.where(signal > 0, signal, np.nan), error


def identify_dynamics(
    record: RunRecord,
    *,
    holdout: float = 0.2,
    tolerance: float = DEFAULT_TOLERANCE,
    use_base_wrench: bool = True,
    chunk: int = IDENTIFY_CHUNK,
) -> DynamicIdentification:
    """Identify the inertial base parameters of a run's robot from its q, qd, qdd, tau.

    The model (joints, kinematics; its inertias only as the truth reported beside the
    estimates) and the base motion come from the record. The base wrench enters when the
    record has one (a moving base, or a fixed base whose mount load was recorded) and
    ``use_base_wrench``: the free-flyer's rows then identify the total mass and centre of mass.

    The run is processed in pieces of ``chunk`` samples, so memory does not grow with its
    length: a first pass folds each piece's weighted regressor and measurements ``[W | y]``
    into the triangular factor R of their QR (``[R; piece] = Q'·R'``), which holds everything
    the base parameters and the fit need; a second pass computes the prediction errors and the
    centre of mass.

    Args:
        record: the run (any robot whose joints are revolute or prismatic)
        holdout: fraction of the run, at its end, held out of the fit to test the prediction,
            0 <= holdout <= 0.9
        tolerance: relative rank tolerance (:func:`base_parameters`)
        use_base_wrench: use the base wrench rows when the record has a base wrench
        chunk: samples per piece, >= 1

    Returns:
        The identification.

    Raises:
        ParameterError: a holdout outside [0, 0.9], or too few training samples for the
            parameters.
        InputFileError: a record whose model cannot be rebuilt.
    """
    import scipy.linalg

    from aaria_pin.core.run import chunk_bounds

    if not (np.isfinite(holdout) and 0 <= holdout <= 0.9):
        raise ParameterError(parameter="holdout", value=holdout, allowed="0 <= holdout <= 0.9")
    n = record.n_samples
    motion = record_base(record)
    wrench = use_base_wrench and (
        motion is not None or bool(np.any(np.asarray(record.base_wrench) != 0))
    )
    # a moving base needs its free flyer for the joint torques, used rows or not
    robot = record_model(record, moving_base=wrench or motion is not None)
    columns = record_columns(record, robot)
    base = motion if motion is not None else BaseMotion.resting(n)
    time = np.asarray(record.time, dtype=float)
    trajectory = JointTrajectory(
        time,
        *(
            np.ascontiguousarray(np.asarray(x, dtype=float)[:, columns])
            for x in (record.q, record.qd, record.qdd)
        ),
    )
    measured = _measured(record, base, columns, wrench)
    signals = (*(BASE_WRENCH_SIGNALS if wrench else ()), *robot.joint_names)
    names, truth = standard_parameters(robot)
    p, n_signals = len(names), len(signals)
    n_train = n - round(holdout * n)
    if n_train * n_signals < p or n_train < 2:
        raise ParameterError(
            parameter="holdout",
            value=holdout,
            allowed=f"a training part of at least {-(-p // n_signals)} samples (the run has {n})",
        )
    skip = 6 if robot.moving_base and not wrench else 0  # the free flyer's rows, unused

    def regressor(start: int, stop: int) -> Array:
        return torque_regressor(robot, *_piece(base, trajectory, start, stop))[:, skip:]

    signal_rms = np.sqrt(np.mean(np.square(measured[:n_train]), axis=0))
    weight = 1.0 / np.where(signal_rms > 0, signal_rms, 1.0)
    R = np.zeros((0, p + 1))
    for start, stop in chunk_bounds(n_train, chunk):
        A = np.empty((stop - start, n_signals, p + 1))
        np.multiply(regressor(start, stop), weight[:, None], out=A[..., :p])
        np.multiply(measured[start:stop], weight, out=A[..., p])
        R = _triangular_factor(np.vstack([R, A.reshape(-1, p + 1)]))
    # [W | y] = Q·R: the least squares of any columns of W against y is the same problem on
    # the columns of R (solved on unit columns, so that it does not depend on units).
    base_set = base_parameters(R[:, :p], names, tolerance=tolerance)
    independent = list(base_set.independent)
    norms = np.linalg.norm(R[:, independent], axis=0)
    scale = np.where(norms > 0, norms, 1.0)
    R1 = R[:, independent] / scale
    estimate_scaled, *_ = np.linalg.lstsq(R1, R[:, p], rcond=None)
    estimate = estimate_scaled / scale
    residual = R1 @ estimate_scaled - R[:, p]
    dof = max(n_train * n_signals - base_set.rank, 1)
    variance = float(residual @ residual) / dof
    R11 = np.linalg.qr(R1, mode="r")
    R_inverse = scipy.linalg.solve_triangular(R11, np.eye(base_set.rank))
    std = np.sqrt(variance * np.sum(np.square(R_inverse), axis=1)) / scale
    standard_estimate = np.zeros(p)
    standard_estimate[independent] = estimate  # any pi with K·pi = estimate
    mass_row = np.zeros(p)
    mass_row[0::10] = 1.0
    mass_model = float(mass_row @ truth)
    total_mass = float(mass_row @ standard_estimate) if base_set.identifiable(mass_row) else np.nan
    with_com = bool(np.isfinite(total_mass) and total_mass > 0)
    train, held_out = _Sums(n_signals), _Sums(n_signals)
    com_sum, com_max, com_start = 0.0, 0.0, {}
    for start, stop in chunk_bounds(n, chunk):
        prediction = regressor(start, stop) @ standard_estimate
        split = min(max(n_train - start, 0), stop - start)
        error, signal = prediction - measured[start:stop], measured[start:stop]
        train.add(error[:split], signal[:split])
        held_out.add(error[split:], signal[split:])
        if not with_com:
            continue
        rows = _centre_of_mass_rows(robot, _piece(base, trajectory, start, stop)[1])
        with_com = base_set.identifiable(rows[:: max(n // 20, 1)].reshape(-1, p))
        com_estimate = (rows @ standard_estimate) / total_mass
        com_model = (rows @ truth) / mass_model
        distance = np.linalg.norm(com_estimate - com_model, axis=1)
        com_sum += float(np.sum(np.square(distance)))
        com_max = max(com_max, float(np.max(distance)))
        if start == 0:
            com_start = {
                "estimate_start": com_estimate[0].tolist(),
                "model_start": com_model[0].tolist(),
            }
    com_error = {"rms": float(np.sqrt(com_sum / n)), "max": com_max} if with_com else {}
    train_relative, _ = train.rms()
    holdout_relative, holdout_rms = held_out.rms()
    return DynamicIdentification(
        signals=signals,
        base=base_set,
        estimate=estimate,
        std=std,
        model_values=base_set.combination @ truth,
        samples_train=n_train,
        samples_holdout=n - n_train,
        holdout_relative_rms=holdout_relative,
        holdout_rms=holdout_rms,
        train_relative_rms=train_relative,
        total_mass=total_mass,
        total_mass_model=mass_model,
        com_error=com_error,
        com_start=com_start if with_com else {},
        extras={"regressor_rows": n_train * n_signals, "moving_base": bool(wrench)},
    )
