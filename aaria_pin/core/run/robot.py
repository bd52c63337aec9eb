"""Robot kinds: what a robot supplies to the run engine, and the registry of kinds by record.

A robot kind (the Aaria DH arm, a URDF robot, the wrist, the pick-and-place arm) is a small
adapter. For a run it is a :class:`RunRobot`: its model, its IMU slots, the mapping of its model
joints to the record's columns, its joint table's sine motion, its base motion and the tables
and attributes its record keeps. The engine (:func:`~aaria_pin.core.run.engine.simulate`) does
the rest.

To re-make a run from its record, each kind registers a :class:`RunKind` (its name, the
``kind`` attribute of its records, and how to re-make a record) with :func:`register_kind`.
The core defines no kind of a higher layer: the modules that define kinds register them when
imported (``aaria_pin.apps.remake`` imports them all), so a reader of a record finds the kind's
adapter by :func:`kind_of` without the core importing up.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from aaria_pin.core.joint_limits import JointBounds, model_velocity_limits
from aaria_pin.core.model import RobotModel
from aaria_pin.core.record import ColumnView, ImuMount, RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory
from aaria_pin.errors import InputFileError

__all__ = ["FixedMount", "RunKind", "RunRobot", "joint_bounds", "kind_of", "register_kind"]


class RunRobot(Protocol):
    """A robot as the run engine uses it (one adapter per robot kind).

    Attributes:
        kind: the record's ``kind`` attribute (a :class:`RunKind` name)
        model: the Pinocchio model the run moves
        joint_names: the record's joint columns (may be more than the model's joints: an
            Aaria arm's empty modules are zero columns)
        columns: the record column of each model joint, in model order (None: the same)
        limits: lower and upper joint limits by record column [rad or m] (a given trajectory
            is checked against them; ±inf where it is not checked)
        imu_frames: the model frames of the IMUs that exist
        imu_slots: the record's IMU slot each of ``imu_frames`` fills (None: 0, 1, ...)
        n_slots: the record's IMU slots (None: ``len(imu_frames)``)
        imu_mounts: the record's IMU mounts (parent ``""``: an empty slot)
        urdf: the URDF text the record keeps
        tables: the robot's input tables the record keeps (e.g. its joint and base tables)
        views: the record's column views
        torque_name: how an error message names a torque table given to drive it

    An adapter may also have a ``payload`` attribute
    (:class:`~aaria_pin.core.run.series.Payload`, or None): a load it carries over part of the
    run, whose torques and base wrench the engine then takes from the loaded model there.
    """

    @property
    def kind(self) -> str:
        """The record's ``kind`` attribute."""
        ...

    @property
    def model(self) -> RobotModel:
        """The Pinocchio model."""
        ...

    @property
    def joint_names(self) -> tuple[str, ...]:
        """The record's joint columns."""
        ...

    @property
    def columns(self) -> list[int] | None:
        """The record column of each model joint (None: the same)."""
        ...

    @property
    def limits(self) -> tuple[Array, Array]:
        """Lower and upper limits by record column [rad or m]."""
        ...

    @property
    def imu_frames(self) -> list[str]:
        """The model frames of the IMUs that exist."""
        ...

    @property
    def imu_slots(self) -> list[int] | None:
        """The IMU slot of each of ``imu_frames`` (None: 0, 1, ...)."""
        ...

    @property
    def n_slots(self) -> int | None:
        """The record's IMU slots (None: one per frame)."""
        ...

    @property
    def imu_mounts(self) -> tuple[ImuMount, ...]:
        """The record's IMU mounts."""
        ...

    @property
    def urdf(self) -> str:
        """The URDF text the record keeps."""
        ...

    @property
    def tables(self) -> dict[str, Array]:
        """The robot's input tables the record keeps."""
        ...

    @property
    def views(self) -> dict[str, ColumnView]:
        """The record's column views."""
        ...

    @property
    def torque_name(self) -> str:
        """How an error names a torque table."""
        ...

    def sines(self, times: Array) -> JointTrajectory:
        """The joint table's motion at ``times`` [s], model order."""
        ...

    def base(self, times: Array) -> BaseMotion:
        """The base motion at ``times`` [s] (at rest on a fixed base)."""
        ...

    def record_columns(self, values: Array) -> Array:
        """Per-model-joint columns ``values`` (T × n) as the record's joint columns."""
        ...

    def attributes(self, peaks: Array) -> dict[str, Any]:
        """The record attributes of this kind, given the peak |torque| so far by model joint."""
        ...


class FixedMount:
    """The motion methods of a robot on a fixed mount with no joint table (an adapter's mixin).

    Its base rests, the joint table's motion rests at zero, and its model's joints are the
    record's columns, in order.

    Attributes:
        model: the robot's model
    """

    model: RobotModel

    def sines(self, times: Array) -> JointTrajectory:
        """At rest at zero (no joint table)."""
        zeros = np.zeros((times.size, self.model.n_joints))
        return JointTrajectory(times, zeros, zeros.copy(), zeros.copy())

    def base(self, times: Array) -> BaseMotion:
        """At rest: a fixed mount."""
        return BaseMotion.resting(times.size)

    def record_columns(self, values: Array) -> Array:
        """The columns as they are."""
        return values


@dataclass(frozen=True)
class RunKind:
    """A kind of run that can be re-made from its record.

    Attributes:
        name: the ``kind`` attribute of its records
        remake: ``remake(stored, **overrides)``, the run re-made from a record's inputs
            (keyword arguments of the kind's producer replace stored ones)
        recognises: whether a record with no ``kind`` attribute (an older file) is of this
            kind, from its tables and attributes
    """

    name: str
    remake: Callable[..., RunRecord]
    recognises: Callable[[RunRecord], bool]


_KINDS: dict[str, RunKind] = {}


def register_kind(kind: RunKind) -> RunKind:
    """Register a kind of run (replacing one of the same name); returns it."""
    _KINDS[kind.name] = kind
    return kind


def kind_of(record: RunRecord) -> RunKind:
    """The registered kind of a record: its ``kind`` attribute, else recognised from its inputs.

    Raises:
        InputFileError: no registered kind (parameter ``kind``).
    """
    name = record.metadata.kind
    if name is None:
        name = next((k.name for k in _KINDS.values() if k.recognises(record)), None)
    if name not in _KINDS:
        raise InputFileError(parameter="kind", value=name, allowed=", ".join(_KINDS), element="run")
    return _KINDS[str(name)]


def joint_bounds(robot: RunRobot) -> JointBounds:
    """The robot's position limits and its model's velocity limits, model order."""
    lower, upper = robot.limits
    columns = list(range(lower.size)) if robot.columns is None else robot.columns
    names = [robot.joint_names[c] for c in columns]
    return JointBounds(names, lower[columns], upper[columns], model_velocity_limits(robot.model))
