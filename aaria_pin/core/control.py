"""Closed-loop drives: a digital joint controller tracks a reference through the robot's dynamics.

Two laws (:data:`LAWS`), each with the gains of a :class:`~aaria_pin.core.joint_sensors.
ControllerModel`:

- ``pd``, independent joint PD, ``τ = Kp·(q_r - q_m) + Kd·(qd_r - v_m)`` (no model: gravity and
  the coupling are disturbances the gains reject). Its default gains place each joint's loop at
  the natural frequency ``ω`` with damping ``ζ`` for the joint's smallest effective inertia
  along the reference, ``m_i = min_t 1 / (M(q_r(t)) + diag(armature))⁻¹_ii`` (every sample, up
  to :data:`INERTIA_SAMPLES`): then
  ``K ≤ diag(1/(M⁻¹)_ii)·ω²`` at every pose, so the modes of ``M⁻¹·K`` (and of ``M⁻¹·D``)
  stay below ``n·ω²`` (``n·2ζω``) wherever the arm goes, which the digital loop's period
  bounds. The largest inertia along the reference was tried first (stiffer at the light
  poses): the Panda then went unstable at 20 Hz with a 1 kHz loop (``max eig(M⁻¹·Kd)·h`` = 2.4
  along its default motion, beyond the hold's bound of 2);
- ``computed-torque``, inverse-dynamics feed-forward plus PD in acceleration,
  ``τ = (M(q_m) + armature)·(qdd_r + Kp·e + Kd·ė) + b(q_m, v_m) + friction(qd_r)``,
  ``Kp = ω²``, ``Kd = 2ζ·ω``: with the nominal model exact, each joint's error obeys
  ``ë + 2ζω·ė + ω²·e = 0`` up to what the controller does not see (quantisation, noise, the
  hold between ticks, saturation).

The controller is digital: it ticks at ``ControllerModel.rate``, once per integration sub-step
(``rate / sample rate`` sub-steps per sample: a whole multiple, :func:`control_substeps`), reads
what its sensors
read (the run's encoder and torque-sensor models: an encoder's offset and counts are in the
loop, the velocity is differentiated from the counts) and holds its torque until the next tick;
the actuator model (armature, friction, torque limits) is in the plant. The kernel
(:mod:`aaria_pin.core._control_kernel`) runs the whole loop compiled.

A run whose joint gets farther than :data:`LOST_TRACKING` from its reference, or whose state is
not finite, has lost the reference (an unstable loop, or a reference the motors cannot follow):
:func:`closed_loop_simulate` reports the sample (``ClosedLoopRun.lost``) and the drive fails
the run naming the joint, the time and the gains.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TypedDict, Unpack

import numpy as np
import pinocchio as pin

from aaria_pin.core.actuator import armature
from aaria_pin.core.forward import (
    INTEGRATORS,
    Progress,
    check_integrator,
    flatten_dynamics,
    joint_torque_limits,
    kernel_base,
    kernel_motor,
    kernel_stops,
    spans,
)
from aaria_pin.core.joint_sensors import (
    ActuatorModel,
    ControllerModel,
    per_joint,
)
from aaria_pin.core.model import RobotModel
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory
from aaria_pin.errors import ParameterError

__all__ = [
    "LAWS",
    "LOST_SPEED",
    "LOST_TRACKING",
    "MAX_TICKS",
    "ClosedLoopOptions",
    "ClosedLoopRun",
    "ControllerSensing",
    "closed_loop_simulate",
    "control_substeps",
    "controller_gains",
]


LOST_TRACKING = 1.0
"""A joint this far from its reference has lost it [rad or m]: the run fails."""

LOST_SPEED = 10.0
"""A joint this much faster or slower than its reference has lost it [rad/s or m/s] (a loop
that rings at high frequency keeps its position error small: ur5 under ``pd`` at 150 Hz rang
at 2642 rad/s within 0.02 rad)."""

MAX_TICKS = 1000
"""Most controller ticks (integration steps) per sample."""

INERTIA_SAMPLES = 10_000
"""Poses of the reference where the ``pd`` gains' effective inertia is evaluated (at most; every
sample of a run up to that: 2.2 ms for ur5's 1001 samples, CRBA per pose and one batched
inverse, against 20 ms with an inverse per pose; 64 poses missed ur5's lightest by 0.3 %)."""


