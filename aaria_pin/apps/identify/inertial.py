"""Dynamic identification: the inertial base parameters of any robot from a run's torques.

Any :class:`~aaria_pin.core.record.RunRecord` (an Aaria DH arm, a URDF robot; the model is
rebuilt from the record, :mod:`aaria_pin.apps.record_model`) is identified the same way:

1. **Regressor** (:mod:`~aaria_pin.apps.identify.inertial_regressor`): the torques are linear in
   the standard inertial parameters, ten per body, ``tau = Y(q, v, a)·pi``, ``Y`` computed for
   the whole trajectory in two compiled passes. A whole identification of a 30 s run at
   200 Hz (ur5, ``aaria-fig2``, moving base) takes 0.13 s, most of it the QR. On a moving base
   (or a fixed one whose mount load was recorded) the free-flyer's six rows are the base
   wrench: they see every body, the base link included, so the total moving mass and its
   centre of mass become identifiable.
2. **Base parameters** (:mod:`~aaria_pin.apps.identify.inertial_base`): QR with column pivoting
   of the stacked regressor; each base parameter is named after its leading standard
   parameter and written out as the combination.
3. **Fit.** Weighted least squares on the training samples: each joint divided by its sensor
   noise 1σ when the run records it and no base wrench enters; else each signal (joint, base
   force, base moment) divided by its RMS, fitted, then divided by its own residual RMS and
   fitted again (the two-step weighted least squares of Gautier and Poignet, 2001: a quiet
   signal, such as a load cell, is not drowned by a noisy one). Standard deviations from the
   residual variance, and on the held-out samples (the last ``holdout`` fraction of the run)
   the relative RMS prediction error of each signal
   (:class:`~aaria_pin.apps.identify.inertial_result.DynamicIdentification`).

What a real robot gives: the torques fitted are the torque sensors', the motors' or the rigid
body's (:mod:`~aaria_pin.apps.identify.inertial_torques`); with the motors' the regressor gains
each joint's viscous and Coulomb friction and armature
(:mod:`~aaria_pin.apps.identify.inertial_friction`), and with motor currents and the base
wrench each joint's torque per ampere is checked against the wrench
(:mod:`~aaria_pin.apps.identify.inertial_scale`); ``consistent`` constrains every body to a
physical one (:mod:`~aaria_pin.apps.identify.inertial_consistent`), whose standard parameters
are then reported per body and can be written back to the URDF
(:mod:`~aaria_pin.apps.identify.inertial_urdf`).
"""

from __future__ import annotations

from dataclasses import fields
from typing import TYPE_CHECKING

import numpy as np

from aaria_pin.apps.identify.inertial_base import (
    DEFAULT_TOLERANCE,
    BaseParameterSet,
    base_parameters,
    triangular_factor,
)
from aaria_pin.apps.identify.inertial_friction import (
    coulomb_velocity,
    friction_names,
    friction_regressor,
    friction_truth,
)
from aaria_pin.apps.identify.inertial_regressor import (
    body_frames,
    standard_parameters,
    torque_regressor,
)
from aaria_pin.apps.identify.inertial_result import DynamicIdentification, StandardEstimate
from aaria_pin.apps.identify.inertial_torques import JointTorques, TorqueSource, joint_torques
from aaria_pin.apps.record_model import record_base, record_columns, record_model
from aaria_pin.core.arguments import checked
from aaria_pin.core.record import RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory
from aaria_pin.errors import ParameterError

if TYPE_CHECKING:  # Pinocchio loads only where a model is used
    from aaria_pin.core.model import RobotModel

__all__ = ["BASE_WRENCH_SIGNALS", "IDENTIFY_CHUNK", "identify_dynamics"]

BASE_WRENCH_SIGNALS = ("base_fx", "base_fy", "base_fz", "base_mx", "base_my", "base_mz")
"""The signals of the base wrench rows, base axes about the base origin [N, N·m]."""

IDENTIFY_CHUNK = 2048
"""Samples per piece of :func:`identify_dynamics` (a piece's regressor of a 6-joint robot on a
moving base: 2048 × 12 × 70 numbers, 14 MB)."""


def _centre_of_mass_rows(robot: RobotModel, trajectory: JointTrajectory, p: int) -> Array:
    """Rows mapping the p parameters to the robot's first moment, (T, 3, p) (bodies' first).

    ``sum_i m_i·p_i``: the whole robot's mass times its centre of mass, about the base origin,
    base axes.
    """
    from aaria_pin.core.kinematics import frame_poses

    joints, _ = body_frames(robot)
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
    rows = np.zeros((trajectory.q.shape[0], 3, p))
    for b in range(len(joints)):
        rows[:, :, 10 * b] = poses[:, b, :3, 3]
        rows[:, :, 10 * b + 1 : 10 * b + 4] = poses[:, b, :3, :3]
    return rows


