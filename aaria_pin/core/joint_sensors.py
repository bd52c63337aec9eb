"""The joint-side hardware models of a run: encoders, torque and current sensors, motors, control.

These dataclasses are the contract the engine, the configuration, the files and the MJCF export
share; their behaviour is built in their own modules (``core/encoder.py``,
``core/torque_sensor.py``, ``core/actuator.py``, ``core/current_sensor.py``), which re-export
them.

Every value is SI, per joint: a number applies to every joint, a sequence gives one value per
joint in the record's joint order. Revolute joints read rad, N·m, kg·m²; prismatic joints m, N,
kg. 0 turns a term off. Each model checks its values when it is made (:func:`check_fields`):
finite numbers, none negative, ``gear_ratio``, ``coulomb_velocity`` and ``stribeck_velocity``
above 0 and ``scale_error`` below 1; a bad one is one line naming its field.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, fields
from typing import TYPE_CHECKING, Any, Protocol, TypeVar

import numpy as np
from numpy.typing import NDArray

from aaria_pin.errors import InputFileError, ParameterError

if TYPE_CHECKING:
    from aaria_pin.core.model import RobotModel

__all__ = [
    "CLOSED_LOOP_DRIVES",
    "JOINT_MODELS",
    "ActuatorModel",
    "ControllerModel",
    "CurrentSensorModel",
    "EncoderModel",
    "JointColumns",
    "JointHardware",
    "JointModel",
    "JointValue",
    "TorqueSensorModel",
    "check_fields",
    "model_attributes",
    "model_from_attributes",
    "per_joint",
    "prismatic_joints",
    "select_joints",
]

JointValue = float | Sequence[float] | NDArray[np.float64]
"""One value for every joint, or one per joint (record order: a sequence or a 1-D array)."""


@dataclass(frozen=True)
class EncoderModel:
    """A joint encoder: ``q_measured = o + Δ·round((q + n)/Δ)``.

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

    def __post_init__(self) -> None:
        check_fields(self)


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

    def __post_init__(self) -> None:
        check_fields(self, below={"scale_error": 1.0})


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

    def __post_init__(self) -> None:
        check_fields(self, positive=("gear_ratio", "coulomb_velocity", "stribeck_velocity"))


CLOSED_LOOP_DRIVES = ("pd", "computed-torque")
"""The closed-loop drives (a run's ``drive``): the laws of :mod:`aaria_pin.core.control`."""


@dataclass(frozen=True)
class ControllerModel:
    """A closed-loop drive's joint controller (``pd`` or ``computed-torque``).

    Attributes:
        frequency: the closed loop's natural frequency ``f``, ``ω = 2π·f`` [Hz]: ``pd`` gains
            ``Kp = m·ω²``, ``Kd = 2ζ·m·ω`` (``m`` the joint's smallest effective inertia along
            the reference, armature included); ``computed-torque`` ``Kp = ω²``, ``Kd = 2ζ·ω``
        damping: the closed loop's damping ratio ``ζ`` [1]
        kp: the ``pd`` stiffness [N·m/rad or N/m] (0: from ``frequency``)
        kd: the ``pd`` damping [N·m·s/rad or N·s/m] (0: from ``frequency`` and ``damping``)
        rate: the control rate, one for every joint [Hz]: the controller reads its sensors and
            holds its torque for one integration sub-step; a whole multiple of the sample rate
        velocity_filter: cut-off of the first-order filter of the velocity differentiated from
            the encoders [Hz] (0: the raw difference; with a coarse encoder it chatters: 2^17
            counts per turn unfiltered gave computed-torque commands of 362 N·m on ur5)
        torque_feedback: gain ``k`` of the joint-torque loop on the torque sensors' reading
            (0: none; 4 tracked well on ur5, 9 chattered) [1]
        torque_filter: cut-off of the joint-torque loop's first-order filter [Hz]
    """

    frequency: JointValue = 50.0
    damping: JointValue = 1.0
    kp: JointValue = 0.0
    kd: JointValue = 0.0
    rate: JointValue = 2000.0
    velocity_filter: JointValue = 0.0
    torque_feedback: JointValue = 0.0
    torque_filter: JointValue = 50.0

    def __post_init__(self) -> None:
        check_fields(self, positive=("frequency", "damping", "rate", "torque_filter"))
        rates = np.unique(np.asarray(self.rate, dtype=float))
        if rates.size != 1:
            raise ParameterError(
                parameter="rate", value=self.rate, allowed="one control rate for every joint"
            )
        object.__setattr__(self, "rate", float(rates[0]))