@dataclass(frozen=True)
class ControllerSensing:
    """What the controller reads with, model order (draws already made).

    Attributes:
        encoder_step: each encoder's count [rad or m] (0: none), or None: no encoders (the
            controller reads the true state)
        encoder_offset: each encoder's zero offset [rad or m]
        encoder_noise: its white noise, 1σ [rad or m]
        torque_scale: each torque sensor's scale error [1], or None: no torque sensors
        torque_bias: its zero offset [N·m or N]
        torque_resolution: its quantisation step [N·m or N] (0: none)
        torque_noise: its white noise, 1σ [N·m or N]
        encoder_generator: the source of the encoders' noise at the controller's ticks
        torque_generator: the source of the torque sensors' noise at its ticks
    """

    encoder_step: Array | None
    encoder_offset: Array
    encoder_noise: Array
    torque_scale: Array | None
    torque_bias: Array
    torque_resolution: Array
    torque_noise: Array
    encoder_generator: np.random.Generator
    torque_generator: np.random.Generator


class ClosedLoopOptions(TypedDict, total=False):
    """The options of :func:`closed_loop_simulate` (every key optional).

    Attributes:
        actuator: the joints' motors, model order (None: torques act on the joints as they are)
        integrator: ``"rk4"`` (default) or ``"euler"`` (:data:`~aaria_pin.core.forward.
            INTEGRATORS`)
        stops: lower and upper position limits held by stiff-damped stops (None: none)
        sensing: what the controller reads with (None: the true state)
        progress: told ``(samples done, samples)`` as the run goes
    """

    actuator: ActuatorModel | None
    integrator: str
    stops: tuple[Array, Array] | None
    sensing: ControllerSensing | None
    progress: Progress | None


@dataclass(frozen=True)
class ClosedLoopRun:
    """A closed-loop run's result.

    Attributes:
        trajectory: the motion that resulted (model order)
        command: the controller's torque at each sample's tick (T × n) [N·m or N]
        kp: the stiffness gains (``pd``: [N·m/rad or N/m]; ``computed-torque``: [1/s²])
        kd: the damping gains (``pd``: [N·m·s/rad or N·s/m]; ``computed-torque``: [1/s])
        substeps: the controller's ticks (and integration steps) per sample
        lost: the first sample farther than :data:`LOST_TRACKING` from the reference (or not
            finite), -1: none
    """

    trajectory: JointTrajectory
    command: Array
    kp: Array
    kd: Array
    substeps: int
    lost: int


def control_substeps(controller: ControllerModel, rate: float) -> int:
    """The controller's ticks per sample: ``controller.rate / rate``, a whole number.

    Raises:
        ParameterError: a control rate that is not a whole multiple of the sample rate, from
            1 to :data:`MAX_TICKS` times it (parameter ``controller``).
    """
    ticks = float(controller.rate) / rate  # type: ignore[arg-type]
    whole = round(ticks)
    if not (1 <= whole <= MAX_TICKS and abs(ticks - whole) <= 1e-9 * ticks):
        raise ParameterError(
            f"controller rate is {controller.rate:g} Hz for samples at {rate:g} Hz; allowed: a "
            f"whole multiple of the sample rate, 1 to {MAX_TICKS} times it ({rate:g}, "
            f"{2 * rate:g}, ... Hz)",
            parameter="controller",
            value=controller.rate,
            element="rate",
        )
    return whole


def controller_gains(
    robot: RobotModel,
    reference: JointTrajectory,
    law: str,
    controller: ControllerModel,
    actuator: ActuatorModel | None = None,
) -> tuple[Array, Array]:
    """The gains of a law (module docstring), model order: given ones kept, others from ``ω``.

    Args:
        robot: the model
        reference: the motion to track (its poses give the ``pd`` gains' inertia)
        law: one of :data:`LAWS`
        controller: the controller (frequency, damping, given gains)
        actuator: the motors (their armature adds to the inertia)

    Returns:
        ``(kp, kd)``, n each.
    """
    n = robot.n_joints
    omega = 2 * np.pi * per_joint(controller.frequency, n, "frequency")
    zeta = per_joint(controller.damping, n, "damping")
    return LAWS[law](robot, reference, controller, actuator, omega, zeta)


