"""Torque-driven motion: forward dynamics with the base prescribed, integrated at a fixed step.

With the base following its prescribed motion, the joints obey
``M_jj(q)·qdd = tau - b(q, v, a_base)``, where ``b`` is the RNEA force with the joints'
accelerations set to zero (gravity, Coriolis and the base's own acceleration) and ``M_jj`` the
joints' block of the mass matrix (CRBA). The state is integrated with the classical fourth-order
Runge–Kutta scheme, ``substeps`` steps per sample; torques and the base state are held linear
between samples.

Pinocchio's ABA is not used here: it would let the base react to the joints' motion, while the
base here is prescribed. Solving the joints' block of the CRBA mass matrix against the RNEA bias
is the same dynamics with the base's motion imposed, as is the kernel's ABA from the base's motion.

With an actuator (:class:`~aaria_pin.core.joint_sensors.ActuatorModel`) the torques are the
motors' and the joints obey ``(M_jj(q) + diag(armature))·qdd = tau - friction(qd) - b``: the
reflected rotor inertia is added to the joints' block (what Pinocchio's ``model.armature``
adds in its CRBA, added here so the shared model is left alone and ``tau`` stays rigid-body)
and the friction (:func:`~aaria_pin.core.actuator.friction`) is taken from the motor torque.
A Coulomb term with a small ``coulomb_velocity`` makes the equations stiff: the fixed step may
then need more ``substeps``.

With ``stops`` (the ``clamp`` policy, :mod:`~aaria_pin.core.joint_limits`) each joint beyond its
position limits gets, at every integrator stage, a one-sided spring-damper
(:func:`stop_torques`): ``-k·(q - clip(q, lower, upper)) - c·qd``, nothing inside the limits.
Its gains are chosen from the sub-step ``h`` so the stop is stable with either integrator: a
critically damped stop of natural frequency ``ω = STOP_OMEGA_H / h`` per joint,
``k = m_i·ω²``, ``c = 2·m_i·ω``, with ``m_i = 1 / (M⁻¹)_ii`` the joint's effective inertia at
that state (mass matrix with armature; the diagonal ``M_ii`` alone would overstate it on a
coupled chain and make the stop unstable). One joint on its stop then moves as a critically
damped oscillator of frequency ω; with ``j`` joints on their stops at once the modes of
``M⁻¹·K`` stay at most ``j·ω²`` and the fastest damped one decays at most at ``2·j·ω``. With
``ω·h = 0.15`` that is ``|λh| ≤ 1.8`` for all six joints of an arm on their stops, inside the
stability bounds of RK4 (2.78) and semi-implicit Euler (2). The stop is stiff, not rigid: a
joint pressed on it by a torque ``τ`` sinks about ``τ / k`` past its limit (on aaria-fig2 at
100 Hz, 4 sub-steps: ω = 60 rad/s; its 2 s open-loop replay of a sine run's torques stays within
1 mm of its rails; replayed 10 s, where the drifting arm leans on its stops with torques of
1000 N·m, up to 0.15 m and 0.27 rad: more ``substeps`` make the stops stiffer).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from functools import partial
from typing import Any, TypedDict, Unpack

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike

from aaria_pin.core.actuator import armature, friction, model_effort_limits, torque_limits
from aaria_pin.core.joint_sensors import ActuatorModel, per_joint
from aaria_pin.core.kinematics import full_state, joint_configuration, joint_kind
from aaria_pin.core.model import RobotModel
from aaria_pin.core.se3 import Array
from aaria_pin.core.torque_table import check_torques
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory
from aaria_pin.errors import ModelError, ParameterError

__all__ = [
    "DEFAULT_SUBSTEPS",
    "DYNAMICS",
    "INTEGRATORS",
    "PROGRESS_SPAN",
    "PROGRESS_STEPS",
    "STOP_OMEGA_H",
    "ForwardOptions",
    "Progress",
    "base_states",
    "check_integrator",
    "flatten_dynamics",
    "forward_simulate",
    "joint_torque_limits",
    "kernel_base",
    "kernel_motor",
    "kernel_stops",
    "reference_forward_simulate",
    "spans",
    "stop_torques",
]

DEFAULT_SUBSTEPS = 4
"""Integration steps per sample."""

INTEGRATORS = ("rk4", "euler")
"""The integrators of :func:`forward_simulate`: classical Runge–Kutta, semi-implicit Euler."""


def check_integrator(name: str) -> str:
    """``name`` if it is one of :data:`INTEGRATORS` (the one check of a given integrator).

    Raises:
        ParameterError: another name (parameter ``integrator``).
    """
    if name not in INTEGRATORS:
        raise ParameterError(parameter="integrator", value=name, allowed=", ".join(INTEGRATORS))
    return name


PROGRESS_STEPS = 100
"""Times a run's ``progress`` is told as its integration goes (at most)."""

