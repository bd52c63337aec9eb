"""A run's settings as one typed value, and the attributes every run records about them.

:class:`RunSettings` holds what every run of every robot takes (duration, rate, pieces, IMU
noise, threads, gravity, the precision of the series), checked once when it is made;
:func:`sampling_attributes` writes it (with the seed) into a record's attributes and
:meth:`RunSettings.from_attributes` reads it back.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, fields, replace
from typing import Any, Literal

import numpy as np

from aaria_pin.core.arguments import checked
from aaria_pin.core.imu_attributes import noise_model_from_attributes
from aaria_pin.core.imu_noise import ADIS16485, ImuNoiseModel, noise_attributes
from aaria_pin.core.joint_sensors import (
    CLOSED_LOOP_DRIVES,
    ActuatorModel,
    ControllerModel,
    CurrentSensorModel,
    EncoderModel,
    TorqueSensorModel,
    joint_model_attributes,
    joint_models_from_attributes,
)
from aaria_pin.core.model import GRAVITY
from aaria_pin.core.run.chunks import CHUNK_SAMPLES
from aaria_pin.core.run_metadata import stored_sampling
from aaria_pin.core.seeds import seed_attributes
from aaria_pin.core.trajectory import (
    DEFAULT_DURATION,
    DEFAULT_RATE,
    MAX_SAMPLES,
    MAX_STREAMED_SAMPLES,
    sample_count,
)
from aaria_pin.errors import InputFileError, ParameterError

__all__ = [
    "DEFAULT_DURATION",
    "DEFAULT_RATE",
    "DTYPES",
    "GRAVITY_VECTOR",
    "UNITS",
    "RunSettings",
    "sampling_attributes",
    "stored_hardware",
]

GRAVITY_VECTOR: tuple[float, float, float] = (
    float(GRAVITY[0]),
    float(GRAVITY[1]),
    float(GRAVITY[2]),
)
"""The default gravity [m/s²], world frame (:data:`~aaria_pin.core.model.GRAVITY` as a tuple)."""

DTYPES = ("float64", "float32")
"""The precisions a run's series may be rounded to (a data set stores ``float32`` by default)."""

UNITS = {
    "time": "s",
    "q": "rad (revolute) or m (prismatic)",
    "angular_velocity": "rad/s",
    "specific_force": "m/s^2",
    "tau": "N*m (revolute) or N (prismatic)",
    "base_wrench": "N (force), N*m (moment about the base origin), world-aligned axes",
    "length": "m",
}
"""The ``units`` attribute of a run (the units of each quantity)."""


def sampling_attributes(
    rate: float,
    duration: float,
    seed: int | np.random.SeedSequence,
    noise: bool,
    noise_model: ImuNoiseModel,
    gravity: tuple[float, float, float] = GRAVITY_VECTOR,
) -> dict[str, Any]:
    """The attributes every run records: rate, duration, seed, noise, gravity, units.

    Args:
        rate: sample rate [Hz]
        duration: run length [s]
        seed: seed of the IMU noise (or a data set run's ``SeedSequence``)
        noise: whether the IMU signals carry noise
        noise_model: the IMU noise parameters
        gravity: the gravity of the run, world frame [m/s²]
    """
    return {
        "rate": float(rate),
        "duration": float(duration),
        **seed_attributes(seed),
        "noise": bool(noise),
        "noise_parameters": noise_attributes(noise_model),
        "gravity": [float(g) for g in gravity],
        "units": UNITS,
    }


def stored_hardware(attributes: Mapping[str, Any]) -> dict[str, Any]:
    """The hardware a run's attributes record, as :class:`RunSettings` fields.

    ``noise_model`` from ``noise_parameters`` (none: the ADIS16485), and ``encoder``,
    ``torque_sensor``, ``actuator`` (absent: None, that hardware off), so a run re-made from its
    record (``--from``) uses the models it was made with; a file written before has none.

    Raises:
        InputFileError: a stored model that is not a table (``parameter`` its name).
    """
    stored = attributes.get("noise_parameters")
    if stored is not None and not isinstance(stored, Mapping):
        raise InputFileError(
            f"the run's attribute 'noise_parameters' is {stored!r}; allowed: a table of its values",
            parameter="noise_parameters",
        )
    hardware: dict[str, Any] = {"noise_model": noise_model_from_attributes(stored)}
    hardware.update(joint_models_from_attributes(attributes))
    return hardware


