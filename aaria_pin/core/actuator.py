"""A joint's motor and gearbox: armature, friction and torque limit (:class:`ActuatorModel`).

The torque a joint's motor must give to follow a motion is the rigid body's torque (RNEA, the
record's ``tau``) plus what the motor and gearbox take themselves::

    tau_motor = tau + armature·qdd + friction(qd)

- **Armature** (reflected rotor inertia): ``armature = rotor_inertia·gear_ratio²`` [kg·m², or
  kg for a prismatic joint], the rotor's inertia seen through the gearbox at the joint.
  Pinocchio's ``rnea`` would add ``model.armature·qdd`` itself; the record keeps ``tau``
  rigid-body only and this term apart (``tau_armature``).
- **Friction** (``tau_friction``), a smooth model of viscous, Coulomb and (optional) Stribeck
  friction::

      friction(v) = viscous·v + (coulomb + stribeck_torque·exp(-(v/stribeck_velocity)²))
                                 · tanh(v/coulomb_velocity)

  It is the torque the motor must ADD: friction opposes the motion, so it has the sign of the
  velocity ``v = qd``. ``tanh(v/coulomb_velocity)`` is a smooth sign: it tends to
  ``sign(v)`` as ``coulomb_velocity → 0`` (and is 0 at rest, ``v = 0``); at
  ``|v| = 3·coulomb_velocity`` it is 0.995 of it. The Stribeck term adds the breakaway
  (static) friction ``stribeck_torque`` above Coulomb near rest, fading over
  ``stribeck_velocity``: at ``v → 0+`` (with ``coulomb_velocity → 0``) the friction tends to
  ``coulomb + stribeck_torque``, at ``|v| ≫ stribeck_velocity`` to ``coulomb·sign(v) +
  viscous·v``.
- **Torque limit**: the motor's (:func:`torque_limits`; 0: the model's effort limit). A
  prescribed motion needing more is reported, never clipped (clipping changes the motion).

Units: revolute joints rad, rad/s, N·m, N·m·s/rad; prismatic joints m, m/s, N, N·s/m. Every
value of an :class:`ActuatorModel` is one number for every joint or one per joint in the
record's joint order (:func:`~aaria_pin.core.joint_sensors.per_joint`); the model checks its
values itself (:mod:`aaria_pin.core.joint_sensors`).

MuJoCo names the armature ``armature``, the viscous coefficient ``damping``, the Coulomb torque
``frictionloss`` (dry friction, solved as a constraint: no ``tanh`` smoothing and no Stribeck
term) and the limit ``actuatorfrcrange`` (:mod:`aaria_pin.core.export.mjcf_actuators`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.core.joint_sensors import ActuatorModel, per_joint
from aaria_pin.core.se3 import Array

if TYPE_CHECKING:
    from collections.abc import Sequence

    from aaria_pin.core.model import RobotModel

__all__ = [
    "ActuatorModel",
    "ActuatorTorques",
    "actuator_torques",
    "armature",
    "friction",
    "model_effort_limits",
    "motor_torque",
    "torque_limits",
]


@dataclass(frozen=True)
class ActuatorTorques:
    """The motor's torques beside the rigid body's, T × n each [N·m or N].

    Attributes:
        armature: ``armature·qdd``
        friction: the friction torque the motor adds, :func:`friction`
    """

    armature: Array
    friction: Array


def armature(model: ActuatorModel, joints: int) -> Array:
    """Each joint's reflected rotor inertia ``rotor_inertia·gear_ratio²`` [kg·m² or kg].

    Args:
        model: the actuators
        joints: the number of joints n (record columns)

    Returns:
        The armature of each joint, n.
    """
    inertia = per_joint(model.rotor_inertia, joints, "rotor_inertia")
    ratio = per_joint(model.gear_ratio, joints, "gear_ratio")
    return inertia * ratio * ratio


def friction(model: ActuatorModel, qd: Array) -> Array:
    """The friction torque the motor adds at joint velocities ``qd`` (module docstring).

    ``viscous·qd + (coulomb + stribeck_torque·exp(-(qd/stribeck_velocity)²))·tanh(qd/
    coulomb_velocity)``: the sign of ``qd`` (friction opposes the motion, the motor adds it),
    0 at rest.

    Args:
        model: the actuators
        qd: joint velocities, T × n (or n) [rad/s or m/s]

    Returns:
        The friction torques, the shape of ``qd`` [N·m or N].
    """
    n = qd.shape[-1]
    viscous = per_joint(model.viscous, n, "viscous")
    coulomb = per_joint(model.coulomb, n, "coulomb")
    smooth = per_joint(model.coulomb_velocity, n, "coulomb_velocity")
    stribeck = per_joint(model.stribeck_torque, n, "stribeck_torque")
    v_s = per_joint(model.stribeck_velocity, n, "stribeck_velocity")
    dry = coulomb + stribeck * np.exp(-((qd / v_s) ** 2))
    return viscous * qd + dry * np.tanh(qd / smooth)


def actuator_torques(model: ActuatorModel, qd: Array, qdd: Array) -> ActuatorTorques:
    """The armature and friction torques over a trajectory (record columns, T × n).

    Args:
        model: the actuators
        qd: joint velocities, T × n [rad/s or m/s]
        qdd: joint accelerations, T × n [rad/s² or m/s²]

    Returns:
        ``armature·qdd`` and :func:`friction` of ``qd``; ``tau_motor`` is ``tau`` plus both.
    """
    return ActuatorTorques(armature(model, qd.shape[-1]) * qdd, friction(model, qd))


def motor_torque(tau: Array, parts: ActuatorTorques) -> Array:
    """The torque the motor gives, ``tau_motor = tau + armature·qdd + friction(qd)`` [N·m or N].

    Args:
        tau: the rigid body's torques, T × n [N·m or N]
        parts: the armature's and friction's torques (:func:`actuator_torques`)
    """
    return tau + parts.armature + parts.friction


def torque_limits(model: ActuatorModel, effort_limit: ArrayLike) -> Array:
    """Each joint's torque limit: the motor's ``torque_limit``, where it is 0 the model's.

    Args:
        model: the actuators
        effort_limit: the model's effort limit of each joint, n (inf: none) [N·m or N]:
            :func:`model_effort_limits` (Pinocchio's ``effortLimit``) or the URDF's ``effort``

    Returns:
        The limits, n [N·m or N] (inf: no limit).
    """
    effort = np.asarray(effort_limit, dtype=float)
    limit = per_joint(model.torque_limit, effort.size, "torque_limit")
    return np.where(limit > 0, limit, effort)


def model_effort_limits(
    robot_model: RobotModel, columns: Sequence[int] | None = None, joints: int | None = None
) -> Array:
    """The Pinocchio model's ``effortLimit`` of each record column [N·m or N].

    Args:
        robot_model: the model (its base's entries left out)
        columns: the record column of each model joint, in model order (None: the same)
        joints: the record's joint columns (default: one per model joint)

    Returns:
        The limits by record column, n; inf for a column without a model joint (an empty
        module of an Aaria arm) and where the model gives none (0).
    """
    effort = np.asarray(robot_model.model.effortLimit, dtype=float)[robot_model.base_nv :]
    effort = np.where((effort > 0) & (effort < 1e300), effort, np.inf)  # unset: huge or 0
    where = list(range(effort.size)) if columns is None else list(columns)
    out = np.full(effort.size if joints is None else joints, np.inf)
    out[where] = effort
    return out