def _measured(
    record: RunRecord, torques: JointTorques, base: BaseMotion, columns: list[int], wrench: bool
) -> Array:
    """The measured generalized forces, (T, nv): base wrench in base axes, then the joints."""
    tau = torques.values[:, columns]
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
        JointTrajectory(
            *(x[rows] for x in (trajectory.time, trajectory.q, trajectory.qd, trajectory.qdd))
        ),
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


def _weights(torques: JointTorques, measured: Array, columns: list[int], wrench: bool) -> Array:
    """Each signal's weight: ``1/σ`` of known sensor noise (joints only), else ``1/RMS``."""
    if torques.noise is not None and not wrench:
        return 1.0 / torques.noise[columns]
    signal_rms = np.sqrt(np.mean(np.square(measured), axis=0))
    return 1.0 / np.where(signal_rms > 0, signal_rms, 1.0)


def _standard_estimate(
    R: Array, base_set: BaseParameterSet, estimate: Array, bodies: int, consistent: bool
) -> Array:
    """Standard parameters giving the base estimate: any (OLS), or a consistent body set."""
    p = R.shape[1] - 1
    standard = np.zeros(p)
    standard[list(base_set.independent)] = estimate  # any pi with K·pi = estimate
    if not consistent:
        return standard
    from aaria_pin.apps.identify.inertial_consistent import consistent_fit

    norms = np.linalg.norm(R[:, :p], axis=0)
    scale = np.where(norms > 0, norms, 1.0)
    least_norm, *_ = np.linalg.lstsq(R[:, :p] / scale, R[:, p], rcond=1e-12)
    return consistent_fit(R, bodies, least_norm / scale)


def _residual_noise(factors: list[Array], samples: int) -> Array:
    """Each signal's noise, 1σ, from its residual of the fit weighted as given [weighted units].

    The second step of the weighted least squares of Gautier and Poignet (Control Engineering
    Practice 9(12), 2001): each signal (joint, base force or moment) is then divided by its
    own residual RMS, so a quiet signal (a load cell, a torque sensor of a small joint) is
    not drowned by a noisy one and the fit is the minimum-variance one. The residuals come
    from the signals' triangular factors (``‖A_s·x − y_s‖ = ‖R_s·[x; −1]‖``), so no pass
    over the run is repeated. A residual under 1e-6 of the signal (an exact one: a simulated
    run's torques) is taken as that, so exact signals keep their RMS weights.

    Args:
        factors: each signal's triangular factor of its weighted ``[W | y]``, (p + 1) columns
        samples: the training samples
    """
    R = triangular_factor(np.vstack(factors))
    p = R.shape[1] - 1
    norms = np.linalg.norm(R[:, :p], axis=0)
    scale = np.where(norms > 0, norms, 1.0)
    solution, *_ = np.linalg.lstsq(R[:, :p] / scale, R[:, p], rcond=1e-12)
    x = np.append(solution / scale, -1.0)
    residual = np.array([np.linalg.norm(f @ x) for f in factors])
    signal = np.array([np.linalg.norm(f[:, p]) for f in factors])
    floor = np.maximum(1e-6 * signal, np.finfo(float).tiny)
    return np.maximum(residual, floor) / np.sqrt(samples)