PROGRESS_SPAN = 100
"""Fewest samples the kernel integrates between two calls of a run's ``progress``."""

Progress = Callable[[int, int], None]
"""Told ``(samples done, samples)`` as a long integration goes."""

STOP_OMEGA_H = 0.15
"""The stops' natural frequency times the sub-step, ``ω·h`` (module docstring)."""


def stop_torques(
    q: Array, v: Array, inertia: Array, stops: tuple[Array, Array], omega: float
) -> Array:
    """The stops' torques at one state: a critically damped spring-damper beyond each limit.

    Args:
        q: joint values [rad or m]
        v: joint velocities [rad/s or m/s]
        inertia: each joint's effective inertia ``1 / (M⁻¹)_ii`` [kg·m² or kg]
        stops: lower and upper position limits [rad or m], model order
        omega: the stops' natural frequency [rad/s]

    Returns:
        ``-m_i·ω²·(q - clip(q, lower, upper)) - 2·m_i·ω·qd`` where q is outside, else 0
        [N·m or N].
    """
    lower, upper = stops
    outside = (q < lower) | (q > upper)
    edge = np.where(q < lower, lower, upper)
    force = -inertia * omega * omega * (q - edge) - 2 * inertia * omega * v
    return np.where(outside, force, 0.0)


class ForwardOptions(TypedDict, total=False):
    """The options of :func:`forward_simulate` (every key optional).

    Attributes:
        substeps: integration steps per sample (default :data:`DEFAULT_SUBSTEPS`)
        actuator: the joints' motors, model order (None, the default: the torques act on the
            joints as they are); with one, ``torques`` are motor torques, saturated at each
            motor's torque limit (:func:`~aaria_pin.core.actuator.torque_limits`) as a real
            drive does
        integrator: ``"rk4"`` (classical Runge–Kutta, the default) or ``"euler"``
            (semi-implicit Euler: velocity first, then position with the new velocity)
        stops: lower and upper position limits [rad or m], model order, held by stiff-damped
            stops (:func:`stop_torques`; None, the default: no stops)
        progress: told ``(samples done, samples)`` as the integration goes (:func:`spans`;
            None, the default: silent)
        articulated: the kernel by ABA (O(n); CRBA beyond the ``stops``); default False: CRBA
    """

    substeps: int
    actuator: ActuatorModel | None
    integrator: str
    stops: tuple[Array, Array] | None
    progress: Progress | None
    articulated: bool


