"""Joint torque sensors: ``tau_measured = Q((1 + s)·tau + b + n)``.

``s`` (scale error) and ``b`` (zero offset) are drawn once per run and joint, from
``N(0, scale_error²)`` and ``N(0, bias²)``; ``n`` is white noise ``N(0, noise²)`` per sample
and ``Q`` rounds to the sensor's resolution (0: none). The draws come from the run's
``torque_sensor`` stream (:func:`~aaria_pin.core.seeds.sensor_sequence`): the biases, then the
scale errors, then the noise piece by piece in time order, so a run in pieces reads what the
run held whole reads, bit for bit.

What the sensor measures: ``tau``, the rigid-body (RNEA) torque the link side needs. A joint
torque sensor sits between the gearbox's output and the link (Franka Emika's and KUKA LBR's
``tau_J``), so the rotor's inertia and the gearbox's friction are on its motor side: with an
actuator on, ``tau_motor`` is what the motor gives and ``tau_measured`` still reads ``tau``
(with its errors). That split is what makes such sensors worth having for identification.

The record keeps ``tau`` (true), ``tau_measured`` (T × n), ``torque_sensor_bias`` (1 × n) and
``torque_sensor_scale`` (1 × n).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from aaria_pin.core.joint_sensors import (
    CurrentSensorModel,
    JointColumns,
    TorqueSensorModel,
    per_joint,
)
from aaria_pin.core.se3 import Array
from aaria_pin.core.seeds import sensor_sequence

__all__ = ["SensorReadings", "TorqueSensorModel", "TorqueSensorStream", "torque_reading"]


def torque_reading(
    tau: Array, scale: Array, bias: Array, resolution: Array, noise: Array | None = None
) -> Array:
    """What the sensors report: ``Q((1 + s)·tau + b + n)`` [N·m or N].

    Args:
        tau: the true torques, T × n [N·m or N]
        scale: each joint's scale error ``s``, n [1]
        bias: each joint's zero offset ``b``, n [N·m or N]
        resolution: each joint's step ``Q``, n (0: none) [N·m or N]
        noise: the noise ``n``, T × n (None: none) [N·m or N]
    """
    seen = (1.0 + scale) * tau + bias
    if noise is not None:
        seen = seen + noise
    stepped = resolution > 0
    safe = np.where(stepped, resolution, 1.0)
    return np.where(stepped, safe * np.round(seen / safe), seen)


class SensorReadings:
    """One run's readings of a joint sensor of the law :func:`torque_reading`.

    Its bias and scale error are drawn when it is made, its noise piece by piece, all from the
    run's stream named :attr:`name` (:func:`~aaria_pin.core.seeds.sensor_sequence`); it records
    them as the tables ``<name>_bias`` and ``<name>_scale``. The torque sensors and the motor
    current sensors (:mod:`aaria_pin.core.current_sensor`) are such sensors.

    Args:
        model: the sensors (``noise``, ``bias``, ``resolution``, ``scale_error``)
        joints: n, the record's joint columns
        noise_seed: the run's noise seed
    """

    name = "torque_sensor"

    def __init__(
        self,
        model: TorqueSensorModel | CurrentSensorModel,
        joints: int,
        noise_seed: int | np.random.SeedSequence,
    ) -> None:
        self.model = model
        self.sigma = per_joint(model.noise, joints, "noise")
        self.resolution = per_joint(model.resolution, joints, "resolution")
        self._generator = np.random.default_rng(sensor_sequence(noise_seed, self.name))
        draw = self._generator.standard_normal
        self.bias = per_joint(model.bias, joints, "bias") * draw(joints)
        self.scale = per_joint(model.scale_error, joints, "scale_error") * draw(joints)

    def read(self, values: Array) -> Array:
        """What the sensors report of the next piece's true ``values`` (T × n)."""
        noise = None
        if (self.sigma > 0).any():
            noise = self.sigma * self._generator.standard_normal(values.shape)
        return torque_reading(values, self.scale, self.bias, self.resolution, noise)

    def run_tables(self) -> dict[str, Array]:
        """``<name>_bias`` (1 × n) and ``<name>_scale`` (1 × n) [1]: the values drawn."""
        return {
            f"{self.name}_bias": self.bias[None, :].copy(),
            f"{self.name}_scale": self.scale[None, :].copy(),
        }

    def attributes(self) -> dict[str, Any]:
        """None: the model is recorded as the run's attribute :attr:`name`."""
        return {}


class TorqueSensorStream(SensorReadings):
    """One run's torque sensors: bias and scale drawn when made, noise piece by piece.

    It is a joint channel of the engine (``core/run/measured.py``): :meth:`tables`,
    :meth:`run_tables` (``torque_sensor_bias`` [N·m or N], ``torque_sensor_scale``),
    :meth:`attributes`.

    Args:
        model: the sensors
        joints: n, the record's joint columns
        noise_seed: the run's noise seed; the draws come from its ``torque_sensor`` stream
    """

    name = "torque_sensor"

    def __init__(
        self, model: TorqueSensorModel, joints: int, noise_seed: int | np.random.SeedSequence
    ) -> None:
        super().__init__(model, joints, noise_seed)

    def tables(self, joints: JointColumns) -> dict[str, Array]:
        """``tau_measured`` of the next piece (T × n) [N·m or N]."""
        return {"tau_measured": self.read(joints.tau)}
