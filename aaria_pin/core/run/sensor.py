"""Sensors of a run as objects: each turns a piece's state into its signals and declares them.

A sensor has a name, its record columns, their units and the name of its noise stream (a
:class:`~aaria_pin.core.seeds.RunSeeds` stream; None: noise-free), and turns the state of a
piece of the run (:class:`SensorState`: times, joint and base motion, the computed series) into
its signals, T × columns. Today's sensor is the IMU (:data:`IMU`, with its noise model): its
signals are computed with the series in one compiled pass and are the record's ``imu`` array.
Any other sensor given to the engine (``simulate(..., sensors=[...])``) is recorded as the
table ``sensor_<name>`` (T × columns) and described in the attribute ``sensors`` (columns,
units, noise stream). :func:`register_sensor` makes a sensor known by name (:func:`sensor`),
so adding one is one module plus its registration.

The run's built-in joint channels (encoders, torque sensors, actuators) are :class:`Channel`
objects instead, made per run from its settings
(:func:`~aaria_pin.core.run.measured.run_sensors`): each names its own tables, keeps per-run
tables (the values it drew) and attributes, and reads the piece's joint columns
(:class:`~aaria_pin.core.joint_sensors.JointColumns`). They are not listed in ``sensors``:
their models are recorded as the attributes ``encoder``, ``torque_sensor``, ``actuator``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from aaria_pin.core.joint_sensors import JointColumns
from aaria_pin.core.record import IMU_SIGNALS, TIMED_HARDWARE
from aaria_pin.core.run.robot import RunRobot
from aaria_pin.core.run.series import RunSeries
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory
from aaria_pin.errors import ParameterError

__all__ = [
    "IMU",
    "SENSOR_TABLE_PREFIX",
    "Channel",
    "ImuSensor",
    "Sensor",
    "SensorState",
    "is_sensor_table",
    "recorded_sensors",
    "register_sensor",
    "sensor",
    "sensor_attributes",
    "sensor_table",
]


@dataclass(frozen=True)
class SensorState:
    """What a sensor sees of a piece of a run.

    Attributes:
        times: the piece's sample times, T [s]
        trajectory: the joint motion (model order)
        base: the base motion
        series: the computed series (IMUs, tool pose, torques, base wrench, base pose)
    """

    times: Array
    trajectory: JointTrajectory
    base: BaseMotion
    series: RunSeries


class Sensor(Protocol):
    """A sensor of a run (see the module docstring)."""

    @property
    def name(self) -> str:
        """Its name (the record's table ``sensor_<name>``)."""
        ...

    @property
    def columns(self) -> tuple[str, ...]:
        """The names of its signals, one per column."""
        ...

    @property
    def units(self) -> str:
        """The units of its signals."""
        ...

    @property
    def noise_stream(self) -> str | None:
        """The :class:`~aaria_pin.core.seeds.RunSeeds` stream of its noise (None: none)."""
        ...

    def signals(self, robot: RunRobot, state: SensorState) -> Array:
        """Its signals over the piece, T × ``len(columns)``."""
        ...


class Channel(Protocol):
    """A built-in channel of one run (see the module docstring); it may keep state per run."""

    @property
    def name(self) -> str:
        """Its name (``encoder``, ``torque_sensor``, ``actuator``)."""
        ...

    def tables(self, joints: JointColumns) -> dict[str, Array]:
        """Its time-axis tables of the next piece (T × n each), pieces given in time order."""
        ...

    def run_tables(self) -> dict[str, Array]:
        """Its per-run tables (no time axis): the values drawn for the run."""
        ...

    def attributes(self) -> dict[str, Any]:
        """Its attributes, covering the pieces measured so far."""
        ...


def measure_channels(channels: tuple[Channel, ...], joints: JointColumns) -> dict[str, Array]:
    """The channels' time-axis tables of a piece, in channel order.

    Raises:
        ParameterError: a table that is not T × n (parameter ``sensors``).
    """
    tables: dict[str, Array] = {}
    shape = joints.q.shape
    for channel in channels:
        for name, values in channel.tables(joints).items():
            if values.shape != shape:
                raise ParameterError(
                    f"channel {channel.name!r} gives {name} of shape {values.shape}; allowed: "
                    f"{shape}",
                    parameter="sensors",
                    value=values.shape,
                    allowed=str(shape),
                )
            tables[name] = values
    return tables


@dataclass(frozen=True)
class ImuSensor:
    """The IMUs (ADIS16485-like noise): ``[wx wy wz fx fy fz]`` per IMU slot.

    The engine computes them with the series (one compiled pass; the noise from the run's
    ``noise`` stream) and records them as the ``imu`` array, T × S × 6.
    """

    name: str = "imu"
    columns: tuple[str, ...] = IMU_SIGNALS
    units: str = "rad/s (wx wy wz), m/s^2 (fx fy fz)"
    noise_stream: str | None = "noise"

    def signals(self, robot: RunRobot, state: SensorState) -> Array:
        """The series' IMU signals, T × (S·6), slot by slot."""
        imu = state.series.imu
        return imu.reshape(imu.shape[0], -1)


IMU = ImuSensor()
"""The IMU sensor every run records."""

_SENSORS: dict[str, Sensor] = {IMU.name: IMU}


def register_sensor(new: Sensor) -> Sensor:
    """Make a sensor known by its name (replacing one of that name); returns it."""
    _SENSORS[new.name] = new
    return new


def sensor(name: str) -> Sensor:
    """The registered sensor ``name``.

    Raises:
        ParameterError: no sensor of that name (parameter ``sensor``).
    """
    if name not in _SENSORS:
        raise ParameterError(parameter="sensor", value=name, allowed=", ".join(_SENSORS))
    return _SENSORS[name]


SENSOR_TABLE_PREFIX = "sensor_"
"""The start of every sensor table's name (``sensor_<name>``)."""


def sensor_table(name: str) -> str:
    """The record table of sensor ``name``'s signals."""
    return f"{SENSOR_TABLE_PREFIX}{name}"


def is_sensor_table(name: str) -> bool:
    """Whether a record table holds a sensor's signals (T × columns: a time axis).

    A user sensor's ``sensor_<name>``, or a hardware table with a time axis
    (:data:`~aaria_pin.core.record.TIMED_HARDWARE`: ``q_measured``, ``tau_motor``, ...,
    ``imu_error_jitter``).
    """
    return name.startswith(SENSOR_TABLE_PREFIX) or name in TIMED_HARDWARE


def sensor_attributes(sensors: tuple[Sensor, ...]) -> dict[str, Any]:
    """The attribute ``sensors`` describing the extra sensors (none: no attribute)."""
    if not sensors:
        return {}
    return {
        "sensors": {
            s.name: {
                "table": sensor_table(s.name),
                "columns": list(s.columns),
                "units": s.units,
                "noise_stream": s.noise_stream or "",
            }
            for s in sensors
        }
    }


def recorded_sensors(attributes: Mapping[str, Any]) -> tuple[Sensor, ...]:
    """The registered sensors a record's attribute ``sensors`` names (to re-make its tables).

    The inverse of :func:`sensor_attributes`, in the recorded order.

    Raises:
        ParameterError: a recorded sensor that is not registered (parameter ``sensor``).
    """
    return tuple(sensor(str(name)) for name in attributes.get("sensors") or {})


def measure(robot: RunRobot, state: SensorState, sensors: tuple[Sensor, ...]) -> dict[str, Array]:
    """The extra sensors' tables of a piece, each checked to be T × its columns.

    Raises:
        ParameterError: a sensor whose signals have another shape (parameter ``sensors``).
    """
    tables: dict[str, Array] = {}
    samples = state.times.size
    for s in sensors:
        values = np.asarray(s.signals(robot, state), dtype=float)
        if values.shape != (samples, len(s.columns)):
            raise ParameterError(
                f"sensor {s.name!r} gives signals of shape {values.shape}; allowed: "
                f"({samples}, {len(s.columns)})",
                parameter="sensors",
                value=values.shape,
                allowed=f"({samples}, {len(s.columns)})",
            )
        tables[sensor_table(s.name)] = values
    return tables
