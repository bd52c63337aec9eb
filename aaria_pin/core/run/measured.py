"""The run's built-in joint channels: encoders, torque sensors, actuators, motor currents.

:func:`run_sensors` turns a run's settings into the per-run channel objects the engine measures
with (:class:`~aaria_pin.core.run.sensor.Channel`), in this order: the actuators
(:class:`ActuatorStream`), the encoders (:class:`~aaria_pin.core.encoder.EncoderStream`), the
torque sensors (:class:`~aaria_pin.core.torque_sensor.TorqueSensorStream`), the motor current
sensors (:class:`~aaria_pin.core.current_sensor.CurrentSensorStream`, which need the
actuators); each draws its
per-run values from its own stream of the run's sensor seed. A run whose models are all None
has no channel and draws nothing. The models are recorded as the attributes ``encoder``,
``torque_sensor``, ``actuator``, ``current_sensor`` (:mod:`aaria_pin.core.joint_sensors`);
:func:`joint_table_shapes` is the tables a run of those settings adds.

The actuators' torques are those a prescribed motion needs; a motor torque beyond its limit is
not clipped (that would change the motion): the run records per joint the limit, the peak
``|tau_motor|`` and whether it went beyond (the attribute ``actuator_limits``) and warns once
(:class:`TorqueLimitWarning`).
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from aaria_pin.core.actuator import (
    actuator_torques,
    model_effort_limits,
    motor_torque,
    torque_limits,
)
from aaria_pin.core.current_sensor import CurrentSensorStream
from aaria_pin.core.encoder import EncoderStream
from aaria_pin.core.joint_sensors import (
    JOINT_MODELS,
    ActuatorModel,
    JointColumns,
    JointHardware,
    prismatic_joints,
    select_joints,
)
from aaria_pin.core.run.robot import RunRobot
from aaria_pin.core.run.sensor import Channel
from aaria_pin.core.se3 import Array
from aaria_pin.core.torque_sensor import TorqueSensorStream
from aaria_pin.errors import ParameterError

__all__ = [
    "HARDWARE_ATTRIBUTES",
    "JOINT_TABLES",
    "ActuatorStream",
    "OnJoints",
    "TorqueLimitWarning",
    "check_joint_values",
    "joint_table_shapes",
    "record_joint_values",
    "run_sensors",
    "sensor_streams",
]


JOINT_TABLES = {
    "actuator": ((), ("tau_motor", "tau_armature", "tau_friction")),
    "encoder": (("encoder_offset",), ("q_measured",)),
    "torque_sensor": (("torque_sensor_bias", "torque_sensor_scale"), ("tau_measured",)),
    "current_sensor": (("current_sensor_bias", "current_sensor_scale"), ("current_measured",)),
    "controller": (
        ("controller_kp", "controller_kd"),
        ("q_reference", "qd_reference", "tau_command"),
    ),
}
"""Each model's per-run tables and time-axis tables (the record's ``JOINT_RUN_TABLES`` and
``JOINT_SERIES``), in the order of the channels (:func:`run_sensors`; the controller's are a
closed-loop drive's, :mod:`~aaria_pin.core.run.closed_loop`, recorded after the channels')."""


HARDWARE_ATTRIBUTES = ("noise_parameters", *JOINT_MODELS, "actuator_limits")
"""The attributes a run records of its hardware (the IMU model, the joint models, the
actuators' limits and peaks): what a robot kind's own record (the wrist's, the pick-and-place
arm's) keeps from the engine's."""


SATURATED = 1e-9
"""How far past its limit a motor torque may seem (relative) and still be at it: a driven run
saturates its motors at the limit, and the torque re-computed from its motion (RNEA plus the
actuator's parts) lands within rounding of it."""


class TorqueLimitWarning(UserWarning):
    """A prescribed motion needs more motor torque than a joint's limit (it is not clipped)."""


class ActuatorStream:
    """One run's actuators: the motor torque's parts per piece, the peaks and limits so far.

    Args:
        model: the actuators
        limits: each joint's torque limit, n (inf: none) [N·m or N]
        joint_names: the record's joint columns (for the warning)
    """

    name = "actuator"

    def __init__(self, model: ActuatorModel, limits: Array, joint_names: tuple[str, ...]) -> None:
        self.model = model
        self.limits = limits
        self.joint_names = joint_names
        self.peaks = np.zeros(limits.size)
        self._warned = False

    def tables(self, joints: JointColumns) -> dict[str, Array]:
        """``tau_motor``, ``tau_armature``, ``tau_friction`` of the next piece (T × n each).

        Warns (:class:`TorqueLimitWarning`, once per run) at the first sample whose
        ``|tau_motor|`` is beyond a joint's limit.
        """
        parts = actuator_torques(self.model, joints.qd, joints.qdd)
        motor = motor_torque(joints.tau, parts)
        size = np.abs(motor)
        if size.size:
            np.maximum(self.peaks, size.max(axis=0), out=self.peaks)
        over = size > self.limits * (1 + SATURATED)
        if not self._warned and over.any():
            self._warned = True
            sample, joint = np.argwhere(over)[0]
            warnings.warn(
                f"tau_motor of joint {self.joint_names[joint]} is {motor[sample, joint]:.6g} at "
                f"t = {joints.time[sample]:.6g} s; allowed: |tau_motor| <= its torque limit "
                f"{self.limits[joint]:.6g} (the motion is kept, not clipped)",
                TorqueLimitWarning,
                stacklevel=2,
            )
        return {"tau_motor": motor, "tau_armature": parts.armature, "tau_friction": parts.friction}

    def run_tables(self) -> dict[str, Array]:
        """None: the actuators draw nothing."""
        return {}

    def attributes(self) -> dict[str, Any]:
        """``actuator_limits``: per joint the limit (0: none), the peak and whether beyond it."""
        limit = np.where(np.isfinite(self.limits), self.limits, 0.0)
        return {
            "actuator_limits": {
                "torque_limit": [float(v) for v in limit],
                "tau_motor_peak": [float(v) for v in self.peaks],
                "exceeded": [bool(v) for v in self.peaks > self.limits * (1 + SATURATED)],
            }
        }


class OnJoints:
    """A channel whose record columns without a model joint read 0 (an Aaria arm's empty modules).

    An empty module has no joint, so no encoder, sensor or motor: its columns are zero, as its
    ``q`` and ``tau`` are. The channel still draws for every column, so its draws do not depend
    on which modules are empty.

    Args:
        inner: the channel
        present: which record columns are a model joint, a bool per column
    """

    def __init__(self, inner: Channel, present: Array) -> None:
        self.inner = inner
        self.present = present

    @property
    def name(self) -> str:
        """The channel's name."""
        return self.inner.name

    def tables(self, joints: JointColumns) -> dict[str, Array]:
        """The channel's tables, zero in the empty columns."""
        return {k: np.where(self.present, v, 0.0) for k, v in self.inner.tables(joints).items()}

    def run_tables(self) -> dict[str, Array]:
        """The channel's per-run tables, zero in the empty columns."""
        return {k: np.where(self.present, v, 0.0) for k, v in self.inner.run_tables().items()}

    def attributes(self) -> dict[str, Any]:
        """The channel's attributes."""
        return self.inner.attributes()


def record_joint_values(robot: RunRobot, values: Array, empty: Any) -> Array:
    """Per-model-joint values (n_model) as the record's joint columns (``empty`` elsewhere)."""
    n = len(robot.joint_names)
    if robot.columns is None:
        return np.asarray(values).copy()
    out = np.full(n, empty, dtype=np.asarray(values).dtype)
    out[robot.columns] = values
    return out


def motor_limits(robot: RunRobot, model: ActuatorModel) -> Array:
    """Each record joint's motor torque limit (the model's effort limit where 0; inf: none)."""
    effort = model_effort_limits(robot.model, robot.columns, len(robot.joint_names))
    return torque_limits(model, effort)


def check_joint_values(settings: JointHardware, joints: int, parameter: str | None = None) -> None:
    """Refuse a joint model's per-joint value that has not one value per joint.

    Args:
        settings: the models (``RunSettings`` or a hardware value)
        joints: n, the record's joints
        parameter: the parameter the error names (None: the model's name, e.g. ``encoder``)

    Raises:
        ParameterError: ``encoder.noise has 3 values; allowed: one number or 6 (one per joint)``.
    """
    for name in JOINT_MODELS:
        model = getattr(settings, name)
        if model is None:
            continue
        try:
            select_joints(model, joints, list(range(joints)))
        except ParameterError as exc:
            raise ParameterError(
                f"{name}.{exc}", parameter=parameter or name, value=exc.value, element=name
            ) from None


def run_sensors(
    robot: RunRobot, settings: JointHardware, seed: int | np.random.SeedSequence
) -> tuple[Channel, ...]:
    """The run's actuator, encoder, torque and current channels (none while every model is off).

    Args:
        robot: the run's robot (its model says which joints slide, and their effort limits)
        settings: the run's settings (``actuator``, ``encoder``, ``torque_sensor``,
            ``current_sensor``)
        seed: the run's noise seed (:func:`~aaria_pin.core.seeds.sensor_sequence`)

    Raises:
        ParameterError: a per-joint value of another length than the record's joints, or a
            current sensor without an actuator (parameter ``current_sensor``).
    """
    n = len(robot.joint_names)
    check_joint_values(settings, n)  # refused before any piece
    if settings.current_sensor is not None and settings.actuator is None:
        raise ParameterError(
            "current_sensor is on but the run has no actuator; allowed: a current sensor with "
            "an actuator (its gear ratio turns the motor's current into the joint's torque)",
            parameter="current_sensor",
        )
    channels: list[Channel] = []
    if settings.actuator is not None:
        channels.append(
            ActuatorStream(
                settings.actuator, motor_limits(robot, settings.actuator), robot.joint_names
            )
        )
    channels.extend(c for c in sensor_streams(robot, settings, seed) if c is not None)
    if settings.current_sensor is not None and settings.actuator is not None:
        channels.append(CurrentSensorStream(settings.current_sensor, settings.actuator, n, seed))
    if robot.columns is None or len(robot.columns) == n:
        return tuple(channels)
    present = record_joint_values(robot, np.ones(len(robot.columns), dtype=bool), False)
    return tuple(OnJoints(channel, present) for channel in channels)


def sensor_streams(
    robot: RunRobot, settings: JointHardware, seed: int | np.random.SeedSequence
) -> tuple[EncoderStream | None, TorqueSensorStream | None]:
    """The run's encoders and torque sensors (record columns; None: off), their draws made.

    The run's channels measure with them, and a closed-loop drive's controller reads with
    streams made the same way (the same offsets, biases and scale errors: the same sensors).
    """
    n = len(robot.joint_names)
    encoder = torque = None
    if settings.encoder is not None:
        prismatic = record_joint_values(robot, prismatic_joints(robot.model), False)
        encoder = EncoderStream(settings.encoder, prismatic, seed)
    if settings.torque_sensor is not None:
        torque = TorqueSensorStream(settings.torque_sensor, n, seed)
    return encoder, torque


def joint_table_shapes(
    settings: JointHardware, samples: int, joints: int
) -> dict[str, tuple[int, ...]]:
    """The tables a run of ``settings`` adds, in record order: per-run tables, then T × n ones.

    The record puts them after its other tables (the robot's, the motion's, the user sensors').
    """
    on = [name for name in JOINT_TABLES if getattr(settings, name) is not None]
    shapes: dict[str, tuple[int, ...]] = {}
    for name in on:
        shapes.update({table: (1, joints) for table in JOINT_TABLES[name][0]})
    for name in on:
        shapes.update({table: (samples, joints) for table in JOINT_TABLES[name][1]})
    return shapes
