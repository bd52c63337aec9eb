"""Motor current sensors: ``current_measured = Q((1 + s)·tau_motor/(k_t·N) + b + n)``.

An arm without joint torque sensors (a UR5, most industrial arms) logs the current of each
joint's motor. The motor's torque on the motor side is ``k_t·i`` (``k_t`` the torque constant,
:class:`~aaria_pin.core.joint_sensors.CurrentSensorModel`), and through the gearbox of ratio
``N`` (the actuator's ``gear_ratio``) it is ``tau_motor = k_t·N·i`` at the joint, with the
rotor's inertia and the friction in it (:mod:`aaria_pin.core.actuator`). So the sensor reads
``tau_motor/(k_t·N)`` [A], with the errors of the torque sensor's law
(:func:`~aaria_pin.core.torque_sensor.torque_reading`, in amperes): ``s`` the torque
constant's error and ``b`` the zero offset, drawn once per run and joint from
``N(0, scale_error²)`` and ``N(0, bias²)``, ``n`` white noise ``N(0, noise²)`` per sample, ``Q``
the reading's step (0: none). The draws come from the run's ``current_sensor`` stream
(:func:`~aaria_pin.core.seeds.sensor_sequence`): the biases, then the scale errors, then the
noise piece by piece in time order, so a run in pieces reads what the run held whole reads.

The defaults of :class:`~aaria_pin.core.joint_sensors.CurrentSensorModel`, each from a data sheet:

- ``torque_constant`` 0.036 N·m/A: maxon EC 45 flat ∅43.5 mm, brushless, 50 W, the 24 V
  winding (maxon catalogue, "EC 45 flat 50 W" page, motor data line 12 "torque constant"
  36 mNm/A; line 13 the speed constant 265 rpm/V agrees, 60/(2π·265) = 36.0 mN·m/A; line 6
  its nominal current 2.52 A).
- ``noise`` 0.0189 A: Allegro ACS712ELCTR-05B Hall current sensor (ACS712 data sheet, "x05B
  performance characteristics" table: sensitivity 185 mV/A typical, noise V_NOISE(PP) 21 mV
  peak to peak at C_F = 47 nF, 2 kHz bandwidth, optimized range ±5 A, which holds the motor's
  nominal current). The data sheet gives peak to peak only; taken as 6σ:
  21/185/6 = 18.9 mA, 1σ.
- ``resolution`` 0.0066 A: the drive's converter, not the sensor's data sheet: 12 bits over the
  sensor's 0–5 V output (V_CC = 5 V in the same table) are 5 V/4096 = 1.22 mV, 6.6 mA at
  185 mV/A.
- ``bias`` and ``scale_error`` 0: a drive zeroes the offset at power-up; the sensitivity's
  spread, 180–190 mV/A min–max (±2.7 %, the same table), is the torque constant's error a run
  may set (``scale_error``) and identification then sees as a wrong ``k_t``.

Behind a gearbox of ratio 100 that is 3.6 N·m of joint torque per ampere and 0.068 N·m of
noise; on a ball screw of 600 rad/m (2π/600 m = 10.5 mm per turn) 21.6 N/A and 0.41 N.

These defaults suit a joint of up to about 9 N·m continuous behind a ratio of 100 (the motor's
nominal 2.52 A; the ACS712-05B's range ±5 A is 18 N·m): a wrist of a UR5-sized arm. No range
or clipping is modelled: a joint that needs more reads an unclipped current (ur5's shoulder
lift needs about 15 A RMS, 21 A peak on a 6 s Fourier run), so give such joints their own
motor's ``torque_constant`` (and sensor) per joint.

The record keeps ``current_measured`` (T × n) [A], ``current_sensor_bias`` (1 × n) [A] and
``current_sensor_scale`` (1 × n) [1]. Identification multiplies the reading back by ``k_t·N``
(:mod:`aaria_pin.apps.identify.inertial_torques`, the ``current`` torques).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from aaria_pin.core.actuator import actuator_torques, motor_torque
from aaria_pin.core.joint_sensors import (
    ActuatorModel,
    CurrentSensorModel,
    JointColumns,
    per_joint,
)
from aaria_pin.core.se3 import Array
from aaria_pin.core.torque_sensor import SensorReadings

__all__ = ["CurrentSensorModel", "CurrentSensorStream", "amperes_to_torque", "recorded_per_ampere"]


def amperes_to_torque(torque_constant: Array, gear_ratio: Array) -> Array:
    """Each joint's torque per ampere of its motor, ``k_t·N`` [N·m/A or N/A].

    Args:
        torque_constant: each motor's ``k_t``, n [N·m/A]
        gear_ratio: each gearbox's ratio ``N``, n [1]
    """
    return torque_constant * gear_ratio


def recorded_per_ampere(attributes: Mapping[str, Any], joints: int) -> Array | None:
    """Each joint's torque per ampere ``k_t·N`` a run records (None: no current sensor recorded).

    Args:
        attributes: the run's attributes (its ``current_sensor`` and ``actuator`` models)
        joints: n, the record's joint columns

    Raises:
        ParameterError: a recorded value of another length than ``joints``.
    """
    sensor, actuator = attributes.get("current_sensor"), attributes.get("actuator")
    if not isinstance(sensor, Mapping) or not isinstance(actuator, Mapping):
        return None
    constant, ratio = sensor.get("torque_constant"), actuator.get("gear_ratio")
    if constant is None or ratio is None:
        return None
    return amperes_to_torque(
        per_joint(constant, joints, "torque_constant"), per_joint(ratio, joints, "gear_ratio")
    )


class CurrentSensorStream(SensorReadings):
    """One run's motor current sensors: bias and scale drawn when made, noise piece by piece.

    It is a joint channel of the engine (``core/run/measured.py``): :meth:`tables`,
    :meth:`run_tables` (``current_sensor_bias`` [A], ``current_sensor_scale``),
    :meth:`attributes`.

    Args:
        model: the sensors
        actuator: the motors and gearboxes (their torque, and the gear ratio)
        joints: n, the record's joint columns
        noise_seed: the run's noise seed; the draws come from its ``current_sensor`` stream
    """

    name = "current_sensor"

    def __init__(
        self,
        model: CurrentSensorModel,
        actuator: ActuatorModel,
        joints: int,
        noise_seed: int | np.random.SeedSequence,
    ) -> None:
        super().__init__(model, joints, noise_seed)
        self.actuator = actuator
        self.per_ampere = amperes_to_torque(
            per_joint(model.torque_constant, joints, "torque_constant"),
            per_joint(actuator.gear_ratio, joints, "gear_ratio"),
        )

    def tables(self, joints: JointColumns) -> dict[str, Array]:
        """``current_measured`` of the next piece (T × n) [A]."""
        motor = motor_torque(joints.tau, actuator_torques(self.actuator, joints.qd, joints.qdd))
        return {"current_measured": self.read(motor / self.per_ampere)}