@dataclass(frozen=True)
class CurrentSensorModel:
    """A motor current sensor: ``current_measured = Q((1 + s)·tau_motor/(k_t·N) + b + n)``.

    What an arm without joint torque sensors logs (a UR5's ``actual_current``): the current of
    each joint's motor, which gives the motor's torque ``tau_motor`` (friction and armature in
    it) through the torque constant ``k_t`` and the actuator's gear ratio ``N``; a run with one
    needs an ``[actuator]``. The defaults are two data sheets' numbers
    (:mod:`aaria_pin.core.current_sensor` cites them): ``k_t`` = 36 mN·m/A, a maxon EC 45 flat
    50 W motor's 24 V winding, read by an Allegro ACS712ELCTR-05B Hall sensor (185 mV/A, 21 mV
    peak to peak at 2 kHz: 18.9 mA, 1σ) through a 12-bit converter over its 5 V output
    (6.6 mA steps). Behind a gearbox of ratio 100 that is 3.6 N·m of joint torque per ampere
    and 0.068 N·m of noise. A real arm's ``k_t·N`` is identified or taken from its maker
    (Clochiatti et al. 2024, Robotica, identify a UR5e's electrical parameters from its
    controller's currents).

    Attributes:
        torque_constant: the motor's torque constant ``k_t``, motor side [N·m/A or N/A]
        noise: white noise of the current reading, 1σ [A]
        bias: 1σ of the per-joint zero offset ``b`` drawn once per run [A]
        resolution: quantisation step ``Q`` of the reading [A] (0: none)
        scale_error: 1σ of the per-joint error ``s`` of the torque constant, drawn once per
            run [1]
    """

    torque_constant: JointValue = 0.036
    noise: JointValue = 0.0189
    bias: JointValue = 0.0
    resolution: JointValue = 0.0066
    scale_error: JointValue = 0.0

    def __post_init__(self) -> None:
        check_fields(self, positive=("torque_constant",), below={"scale_error": 1.0})


JointModel = EncoderModel | TorqueSensorModel | ActuatorModel | ControllerModel | CurrentSensorModel
"""Any of the joint hardware models."""

JOINT_MODELS: dict[str, type[JointModel]] = {
    "encoder": EncoderModel,
    "torque_sensor": TorqueSensorModel,
    "actuator": ActuatorModel,
    "controller": ControllerModel,
    "current_sensor": CurrentSensorModel,
}
"""The joint models by their name: the ``RunSettings`` field, the run attribute and the
hardware file's table (the order a data set's hardware ranges are drawn in: a new model goes
last, so the draws of the others stay)."""

Model = TypeVar(
    "Model", EncoderModel, TorqueSensorModel, ActuatorModel, ControllerModel, CurrentSensorModel
)


@dataclass(frozen=True)
class JointColumns:
    """A piece of a run's joint motion and torques as the record holds them (record columns).

    What the joint channels (encoders, torque sensors, actuators) measure, T × n each.

    Attributes:
        time: the piece's sample times, T [s]
        q: joint values [rad or m]
        qd: joint velocities [rad/s or m/s]
        qdd: joint accelerations [rad/s² or m/s²]
        tau: the rigid-body (RNEA) joint torques [N·m or N]
    """

    time: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    tau: np.ndarray


def check_fields(
    model: JointModel,
    positive: tuple[str, ...] = (),
    below: Mapping[str, float] | None = None,
) -> None:
    """Refuse a model field that is not a finite number >= 0 (or a sequence of them).

    Each field may be one number or a non-empty flat sequence (one per joint); the sequence is
    kept as a tuple of floats, so the model stays hashable and records the same.

    Args:
        model: the model, checked field by field in declaration order
        positive: the fields that must be > 0 (not only >= 0)
        below: an upper bound (exclusive) of some fields

    Raises:
        ParameterError: a value that is not such a number (parameter: the field's name).
    """
    limits = below or {}
    for f in fields(model):
        name, value = f.name, getattr(model, f.name)
        floor = "> 0" if name in positive else ">= 0"
        allowed = f"finite numbers {floor}" + (f" and < {limits[name]:g}" if name in limits else "")
        allowed += " (one, or one per joint)"
        try:
            values = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise ParameterError(parameter=name, value=value, allowed=allowed) from None
        good = values.ndim <= 1 and values.size > 0 and bool(np.isfinite(values).all())
        good = good and bool((values > 0).all() if name in positive else (values >= 0).all())
        good = good and (name not in limits or bool((values < limits[name]).all()))
        if not good:
            raise ParameterError(parameter=name, value=value, allowed=allowed)
        if values.ndim == 1:
            object.__setattr__(model, name, tuple(float(v) for v in values))


