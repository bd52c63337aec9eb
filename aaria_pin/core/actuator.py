"""A joint's motor and gearbox: armature, friction, torque limit (CONTRACT STUB, to be built).

``tau_motor = tau + armature·qdd + friction(qd)`` with ``armature = rotor_inertia·gear_ratio²``
and ``friction(v) = viscous·v + (coulomb + stribeck_torque·exp(-(v/stribeck_velocity)²))
·tanh(v/coulomb_velocity)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from aaria_pin.core.joint_sensors import ActuatorModel, per_joint
from aaria_pin.core.se3 import Array

__all__ = ["ActuatorModel", "ActuatorTorques", "actuator_torques", "armature", "friction"]


@dataclass(frozen=True)
class ActuatorTorques:
    """The motor's torques beside the rigid body's, T × n each [N·m or N].

    Attributes:
        armature: ``armature·qdd``
        friction: the friction torque
    """

    armature: Array
    friction: Array


def armature(model: ActuatorModel, joints: int) -> Array:
    """Each joint's reflected rotor inertia ``rotor_inertia·gear_ratio²`` [kg·m² or kg]."""
    inertia = per_joint(model.rotor_inertia, joints, "rotor_inertia")
    ratio = per_joint(model.gear_ratio, joints, "gear_ratio")
    return inertia * ratio * ratio


def friction(model: ActuatorModel, qd: Array) -> Array:
    """The friction torque at joint velocities ``qd`` (T × n) [N·m or N]."""
    n = qd.shape[-1]
    viscous = per_joint(model.viscous, n, "viscous")
    coulomb = per_joint(model.coulomb, n, "coulomb")
    smooth = per_joint(model.coulomb_velocity, n, "coulomb_velocity")
    stribeck = per_joint(model.stribeck_torque, n, "stribeck_torque")
    v_s = per_joint(model.stribeck_velocity, n, "stribeck_velocity")
    dry = coulomb + stribeck * np.exp(-((qd / v_s) ** 2))
    return viscous * qd + dry * np.tanh(qd / smooth)


def actuator_torques(model: ActuatorModel, qd: Array, qdd: Array) -> ActuatorTorques:
    """The armature and friction torques over a trajectory (record columns, T × n)."""
    return ActuatorTorques(armature(model, qd.shape[-1]) * qdd, friction(model, qd))
