"""Which joint torques a dynamic identification fits, and how noisy they are.

A run (or a robot) gives joint torques in one of four ways (:data:`TORQUE_SOURCES`):

- ``measured``: the joint torque sensors' ``tau_measured``
  (:class:`~aaria_pin.core.joint_sensors.TorqueSensorModel`). The sensor sits between the
  gearbox and the link (:mod:`aaria_pin.core.torque_sensor`): it reads the rigid body's torque,
  without the motor's friction and armature, with its white noise (1σ per joint, recorded in the
  run's ``torque_sensor`` attribute), which then weighs each joint (``1/σ``).
- ``current``: the motor currents ``current_measured`` [A] times each joint's torque per
  ampere ``k_t·N`` (:class:`~aaria_pin.core.joint_sensors.CurrentSensorModel`,
  :mod:`aaria_pin.core.current_sensor`): the motor's torque as a robot without torque sensors
  gives it, friction and armature in it, with the reading's noise (white and its step, 1σ in
  amperes from the run's ``current_sensor`` attribute, times ``k_t·N``) weighing each joint.
  ``k_t`` and ``N`` come from the run's ``current_sensor`` and ``actuator`` attributes, or from
  the caller (:class:`TorqueSource`: a robot's data sheet), which wins.
- ``motor``: the motor's ``tau_motor = tau + armature·qdd + friction(qd)`` as the simulator
  computed it, exact (no noise): friction and armature are in it, so they are identified beside
  the inertial parameters.
- ``rigid``: the record's ``tau`` (the rigid body's torque, exact in a simulated run).

``auto`` takes the first the record has of ``measured``, ``current``, ``motor``, ``rigid``: a
link-side torque sensor gives the bodies without the friction to separate (the cleaner fit of
the inertial parameters); without one, the currents are what a real arm logs (friction fitted
with the bodies), and a simulated run's exact ``tau_motor`` comes after them.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from aaria_pin.core.arguments import checked
from aaria_pin.core.current_sensor import amperes_to_torque
from aaria_pin.core.joint_sensors import JointValue, per_joint
from aaria_pin.core.record import RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = ["TORQUE_SOURCES", "JointTorques", "TorqueSource", "joint_torques"]

TORQUE_SOURCES = ("auto", "measured", "current", "motor", "rigid")
"""The joint torques an identification may fit (module docstring)."""

_TABLES = {"measured": "tau_measured", "current": "current_measured", "motor": "tau_motor"}
_WITH_FRICTION = ("current", "motor")


@checked
@dataclass(frozen=True)
class TorqueSource:
    """The joint torques fitted, and what turns motor currents into them.

    Attributes:
        name: one of :data:`TORQUE_SOURCES`
        torque_constant: each motor's torque constant ``k_t`` [N·m/A or N/A] (one, or one per
            joint; None: the run's ``current_sensor`` attribute's)
        gear_ratio: each gearbox's ratio ``N`` [1] (one, or one per joint; None: the run's
            ``actuator`` attribute's)
    """

    name: str = "auto"
    torque_constant: JointValue | None = None
    gear_ratio: JointValue | None = None


@dataclass(frozen=True)
class JointTorques:
    """The joint torques fitted, in the record's columns.

    Attributes:
        source: ``measured``, ``current``, ``motor`` or ``rigid``
        values: the torques, T × n [N·m or N]
        noise: each joint's noise, 1σ, n [N·m or N] (white noise and quantisation; None: not
            known, or zero)
        with_friction: whether the torques hold the motor's friction and armature
        from_currents: whether the torques are motor currents times a given ``k_t·N`` (which
            the base wrench can check: inertial_scale)
    """

    source: str
    values: Array
    noise: Array | None
    with_friction: bool
    from_currents: bool = False


def _reading_noise(model: Any, joints: int) -> Array | None:
    """A sensor's noise per joint (white and quantisation, 1σ), None if zero or unknown.

    Args:
        model: the sensor's recorded attribute (``noise``, ``resolution``), or anything else
        joints: n
    """
    if not isinstance(model, Mapping):
        return None
    white = per_joint(model.get("noise", 0.0), joints, "noise")
    step = per_joint(model.get("resolution", 0.0), joints, "resolution")
    sigma = np.sqrt(white * white + step * step / 12.0)
    return sigma if bool((sigma > 0).all()) else None


def _recorded(record: RunRecord, attribute: str, key: str) -> Any:
    """A recorded joint model's field (None: the run records no such model)."""
    model = record.attributes.get(attribute)
    return model.get(key) if isinstance(model, Mapping) else None


def _per_ampere(record: RunRecord, source: TorqueSource, joints: int) -> Array:
    """Each joint's torque per ampere ``k_t·N``, the caller's values over the run's.

    Raises:
        ParameterError: a torque constant or gear ratio neither given nor recorded, or not
            finite and > 0 (parameter ``torque_constant`` or ``gear_ratio``).
    """
    given = {
        "torque_constant": source.torque_constant
        if source.torque_constant is not None
        else _recorded(record, "current_sensor", "torque_constant"),
        "gear_ratio": source.gear_ratio
        if source.gear_ratio is not None
        else _recorded(record, "actuator", "gear_ratio"),
    }
    values = {}
    for name, value in given.items():
        if value is None:
            raise ParameterError(
                f"torques is 'current' but the run records no {name}; allowed: {name} given "
                "(the motor's data sheet)",
                parameter=name,
            )
        values[name] = per_joint(value, joints, name)
        if not (np.isfinite(values[name]).all() and (values[name] > 0).all()):
            raise ParameterError(parameter=name, value=value, allowed="finite numbers > 0")
    return amperes_to_torque(values["torque_constant"], values["gear_ratio"])


def joint_torques(record: RunRecord, source: str | TorqueSource = "auto") -> JointTorques:
    """The joint torques of ``source`` the record gives (module docstring).

    Args:
        record: the run
        source: one of :data:`TORQUE_SOURCES`, or a :class:`TorqueSource` (the torque
            constant and gear ratio of motor currents)

    Returns:
        The torques, their noise and whether friction is in them.

    Raises:
        ParameterError: an unknown source, one the record does not have, or currents without
            a torque constant or gear ratio.
    """
    chosen = source if isinstance(source, TorqueSource) else TorqueSource(source)
    name = chosen.name
    if name not in TORQUE_SOURCES:
        raise ParameterError(parameter="torques", value=name, allowed=", ".join(TORQUE_SOURCES))
    if name == "auto":
        name = next((s for s, t in _TABLES.items() if t in record.tables), "rigid")
    if name == "rigid":
        return JointTorques("rigid", np.asarray(record.tau, dtype=float), None, False)
    table = _TABLES[name]
    if table not in record.tables:
        have = [s for s, t in _TABLES.items() if t in record.tables] + ["rigid"]
        raise ParameterError(
            f"torques is {name!r} but the run has no {table}; allowed: {', '.join(have)}",
            parameter="torques",
        )
    values = np.asarray(record.tables[table], dtype=float)
    joints = values.shape[1]
    noise = None
    if name == "measured":
        noise = _reading_noise(record.attributes.get("torque_sensor"), joints)
    elif name == "current":
        per_ampere = _per_ampere(record, chosen, joints)
        values = values * per_ampere
        amperes = _reading_noise(record.attributes.get("current_sensor"), joints)
        noise = None if amperes is None else amperes * per_ampere
    return JointTorques(name, values, noise, name in _WITH_FRICTION, name == "current")