@checked
@dataclass(frozen=True)
class RunSettings:
    """What every run takes beside its robot and its motion, checked once here.

    Attributes:
        duration: run length [s], 0 < duration <= 86,400
        rate: sample rate [Hz], 0 < rate <= 100,000
        chunk: samples per piece of a run computed in time pieces (the engine's
            ``simulate_pieces``; :data:`~aaria_pin.core.run.chunks.CHUNK_SAMPLES` is the
            measured choice); None: one piece
        noise: add IMU noise (False gives the exact signals)
        noise_model: the IMU noise parameters
        threads: worker threads of the batched RNEA
        gravity: the gravity vector in the world frame [m/s²] (Earth's standard
            ``(0, 0, -9.81)``; the Moon's ``(0, 0, -1.62)``; a tilted world for a wall-mounted
            base); it enters the torques, the base wrench, the torque drive's dynamics and the
            accelerometers' specific force, and is recorded as the ``gravity`` attribute
        dtype: the precision of the record's series: ``"float64"``, or ``"float32"`` to have in
            memory exactly what a ``float32`` data set stores and reads back (the series are
            rounded to float32 and held as float64, as :func:`~aaria_pin.files.source.open_record`
            returns them); the computation is float64 either way
        encoder: the joint encoders (None: none; the record then has no ``q_measured``)
        torque_sensor: the joint torque sensors (None: none; no ``tau_measured``)
        actuator: the joints' motors and gearboxes (None: none; no ``tau_motor``)
        controller: the joint controller of a closed-loop drive (``pd``, ``computed-torque``;
            None: none, and a run of another drive has none)
        current_sensor: the motor current sensors (None: none; no ``current_measured``;
            needs an ``actuator``)

    Raises:
        ParameterError: a duration or rate outside its range or giving fewer than two samples
            (as :func:`~aaria_pin.core.trajectory.sample_count`), a chunk < 1, threads < 1, a
            gravity that is not three finite numbers, or a dtype not in :data:`DTYPES`.
    """

    duration: float = DEFAULT_DURATION
    rate: float = DEFAULT_RATE
    chunk: int | None = None
    noise: bool = True
    noise_model: ImuNoiseModel = field(default=ADIS16485)
    threads: int = 1
    gravity: tuple[float, float, float] = GRAVITY_VECTOR
    dtype: Literal["float64", "float32"] = "float64"
    encoder: EncoderModel | None = None
    torque_sensor: TorqueSensorModel | None = None
    actuator: ActuatorModel | None = None
    controller: ControllerModel | None = None
    current_sensor: CurrentSensorModel | None = None

    def __post_init__(self) -> None:
        sample_count(self.duration, self.rate, None)  # ranges, and two samples at least
        if self.chunk is not None and (isinstance(self.chunk, bool) or self.chunk < 1):
            raise ParameterError(
                f"chunk is {self.chunk!r} samples; allowed: >= 1",
                parameter="chunk",
                value=self.chunk,
                allowed=">= 1",
            )
        if isinstance(self.threads, bool) or self.threads < 1:
            raise ParameterError(parameter="threads", value=self.threads, allowed=">= 1")
        gravity = _gravity_vector(self.gravity)
        if gravity is None:
            raise ParameterError(
                parameter="gravity", value=self.gravity, allowed="three finite numbers [m/s²]"
            )
        object.__setattr__(self, "gravity", gravity)
        if self.dtype not in DTYPES:
            raise ParameterError(parameter="dtype", value=self.dtype, allowed=", ".join(DTYPES))

    def for_drive(self, drive: str) -> RunSettings:
        """The settings of a run of ``drive`` (its ``drive`` attribute).

        A closed-loop drive (:data:`~aaria_pin.core.joint_sensors.CLOSED_LOOP_DRIVES`) has a
        controller: the default :class:`~aaria_pin.core.joint_sensors.ControllerModel` when
        none is given; another drive has none.

        Raises:
            ParameterError: a controller for a run that is not closed-loop (parameter
                ``controller``).
        """
        if drive in CLOSED_LOOP_DRIVES:
            return (
                self if self.controller is not None else replace(self, controller=ControllerModel())
            )
        if self.controller is not None:
            raise ParameterError(
                f"controller is given for a run of drive {drive!r}; allowed: a controller with "
                f"a closed-loop drive ({', '.join(CLOSED_LOOP_DRIVES)})",
                parameter="controller",
                value=drive,
                allowed=", ".join(CLOSED_LOOP_DRIVES),
            )
        return self

    @property
    def needs_whole_run(self) -> bool:
        """Whether the run must be computed in one piece (IMU terms over the whole run)."""
        return bool(self.noise and getattr(self.noise_model, "needs_whole_run", False))

    def samples(self, whole: bool = False) -> int:
        """T, the run's samples, within the bound of a run in pieces or (``whole``) held whole.

        Raises:
            ParameterError: more samples than that bound (parameter ``duration``).
        """
        streamed = self.chunk is not None and not whole
        return sample_count(
            self.duration, self.rate, MAX_STREAMED_SAMPLES if streamed else MAX_SAMPLES
        )

    @classmethod
    def from_options(cls, options: Mapping[str, Any]) -> RunSettings:
        """The settings among a run request's keyword options (its other options ignored).

        A request's run is made in pieces of :data:`~aaria_pin.core.run.CHUNK_SAMPLES` samples
        unless its ``chunk`` option says otherwise (None: one piece).
        """
        given = {f.name: options[f.name] for f in fields(cls) if f.name in options}
        return cls(**{"chunk": CHUNK_SAMPLES, **given})

    @classmethod
    def from_attributes(cls, attributes: dict[str, Any], **overrides: Any) -> RunSettings:
        """The settings a record's attributes hold, ``overrides`` applied.

        The sampling (:func:`stored_sampling`), the gravity and the hardware
        (:func:`stored_hardware`: the IMU model, the joint models).

        Raises:
            InputFileError: a stored duration or rate that is not a positive number, or a
                stored model that is not a table.
        """
        stored = stored_sampling(attributes)
        values: dict[str, Any] = {
            "duration": stored["duration"],
            "rate": stored["rate"],
            "noise": stored["noise"],
            "gravity": _stored_gravity(attributes),
            **stored_hardware(attributes),
        }
        values.update(overrides)
        return cls(**values)

    def attributes(self, seed: int | np.random.SeedSequence) -> dict[str, Any]:
        """The attributes every run records: :func:`sampling_attributes` and the joint models.

        The joint models as :func:`~aaria_pin.core.joint_sensors.joint_model_attributes`
        (none when they are off, as in the runs made before).
        """
        return {
            **sampling_attributes(
                self.rate, self.duration, seed, self.noise, self.noise_model, self.gravity
            ),
            **joint_model_attributes(self),
        }


def _stored_gravity(attributes: Mapping[str, Any]) -> tuple[float, float, float]:
    """The gravity a record's attributes hold (the default where a file has none).

    Raises:
        InputFileError: a stored gravity that is not three finite numbers.
    """
    stored = attributes.get("gravity", GRAVITY_VECTOR)
    gravity = _gravity_vector(stored)
    if gravity is None:
        raise InputFileError(
            f"the run's attribute 'gravity' is {stored!r}; allowed: three finite numbers [m/s²]",
            parameter="gravity",
        )
    return gravity


def _gravity_vector(value: Any) -> tuple[float, float, float] | None:
    """``value`` as three finite numbers [m/s²], or None (the one rule, given or stored)."""
    try:
        gravity = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return None
    if gravity.shape != (3,) or not np.isfinite(gravity).all():
        return None
    return (float(gravity[0]), float(gravity[1]), float(gravity[2]))
