"""Which joint torques a dynamic identification fits, and how noisy they are.

A run (or a robot) gives joint torques in one of three ways (:data:`TORQUE_SOURCES`):

- ``measured``: the joint torque sensors' ``tau_measured``
  (:class:`~aaria_pin.core.joint_sensors.TorqueSensorModel`). The sensor sits between the
  gearbox and the link (:mod:`aaria_pin.core.torque_sensor`): it reads the rigid body's torque,
  without the motor's friction and armature, with its white noise (1σ per joint, recorded in the
  run's ``torque_sensor`` attribute), which then weighs each joint (``1/σ``).
- ``motor``: the motor's ``tau_motor = tau + armature·qdd + friction(qd)`` (a real robot's
  motor currents times its torque constant): friction and armature are in it, so they are
  identified beside the inertial parameters. Our runs record it without noise and record no
  motor currents (no current channel exists); a recording's currents would enter here once
  multiplied by the torque constant.
- ``rigid``: the record's ``tau`` (the rigid body's torque, exact in a simulated run).

``auto`` takes the first the record has of ``measured``, ``motor``, ``rigid``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from aaria_pin.core.joint_sensors import per_joint
from aaria_pin.core.record import RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = ["TORQUE_SOURCES", "JointTorques", "joint_torques"]

TORQUE_SOURCES = ("auto", "measured", "motor", "rigid")
"""The joint torques an identification may fit (module docstring)."""

_TABLES = {"measured": "tau_measured", "motor": "tau_motor"}


@dataclass(frozen=True)
class JointTorques:
    """The joint torques fitted, in the record's columns.

    Attributes:
        source: ``measured``, ``motor`` or ``rigid``
        values: the torques, T × n [N·m or N]
        noise: each joint's noise, 1σ, n [N·m or N] (white noise and quantisation; None: not
            known, or zero)
        with_friction: whether the torques hold the motor's friction and armature
    """

    source: str
    values: Array
    noise: Array | None
    with_friction: bool


def _sensor_noise(record: RunRecord, joints: int) -> Array | None:
    """The torque sensors' noise per joint (white and quantisation, 1σ), None if zero/unknown."""
    model = record.attributes.get("torque_sensor")
    if not isinstance(model, dict):
        return None
    white = per_joint(model.get("noise", 0.0), joints, "noise")
    step = per_joint(model.get("resolution", 0.0), joints, "resolution")
    sigma = np.sqrt(white * white + step * step / 12.0)
    return sigma if bool((sigma > 0).all()) else None


def joint_torques(record: RunRecord, source: str = "auto") -> JointTorques:
    """The joint torques of ``source`` the record gives (module docstring).

    Args:
        record: the run
        source: one of :data:`TORQUE_SOURCES`

    Returns:
        The torques, their noise and whether friction is in them.

    Raises:
        ParameterError: an unknown source, or one the record does not have.
    """
    if source not in TORQUE_SOURCES:
        raise ParameterError(parameter="torques", value=source, allowed=", ".join(TORQUE_SOURCES))
    if source == "auto":
        source = next((s for s, t in _TABLES.items() if t in record.tables), "rigid")
    if source == "rigid":
        return JointTorques("rigid", np.asarray(record.tau, dtype=float), None, False)
    table = _TABLES[source]
    if table not in record.tables:
        have = [s for s, t in _TABLES.items() if t in record.tables] + ["rigid"]
        raise ParameterError(
            f"torques is {source!r} but the run has no {table}; allowed: {', '.join(have)}",
            parameter="torques",
        )
    values = np.asarray(record.tables[table], dtype=float)
    joints = values.shape[1]
    noise = _sensor_noise(record, joints) if source == "measured" else None
    return JointTorques(source, values, noise, source == "motor")