def _pd_gains(
    robot: RobotModel,
    reference: JointTrajectory,
    controller: ControllerModel,
    actuator: ActuatorModel | None,
    omega: Array,
    zeta: Array,
) -> tuple[Array, Array]:
    """``pd``: ``Kp = m·ω²``, ``Kd = 2ζ·m·ω`` (``m`` the smallest effective inertia), or given."""
    n = robot.n_joints
    inertia = _smallest_effective_inertia(robot, reference, actuator)
    kp = per_joint(controller.kp, n, "kp")
    kd = per_joint(controller.kd, n, "kd")
    kp = np.where(kp > 0, kp, inertia * omega**2)
    kd = np.where(kd > 0, kd, 2 * zeta * inertia * omega)
    return kp, kd


def _computed_torque_gains(
    robot: RobotModel,
    reference: JointTrajectory,
    controller: ControllerModel,
    actuator: ActuatorModel | None,
    omega: Array,
    zeta: Array,
) -> tuple[Array, Array]:
    """``computed-torque``: ``Kp = ω²``, ``Kd = 2ζ·ω`` (the error's own dynamics)."""
    return omega**2, 2 * zeta * omega


Gains = Callable[
    [RobotModel, JointTrajectory, ControllerModel, ActuatorModel | None, Array, Array],
    tuple[Array, Array],
]
"""A law's gains rule: ``(robot, reference, controller, actuator, ω, ζ) -> (kp, kd)``."""

LAWS: dict[str, Gains] = {"pd": _pd_gains, "computed-torque": _computed_torque_gains}
"""The closed-loop drives (a run's ``drive``), each with its gains rule, in the order of
:data:`~aaria_pin.core.joint_sensors.CLOSED_LOOP_DRIVES`: a law's position is its code in the
compiled kernel (``PD``, ``COMPUTED_TORQUE`` of :mod:`aaria_pin.core._control_kernel`)."""


def _smallest_effective_inertia(
    robot: RobotModel, reference: JointTrajectory, actuator: ActuatorModel | None
) -> Array:
    """``min_t 1 / (M(q_r(t)) + diag(armature))⁻¹_ii`` over up to :data:`INERTIA_SAMPLES` poses."""
    model = robot.model
    data = model.createData()
    n, nb = robot.n_joints, robot.base_nv
    rotor = np.zeros(n) if actuator is None else armature(actuator, n)
    picks = np.unique(np.linspace(0, reference.q.shape[0] - 1, INERTIA_SAMPLES).astype(int))
    q_full = pin.neutral(model)
    blocks = np.empty((picks.size, n, n))
    for row, t in enumerate(picks):  # CRBA per pose (Pinocchio has no batched one)
        q_full[robot.base_nq :] = reference.q[t]
        blocks[row] = pin.crba(model, data, q_full)[nb:, nb:]
    blocks = np.triu(blocks) + np.swapaxes(np.triu(blocks, 1), 1, 2) + np.diag(rotor)
    inverse = np.linalg.inv(blocks)  # one batched call
    return 1 / np.diagonal(inverse, axis1=1, axis2=2).max(axis=0)