def prismatic_joints(robot: RobotModel) -> np.ndarray:
    """Which of the model's joints (model order, its base apart) slide: a bool per joint.

    Read from the Pinocchio model's joint types (``JointModelPX``/``PY``/``PZ``,
    ``JointModelPrismaticUnaligned``); every other joint of one degree of freedom turns.
    """
    model = robot.model
    out = np.zeros(robot.n_joints, dtype=bool)
    for joint in model.joints[1:]:
        index = joint.idx_v - robot.base_nv
        if 0 <= index < robot.n_joints:
            kind = joint.shortname()
            out[index] = kind.startswith("JointModelPrismatic") or kind[:-1] == "JointModelP"
    return out


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


def select_joints(model: Model, joints: int, columns: Sequence[int] | None) -> Model:
    """The model of some of ``joints`` joints: per-joint values taken at ``columns``.

    Turns a model of the record's joint columns into one of a robot model's joints (an Aaria
    arm's empty modules are record columns without a joint).

    Args:
        model: the model, one value or ``joints`` values per field
        joints: the joints ``model`` describes
        columns: the joints kept, in their new order (None: all, as they are)
    """
    if columns is None:
        return model
    values = {
        f.name: tuple(float(v) for v in per_joint(getattr(model, f.name), joints, f.name)[columns])
        for f in fields(model)
    }
    return type(model)(**values)


def model_attributes(model: JointModel) -> dict[str, Any]:
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


class JointHardware(Protocol):
    """The joint models of a run's settings (:class:`~aaria_pin.core.run.settings.RunSettings`).

    A protocol: ``RunSettings``, the hardware of a data set's run, anything with the models.
    """

    @property
    def encoder(self) -> EncoderModel | None:
        """The encoders (None: none)."""
        ...

    @property
    def torque_sensor(self) -> TorqueSensorModel | None:
        """The torque sensors (None: none)."""
        ...

    @property
    def actuator(self) -> ActuatorModel | None:
        """The actuators (None: none)."""
        ...

    @property
    def controller(self) -> ControllerModel | None:
        """The controller of a closed-loop drive (None: none)."""
        ...

    @property
    def current_sensor(self) -> CurrentSensorModel | None:
        """The motor current sensors (None: none)."""
        ...


def joint_model_attributes(settings: JointHardware) -> dict[str, Any]:
    """The attributes ``encoder``, ``torque_sensor``, ... (:data:`JOINT_MODELS`) of those on."""
    return {
        name: model_attributes(model)
        for name in JOINT_MODELS
        if (model := getattr(settings, name)) is not None
    }


def joint_models_from_attributes(attributes: Mapping[str, Any]) -> dict[str, Any]:
    """The joint models a run's attributes record: ``{"encoder": ..., ...}`` (None: absent).

    The inverse of :func:`joint_model_attributes`, as ``RunSettings`` fields.

    Raises:
        InputFileError: a recorded model that is not a table of its fields, or whose values
            are not allowed (parameter ``file``).
    """
    models: dict[str, Any] = {}
    for name, cls in JOINT_MODELS.items():
        stored = attributes.get(name)
        if stored is None:
            models[name] = None
            continue
        if not isinstance(stored, Mapping):
            raise InputFileError(
                f"the run's attribute {name!r} is {stored!r}; allowed: a table of the "
                f"{cls.__name__} fields",
                parameter="file",
            )
        try:
            models[name] = model_from_attributes(cls, stored)  # type: ignore[type-var]
        except (ParameterError, TypeError, ValueError) as exc:
            raise InputFileError(f"the run's attribute {name!r}: {exc}", parameter="file") from None
    return models