def forward_simulate(
    robot: RobotModel,
    base: BaseMotion,
    torques: ArrayLike,
    time: Array,
    q0: ArrayLike,
    v0: ArrayLike,
    **options: Unpack[ForwardOptions],
) -> JointTrajectory:
    """Integrate the joints' motion under given torques, the base prescribed, in one compiled call.

    The compiled kernel (:mod:`aaria_pin.core._forward_kernel`) runs the whole integration; a
    model it does not do (:func:`flatten_dynamics` returns None) takes the Pinocchio path,
    :func:`reference_forward_simulate` (RK4 only).

    Args:
        robot: the model (with ``moving_base`` the base follows ``base``)
        base: the base motion at the sample times
        torques: (T, n) joint torques [N·m] or forces [N], model order, at the sample times
        time: (T,) sample times, evenly spaced [s]
        q0: initial joint values [rad or m]
        v0: initial joint velocities [rad/s or m/s]
        **options: :class:`ForwardOptions` (sub-steps, actuator, integrator, stops)

    Returns:
        Joint values, velocities and accelerations at the sample times.

    Raises:
        ParameterError: an unknown ``integrator``, or one the model's path does not offer.
    """
    substeps = options.get("substeps", DEFAULT_SUBSTEPS)
    actuator = options.get("actuator")
    integrator = check_integrator(options.get("integrator", "rk4"))
    flat = flatten_dynamics(robot)
    if flat is None:
        if integrator != "rk4":
            raise ParameterError(
                f"integrator is {integrator!r} for joints the kernel cannot do; allowed: rk4",
                parameter="integrator",
                value=integrator,
                allowed="rk4",
            )
        return reference_forward_simulate(
            robot,
            base,
            torques,
            time,
            q0,
            v0,
            substeps=substeps,
            actuator=actuator,
            stops=options.get("stops"),
        )
    from aaria_pin.core._articulated_kernel import articulated_workspace
    from aaria_pin.core._forward_kernel import integrate

    n = robot.n_joints
    T = time.size
    tau = _checked_torques(robot, torques, time, actuator)
    base_arrays = kernel_base(robot, base, time)
    motor = kernel_motor(actuator, n)
    q = np.empty((T, n))
    v = np.empty((T, n))
    a = np.empty((T, n))
    dt = float(time[1] - time[0]) if T > 1 else 0.0
    q[0] = np.asarray(q0, dtype=float).reshape(n)
    v[0] = np.asarray(v0, dtype=float).reshape(n)
    method = INTEGRATORS.index(integrator)
    h = dt / substeps
    stop = kernel_stops(options.get("stops"), n, h)
    run = (flat, base_arrays, tau, h, substeps, method, motor, stop, q, v, a)
    fast = options.get("articulated", False)  # (): compiled as the ``kernel`` runs were made
    aba = (articulated_workspace(len(flat[0])),) if fast else ()
    for first, last in spans(T, options.get("progress")):
        integrate(*run, first, last, *aba)
    return JointTrajectory(time, q, v, a)


def kernel_stops(stops: tuple[Array, Array] | None, n: int, h: float) -> tuple[Any, ...]:
    """The stops as the kernel reads them: ``(on, lower, upper, omega)`` (h the sub-step [s])."""
    if stops is None:
        return (False, np.zeros(n), np.zeros(n), 0.0)
    lower, upper = (np.array(b, dtype=float).reshape(n) for b in stops)
    return (True, lower, upper, _omega(h))


def kernel_motor(actuator: ActuatorModel | None, n: int) -> tuple[Any, ...]:
    """The actuator as the kernel reads it: ``(on, armature, viscous, coulomb, ...)``."""
    if actuator is None:
        return (False, *(np.ones(n) for _ in range(6)))
    return (
        True,
        armature(actuator, n),
        *(
            per_joint(getattr(actuator, name), n, name)
            for name in (
                "viscous",
                "coulomb",
                "coulomb_velocity",
                "stribeck_torque",
                "stribeck_velocity",
            )
        ),
    )


