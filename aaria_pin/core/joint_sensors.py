"""The joint-side hardware models of a run: encoders, torque sensors, actuators (CONTRACT STUB).

These dataclasses are the contract the engine, the configuration, the files and the MJCF export
share; their behaviour is built in their own modules (``core/encoder.py``,
``core/torque_sensor.py``, ``core/actuator.py``), which re-export them.

Every value is SI, per joint: a number applies to every joint, a sequence gives one value per
joint in the record's joint order. Revolute joints read rad, N·m, kg·m²; prismatic joints m, N,
kg. 0 turns a term off.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, fields
from typing import Any, TypeVar

import numpy as np

from aaria_pin.errors import ParameterError

__all__ = [
    "ActuatorModel",
    "EncoderModel",
    "JointValue",
    "TorqueSensorModel",
    "model_attributes",
    "model_from_attributes",
    "per_joint",
]

JointValue = float | Sequence[float]
"""One value for every joint, or one per joint (record order)."""


@dataclass(frozen=True)
class EncoderModel:
    """A joint encoder: ``q_measured = o + Δ·round((q + n - o)/Δ)``.

    Attributes:
        counts_per_revolution: counts per revolution of a revolute joint (0: no quantisation)
        counts_per_metre: counts per metre of a prismatic joint (0: no quantisation)
        noise: white noise before quantisation, 1σ [rad or m]
        offset: 1σ of the per-joint zero offset ``o`` drawn once per run [rad or m]
    """

    counts_per_revolution: JointValue = 0.0
    counts_per_metre: JointValue = 0.0
    noise: JointValue = 0.0
    offset: JointValue = 0.0


@dataclass(frozen=True)
class TorqueSensorModel:
    """A joint torque sensor: ``tau_measured = Q((1 + s)·tau + b + n)``.

    Attributes:
        noise: white noise, 1σ [N·m or N]
        bias: 1σ of the per-joint zero offset ``b`` drawn once per run [N·m or N]
        resolution: quantisation step ``Q`` [N·m or N] (0: none)
        scale_error: 1σ of the per-joint scale error ``s`` drawn once per run [1]
    """

    noise: JointValue = 0.0
    bias: JointValue = 0.0
    resolution: JointValue = 0.0
    scale_error: JointValue = 0.0


@dataclass(frozen=True)
class ActuatorModel:
    """A joint's motor and gearbox: ``tau_motor = tau + armature·qdd + friction(qd)``.

    Attributes:
        rotor_inertia: the motor rotor's inertia [kg·m²] (armature = rotor_inertia·gear_ratio²)
        gear_ratio: the gearbox ratio, motor turns per joint turn [1]
        viscous: viscous friction coefficient [N·m·s/rad or N·s/m]
        coulomb: Coulomb friction torque [N·m or N]
        coulomb_velocity: the smoothing velocity of the Coulomb term, ``tanh(qd/v)`` [rad/s or m/s]
        stribeck_torque: static (breakaway) friction above Coulomb, 0: no Stribeck term [N·m or N]
        stribeck_velocity: the Stribeck velocity [rad/s or m/s]
        torque_limit: the motor's torque limit [N·m or N] (0: the model's effort limit)
    """

    rotor_inertia: JointValue = 0.0
    gear_ratio: JointValue = 1.0
    viscous: JointValue = 0.0
    coulomb: JointValue = 0.0
    coulomb_velocity: JointValue = 0.01
    stribeck_torque: JointValue = 0.0
    stribeck_velocity: JointValue = 0.1
    torque_limit: JointValue = 0.0


Model = TypeVar("Model", EncoderModel, TorqueSensorModel, ActuatorModel)


def per_joint(value: JointValue, joints: int, name: str) -> np.ndarray:
    """A model's value for each of ``joints`` joints, float64 (a number repeated, or checked).

    Raises:
        ParameterError: a sequence of another length (parameter ``name``).
    """
    values = np.asarray(value, dtype=float)
    if values.ndim == 0:
        return np.full(joints, float(values))
    if values.shape != (joints,):
        raise ParameterError(
            f"{name} has {values.size} values; allowed: one number or {joints} (one per joint)",
            parameter=name,
            value=value,
            allowed=f"one number or {joints} values",
        )
    return values.copy()


def model_attributes(model: EncoderModel | TorqueSensorModel | ActuatorModel) -> dict[str, Any]:
    """A model's fields as a run records them: numbers, or lists of per-joint numbers."""
    out: dict[str, Any] = {}
    for f in fields(model):
        value = getattr(model, f.name)
        out[f.name] = float(value) if np.ndim(value) == 0 else [float(v) for v in value]
    return out


def model_from_attributes(cls: type[Model], stored: Mapping[str, Any]) -> Model:
    """The model a run's attributes record (:func:`model_attributes`); missing keys: defaults."""
    known = {f.name for f in fields(cls)}
    values = {
        key: float(value) if np.ndim(value) == 0 else tuple(float(v) for v in value)
        for key, value in stored.items()
        if key in known
    }
    return cls(**values)