@checked
def identify_dynamics(
    record: RunRecord,
    *,
    holdout: float = 0.2,
    tolerance: float = DEFAULT_TOLERANCE,
    use_base_wrench: bool = True,
    chunk: int = IDENTIFY_CHUNK,
    torques: str | TorqueSource = "auto",
    friction: bool | None = None,
    consistent: bool = False,
) -> DynamicIdentification:
    """Identify the inertial base parameters of a run's robot from its q, qd, qdd and torques.

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
        torques: the joint torques fitted, one of
            :data:`~aaria_pin.apps.identify.inertial_torques.TORQUE_SOURCES` (``auto``: the
            torque sensors', else the motor currents', else the motors', else the rigid
            body's), or a :class:`~aaria_pin.apps.identify.inertial_torques.TorqueSource`
            (currents with the caller's torque constant)
        friction: fit each joint's viscous and Coulomb friction and armature
            (:mod:`~aaria_pin.apps.identify.inertial_friction`; None: when the torques hold
            them, the motors')
        consistent: constrain every body's pseudo-inertia to be positive definite and the
            friction and armature to be >= 0
            (:mod:`~aaria_pin.apps.identify.inertial_consistent`)

    Returns:
        The identification.

    Raises:
        ParameterError: a holdout outside [0, 0.9], too few training samples for the
            parameters, torques the record does not have, or friction asked of torques
            without it.
        InputFileError: a record whose model cannot be rebuilt.
    """
    import scipy.linalg

    from aaria_pin.core.run import chunk_bounds

    if not (np.isfinite(holdout) and 0 <= holdout <= 0.9):
        raise ParameterError(parameter="holdout", value=holdout, allowed="0 <= holdout <= 0.9")
    fitted = joint_torques(record, torques)
    with_friction = fitted.with_friction if friction is None else friction
    if with_friction and not fitted.with_friction:
        raise ParameterError(
            f"friction is on but the {fitted.source} torques hold no friction; allowed: "
            "torques current or motor (the torque sensors read the link side, after the gearbox)",
            parameter="friction",
        )
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
    measured = _measured(record, fitted, base, columns, wrench)
    signals = (*(BASE_WRENCH_SIGNALS if wrench else ()), *robot.joint_names)
    names, truth = standard_parameters(robot)
    bodies = len(names) // 10
    if with_friction:
        names = (*names, *friction_names(robot.joint_names))
        truth = np.concatenate([truth, friction_truth(record, columns)])
    smoothing = coulomb_velocity(record, columns)
    p, n_signals = len(names), len(signals)
    n_train = n - round(holdout * n)
    if n_train * n_signals < p or n_train < 2:
        raise ParameterError(
            parameter="holdout",
            value=holdout,
            allowed=f"a training part of at least {-(-p // n_signals)} samples (the run has {n})",
        )
    skip = 6 if robot.moving_base and not wrench else 0  # the free flyer's rows, unused
    first = 6 if wrench else 0  # the joints' first row

    def regressor(start: int, stop: int) -> Array:
        piece = _piece(base, trajectory, start, stop)
        Y = torque_regressor(robot, *piece)[:, skip:]
        if not with_friction:
            return Y
        extra = friction_regressor(piece[1].qd, piece[1].qdd, smoothing, n_signals, first)
        return np.concatenate([Y, extra], axis=2)

    weight = _weights(fitted, measured[:n_train], columns, wrench)
    # currents with the base wrench (and the friction they hold fitted): each joint's k_t·N
    # checked, with one constant column per joint for its current offset (inertial_scale)
    scaled = n_signals - first if fitted.from_currents and wrench and with_friction else 0
    q = p + scaled
    factors = [np.zeros((0, q + 1))] * n_signals  # each signal's [W | 1… | y] = Q·R
    for start, stop in chunk_bounds(n_train, chunk):
        A = np.zeros((stop - start, n_signals, q + 1))
        np.multiply(regressor(start, stop), weight[:, None], out=A[..., :p])
        np.multiply(measured[start:stop], weight, out=A[..., q])
        for j in range(scaled):
            A[:, first + j, p + j] = weight[first + j]
        factors = [triangular_factor(np.vstack([f, A[:, s]])) for s, f in enumerate(factors)]
    fit_columns = [*range(p), q]
    sigma = np.ones(n_signals)  # each weighted signal's noise, 1σ (1: the sensor's, known)
    if fitted.noise is None or wrench:
        sigma = _residual_noise([f[:, fit_columns] for f in factors], n_train)
    R_all = triangular_factor(np.vstack([f / s for f, s in zip(factors, sigma, strict=True)]))
    R = R_all[:, fit_columns]
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
    scale_rows = []
    if scaled:
        from aaria_pin.apps.identify.inertial_scale import torque_scale

        weighted = [f / s for f, s in zip(factors, sigma, strict=True)]
        c, c_std = torque_scale(weighted, first, independent, n_train)
        scale_rows = [
            {"joint": j, "scale": float(v), "std": float(e) if np.isfinite(e) else None}
            for j, v, e in zip(robot.joint_names, c, c_std, strict=True)
        ]
    standard_estimate = _standard_estimate(R, base_set, estimate, bodies, consistent)
    if consistent:
        estimate = base_set.combination @ standard_estimate
    mass_row = np.zeros(p)
    mass_row[0 : 10 * bodies : 10] = 1.0
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
        rows = _centre_of_mass_rows(robot, _piece(base, trajectory, start, stop)[1], p)
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
    _, body_names = body_frames(robot)
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
        standard=StandardEstimate(
            values=standard_estimate,
            model=truth,
            bodies=tuple(body_names),
            joints=tuple(robot.joint_names) if with_friction else (),
            consistent=consistent,
            determined=tuple(base_set.identifiable(row) for row in np.eye(p)),
            free_flyer=robot.moving_base,
        ),
        extras={
            "regressor_rows": n_train * n_signals,
            "moving_base": bool(wrench),
            "torques": fitted.source,
            "torque_noise": None if fitted.noise is None else fitted.noise[columns].tolist(),
            "signal_noise": (sigma / weight).tolist(),
            "torque_scale": scale_rows,
            **(
                {
                    "torque_scale_unchecked": "not checked, the friction is not fitted (the "
                    "scale would take up the motor's friction the currents hold)"
                }
                if fitted.from_currents and wrench and not with_friction
                else {}
            ),
        },
    )