def spans(samples: int, progress: Progress | None) -> Iterator[tuple[int, int]]:
    """The spans of samples the kernel integrates in turn, ``progress`` told after each.

    One span without ``progress``; with it, :data:`PROGRESS_STEPS` spans (of at least
    :data:`PROGRESS_SPAN` samples): a run in spans is the run at once, bit for bit
    (:func:`~aaria_pin.core._forward_kernel.integrate`).
    """
    last = samples - 1
    if progress is None:
        yield 0, last
        return
    size = max(PROGRESS_SPAN, -(-last // PROGRESS_STEPS))
    for first in range(0, max(last, 1), size):
        end = min(first + size, last)
        yield first, end
        progress(end + 1, samples)


def _omega(h: float) -> float:
    """The stops' natural frequency for the sub-step h [s]: ``STOP_OMEGA_H / h`` [rad/s]."""
    return STOP_OMEGA_H / h if h > 0 else 0.0


def flatten_dynamics(robot: RobotModel) -> tuple[Array, ...] | None:
    """The model as the compiled kernel reads it, or None for joints the kernel does not do.

    Per joint (0 the universe): kind (``_kinematics_kernel`` codes), unit axis, parent, column
    (joint index in model order), placement in the parent (rotation, translation), body mass
    [kg], centre of mass in the joint frame [m], rotational inertia about it [kg·m²]; and the
    gravity [m/s²]. The kernel does revolute and prismatic joints about an axis (not the
    continuous ones, with a cos/sin configuration) and a free-flyer only as the moving base.
    """
    from aaria_pin.core._kinematics_kernel import FREEFLYER, PRISMATIC, REVOLUTE

    model = robot.model
    if model.nq - robot.base_nq != robot.n_joints or model.nv - robot.base_nv != robot.n_joints:
        return None
    codes = {"revolute": REVOLUTE, "prismatic": PRISMATIC, "freeflyer": FREEFLYER}
    kinds, axes, columns = [FREEFLYER], [np.zeros(3)], [0]
    for j in range(1, model.njoints):
        try:
            kind, axis = joint_kind(model.joints[j])
        except ModelError:
            return None
        if kind == "freeflyer" and not (j == 1 and robot.moving_base):
            return None
        if kind != "freeflyer" and model.joints[j].nq != 1:
            return None
        kinds.append(codes[kind])
        axes.append(axis)
        columns.append(model.joints[j].idx_v - robot.base_nv)
    inertias = list(model.inertias)
    return (
        np.array(kinds, dtype=np.int64),
        np.array(axes, dtype=float),
        np.array(list(model.parents), dtype=np.int64),
        np.array(columns, dtype=np.int64),
        np.array([placement.rotation for placement in model.jointPlacements], dtype=float),
        np.array([placement.translation for placement in model.jointPlacements], dtype=float),
        np.array([inertia.mass for inertia in inertias], dtype=float),
        np.array([inertia.lever for inertia in inertias], dtype=float),
        np.array([inertia.inertia for inertia in inertias], dtype=float),
        np.asarray(model.gravity.linear, dtype=float).copy(),
    )


def base_states(robot: RobotModel, base: BaseMotion, time: Array) -> tuple[Array, Array, Array]:
    """The base's configuration, velocity and acceleration at the sample times, Pinocchio's.

    (:func:`~aaria_pin.core.kinematics.full_state`, the joints at rest: only the base columns
    are used.)
    """
    zeros = np.zeros((time.size, robot.n_joints))
    return full_state(robot, base, JointTrajectory(time, zeros, zeros, zeros))


def kernel_base(robot: RobotModel, base: BaseMotion, time: Array) -> tuple[Array, Array, Array]:
    """The base's state as the compiled kernels read it: its own columns, contiguous."""
    q_base, v_base, a_base = base_states(robot, base, time)
    nb_q, nb_v = robot.base_nq, robot.base_nv
    return (
        np.ascontiguousarray(q_base[:, :nb_q]),
        np.ascontiguousarray(v_base[:, :nb_v]),
        np.ascontiguousarray(a_base[:, :nb_v]),
    )


def joint_torque_limits(robot: RobotModel, actuator: ActuatorModel | None) -> Array:
    """Each joint's motor torque limit (inf without an actuator) [N·m or N]."""
    if actuator is None:
        return np.full(robot.n_joints, np.inf)
    return torque_limits(actuator, model_effort_limits(robot))


def _checked_torques(
    robot: RobotModel, torques: ArrayLike, time: Array, actuator: ActuatorModel | None
) -> Array:
    """The checked torques, clipped at the motors' limits with an actuator."""
    tau = check_torques(torques, time.size, robot.n_joints)
    if actuator is None:
        return tau
    limit = joint_torque_limits(robot, actuator)
    return np.clip(tau, -limit, limit)


def reference_forward_simulate(
    robot: RobotModel,
    base: BaseMotion,
    torques: ArrayLike,
    time: Array,
    q0: ArrayLike,
    v0: ArrayLike,
    **options: Unpack[ForwardOptions],
) -> JointTrajectory:
    """Integrate the joints' motion under given torques, the base prescribed: Pinocchio calls.

    The reference twin of :func:`forward_simulate` (classical RK4 in Python, ``pin.rnea`` and
    ``pin.crba`` per evaluation), and its path for joints the compiled kernel does not do
    (continuous joints, spherical, a free-flyer inside the chain, mimic).

    Args:
        robot: the model (with ``moving_base`` the base follows ``base``)
        base: the base motion at the sample times
        torques: (T, n) joint torques [N·m] or forces [N], model order, at the sample times
        time: (T,) sample times, evenly spaced [s]
        q0: initial joint values [rad or m]
        v0: initial joint velocities [rad/s or m/s]
        **options: :class:`ForwardOptions`: ``substeps`` (Runge–Kutta steps per sample),
            ``actuator``, ``stops`` (``integrator`` is RK4 here, whatever it says)

    Returns:
        Joint values, velocities and accelerations at the sample times.
    """
    substeps = options.get("substeps", DEFAULT_SUBSTEPS)
    actuator = options.get("actuator")
    stops = options.get("stops")
    n = robot.n_joints
    T = time.size
    tau = _checked_torques(robot, torques, time, actuator)
    q_base, v_base, a_base = base_states(robot, base, time)
    dt = float(time[1] - time[0]) if T > 1 else 0.0
    h = dt / substeps
    omega = _omega(h)
    model = robot.model
    data = model.createData()
    nb_q, nb_v = robot.base_nq, robot.base_nv
    rotor = np.zeros(n) if actuator is None else armature(actuator, n)
    if model.nq - nb_q == n:

        def configuration(q: Array) -> Array:
            return q

    else:  # continuous joints: cos θ, sin θ

        def configuration(q: Array) -> Array:
            return joint_configuration(robot, q[None, :])[0]

    def acceleration(k: float, q: Array, v: Array) -> Array:
        """Joint accelerations at fractional sample index k."""
        i = min(int(k), T - 2)
        w = k - i
        qf = np.concatenate(
            [(1 - w) * q_base[i, :nb_q] + w * q_base[i + 1, :nb_q], configuration(q)]
        )
        if nb_q:
            qf[3:7] /= np.linalg.norm(qf[3:7])
        vf = np.concatenate([(1 - w) * v_base[i, :nb_v] + w * v_base[i + 1, :nb_v], v])
        af = np.concatenate([(1 - w) * a_base[i, :nb_v] + w * a_base[i + 1, :nb_v], np.zeros(n)])
        bias = pin.rnea(model, data, qf, vf, af)[nb_v:]
        mass = pin.crba(model, data, qf)
        block = np.triu(mass)[nb_v:, nb_v:]
        block = block + np.triu(block, 1).T
        torque = (1 - w) * tau[i] + w * tau[i + 1]
        if actuator is not None:
            block = block + np.diag(rotor)
            torque = torque - friction(actuator, v)
        if stops is not None:
            inertia = 1 / np.diag(np.linalg.inv(block))
            torque = torque + stop_torques(q, v, inertia, stops, omega)
        return np.linalg.solve(block, torque - bias)

    q = np.empty((T, n))
    v = np.empty((T, n))
    a = np.empty((T, n))
    q[0], v[0] = np.asarray(q0, dtype=float), np.asarray(v0, dtype=float)
    x, y = q[0].copy(), v[0].copy()
    for i in range(T - 1):
        for s in range(substeps):
            k = i + s / substeps
            dk = 1.0 / substeps
            k1v, k1a = y, acceleration(k, x, y)
            if s == 0:
                a[i] = k1a  # the acceleration at sample i itself
            k2v, k2a = y + h / 2 * k1a, acceleration(k + dk / 2, x + h / 2 * k1v, y + h / 2 * k1a)
            k3v, k3a = y + h / 2 * k2a, acceleration(k + dk / 2, x + h / 2 * k2v, y + h / 2 * k2a)
            k4v, k4a = y + h * k3a, acceleration(k + dk, x + h * k3v, y + h * k3a)
            x = x + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
            y = y + h / 6 * (k1a + 2 * k2a + 2 * k3a + k4a)
        q[i + 1], v[i + 1] = x, y
    a[T - 1] = acceleration(float(T - 1), q[T - 1], v[T - 1])
    return JointTrajectory(time, q, v, a)


DYNAMICS: dict[str, Callable[..., JointTrajectory]] = {
    "aba": partial(forward_simulate, articulated=True),
    "kernel": forward_simulate,
    "reference": reference_forward_simulate,
}
"""The torque drive's integrators by the name a run records (attribute ``dynamics``): the
articulated-body kernel for new runs, the CRBA kernel and the Pinocchio path for older ones,
each re-making its runs bit for bit (their sums differ in the last bits: the CRBA kernel's from
Pinocchio's up to 7e-15 relative on the 0.3 fixture ``dh_torque.h5``)."""