def closed_loop_simulate(
    robot: RobotModel,
    base: BaseMotion,
    reference: JointTrajectory,
    law: str,
    controller: ControllerModel,
    **options: Unpack[ClosedLoopOptions],
) -> ClosedLoopRun:
    """Simulate the joints under a controller tracking ``reference``, the base prescribed.

    The run starts on the reference (its values and velocities at t = 0) and is integrated at
    the control period (:func:`control_substeps`), the controller ticking at every step.

    Args:
        robot: the model (with ``moving_base`` the base follows ``base``)
        base: the base motion at the sample times
        reference: the motion to track at the sample times (evenly spaced), model order
        law: one of :data:`LAWS`
        controller: the controller's gains and rate
        **options: :class:`ClosedLoopOptions`

    Returns:
        The resulting motion, the commands, the gains and where the reference was lost.

    Raises:
        ParameterError: an unknown law or integrator, or a model the compiled kernel does not
            do (continuous, spherical or mimic joints).
    """
    from aaria_pin.core._articulated_kernel import articulated_workspace
    from aaria_pin.core._control_kernel import integrate_closed

    if law not in LAWS:
        raise ParameterError(parameter="drive", value=law, allowed=", ".join(LAWS))
    integrator = check_integrator(options.get("integrator", "rk4"))
    flat = flatten_dynamics(robot)
    if flat is None:
        raise ParameterError(
            f"drive is {law!r} for joints the compiled kernel cannot do; allowed: revolute and "
            "prismatic joints about an axis",
            parameter="drive",
            value=law,
        )
    time = reference.time
    T, n = reference.q.shape
    rate = 1.0 / float(time[1] - time[0])
    substeps = control_substeps(controller, rate)
    h = 1.0 / (rate * substeps)
    actuator = options.get("actuator")
    kp, kd = controller_gains(robot, reference, law, controller, actuator)
    base_arrays = kernel_base(robot, base, time)
    limit = joint_torque_limits(robot, actuator)
    feedback = per_joint(controller.torque_feedback, n, "torque_feedback")
    beta = -np.expm1(-2 * np.pi * per_joint(controller.torque_filter, n, "torque_filter") * h)
    control = (list(LAWS).index(law), kp, kd, feedback, beta, limit)
    sensing = options.get("sensing")
    alpha = _filter_weights(controller, n, h)
    refs = tuple(
        np.ascontiguousarray(x, dtype=float) for x in (reference.q, reference.qd, reference.qdd)
    )
    q, v, a, command = (np.empty((T, n)) for _ in range(4))
    q[0], v[0] = refs[0][0], refs[1][0]
    memory = np.zeros((5, n))
    motor = kernel_motor(actuator, n)
    stop = kernel_stops(options.get("stops"), n, h)
    method = INTEGRATORS.index(integrator)
    lost = np.array([np.full(n, LOST_TRACKING), np.full(n, LOST_SPEED)])
    aba = articulated_workspace(len(flat[0]))  # the plant by ABA, as the torque drive's
    for first, last in spans(T, options.get("progress") or _silent):  # noise drawn per span
        ticks = (last - first) * substeps + (1 if last == T - 1 else 0)
        kernel_sensing = _kernel_sensing(sensing, ticks, n, alpha)
        at = integrate_closed(
            flat, base_arrays, refs, h, substeps, method, motor, stop, control, kernel_sensing,
            q, v, a, command, memory, first, last, lost, aba,
        )  # fmt: skip
        if at >= 0:
            return ClosedLoopRun(JointTrajectory(time, q, v, a), command, kp, kd, substeps, at)
    return ClosedLoopRun(JointTrajectory(time, q, v, a), command, kp, kd, substeps, -1)


def _silent(done: int, samples: int) -> None:
    """No progress told (the spans still bound the noise drawn at once to 1/100 of the run)."""


def _filter_weights(controller: ControllerModel, n: int, h: float) -> Array:
    """The velocity filter's weight per tick, ``1 - exp(-2π·f_c·h)`` (1: no filter)."""
    cutoff = per_joint(controller.velocity_filter, n, "velocity_filter")
    return np.where(cutoff > 0, -np.expm1(-2 * np.pi * cutoff * h), 1.0)


def _kernel_sensing(
    sensing: ControllerSensing | None, ticks: int, n: int, alpha: Array
) -> tuple[object, ...]:
    """The sensors as the kernel reads them, with the noise of a span's ``ticks`` drawn.

    Each sensor's noise comes from its own generator, span after span in time order: a run's
    draws do not depend on how it is cut into spans.
    """
    none = np.zeros(n)
    empty = np.zeros((ticks, n))
    if sensing is None:
        return (False, none, none, empty, alpha, False, none, none, none, empty)
    encoder = sensing.encoder_step is not None
    torque = sensing.torque_scale is not None
    encoder_noise = empty
    if encoder:
        encoder_noise = sensing.encoder_noise * sensing.encoder_generator.standard_normal(
            (ticks, n)
        )
    torque_noise = empty
    if torque:
        torque_noise = sensing.torque_noise * sensing.torque_generator.standard_normal((ticks, n))
    return (
        encoder,
        sensing.encoder_offset,
        none if sensing.encoder_step is None else sensing.encoder_step,
        encoder_noise,
        alpha if encoder else np.ones(n),
        torque,
        none if sensing.torque_scale is None else sensing.torque_scale,
        sensing.torque_bias,
        sensing.torque_resolution,
        torque_noise,
    )
