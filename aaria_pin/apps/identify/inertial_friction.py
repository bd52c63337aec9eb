"""Friction and armature columns of the joint torque regressor.

A motor's torque is the rigid body's plus what the motor and gearbox take
(:mod:`aaria_pin.core.actuator`), linear in three parameters per joint
(:data:`FRICTION_PARAMETERS`)::

    tau_motor - tau = Fv·qd + Fc·tanh(qd/coulomb_velocity) + Ia·qdd

the same law as :func:`aaria_pin.core.actuator.friction` (its sign: the torque the motor adds,
the sign of ``qd``; its smoothing ``tanh(qd/coulomb_velocity)``), so a run made with it is
fitted exactly. The smoothing velocity is not fitted: the run's actuator attribute gives it
(else :data:`DEFAULT_COULOMB_VELOCITY`). The Stribeck term is not modelled (a run with one is
not fitted exactly).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from aaria_pin.core.actuator import armature
from aaria_pin.core.joint_sensors import ActuatorModel, model_from_attributes, per_joint
from aaria_pin.core.record import RunRecord
from aaria_pin.core.se3 import Array

__all__ = [
    "DEFAULT_COULOMB_VELOCITY",
    "FRICTION_PARAMETERS",
    "friction_names",
    "friction_regressor",
    "friction_truth",
]

FRICTION_PARAMETERS = ("Fv", "Fc", "Ia")
"""Per joint: viscous coefficient [N·m·s/rad or N·s/m], Coulomb torque [N·m or N], armature
[kg·m² or kg]."""

DEFAULT_COULOMB_VELOCITY = float(np.asarray(ActuatorModel().coulomb_velocity))
"""The Coulomb smoothing velocity when the run records no actuator [rad/s or m/s] (the
:class:`~aaria_pin.core.joint_sensors.ActuatorModel` default)."""


def friction_names(joint_names: Sequence[str]) -> tuple[str, ...]:
    """``Fv_<joint>``, ``Fc_<joint>``, ``Ia_<joint>`` of each joint, joint by joint."""
    return tuple(f"{p}_{joint}" for joint in joint_names for p in FRICTION_PARAMETERS)


def _actuator(record: RunRecord) -> ActuatorModel | None:
    stored = record.attributes.get("actuator")
    return model_from_attributes(ActuatorModel, stored) if isinstance(stored, dict) else None


def coulomb_velocity(record: RunRecord, columns: Sequence[int]) -> Array:
    """Each model joint's Coulomb smoothing velocity (the run's actuator's, else the default)."""
    model = _actuator(record)
    if model is None:
        return np.full(len(columns), DEFAULT_COULOMB_VELOCITY)
    values = per_joint(model.coulomb_velocity, len(record.joint_names), "coulomb_velocity")
    return values[list(columns)]


def friction_truth(record: RunRecord, columns: Sequence[int]) -> Array:
    """The run's own friction parameters of each model joint, (3·n,) (zero without actuator).

    ``[Fv, Fc, Ia]`` per joint: the actuator's ``viscous``, ``coulomb`` and armature
    ``rotor_inertia·gear_ratio²``.
    """
    model = _actuator(record)
    out = np.zeros((len(columns), 3))
    if model is not None:
        n = len(record.joint_names)
        where = list(columns)
        out[:, 0] = per_joint(model.viscous, n, "viscous")[where]
        out[:, 1] = per_joint(model.coulomb, n, "coulomb")[where]
        out[:, 2] = armature(model, n)[where]
    return out.reshape(-1)


def friction_regressor(qd: Array, qdd: Array, smoothing: Array, rows: int, first: int) -> Array:
    """The friction and armature columns, (T, rows, 3·n).

    Args:
        qd: joint velocities, T × n, model order [rad/s or m/s]
        qdd: joint accelerations, T × n [rad/s² or m/s²]
        smoothing: each joint's Coulomb smoothing velocity, n [rad/s or m/s]
        rows: the rows of the regressor (signals)
        first: the row of the first joint (6 after a base wrench's rows, else 0)

    Returns:
        Zero but in joint j's row: ``qd``, ``tanh(qd/smoothing)``, ``qdd`` in its three columns.
    """
    samples, n = qd.shape
    out = np.zeros((samples, rows, 3 * n))
    joints = np.arange(n)
    out[:, first + joints, 3 * joints] = qd
    out[:, first + joints, 3 * joints + 1] = np.tanh(qd / smoothing)
    out[:, first + joints, 3 * joints + 2] = qdd
    return out
