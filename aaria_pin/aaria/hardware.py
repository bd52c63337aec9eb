"""A run's hardware read from TOML: the IMU model, joint encoders, torque sensors and actuators.

A hardware file (``aaria simulate --hardware FILE``, ``aaria template hardware``) and a data
set's configuration (``aaria dataset --config FILE``) share these tables; every key is a field
of its model, in SI units, 0 turning a term off:

- ``[imu]``: ``preset = "adis16485"`` (a name of
  :data:`~aaria_pin.core.imu_presets.IMU_PRESETS`; default the ``--imu-model`` flag's model, else
  the ADIS16485) and any field of :class:`~aaria_pin.core.imu_noise.ImuNoiseModel`; the
  sub-tables ``[imu.gyro]`` and ``[imu.accel]`` take the fields of
  :class:`~aaria_pin.core.imu_noise.SensorNoise`. The table ``[noise]`` of the configurations
  written before (the same keys, no ``preset``) still reads as ``[imu]``.
- ``[encoder]``, ``[torque_sensor]``, ``[actuator]``, ``[current_sensor]``: the fields of
  :class:`~aaria_pin.core.joint_sensors.EncoderModel`,
  :class:`~aaria_pin.core.joint_sensors.TorqueSensorModel`,
  :class:`~aaria_pin.core.joint_sensors.ActuatorModel`,
  :class:`~aaria_pin.core.joint_sensors.CurrentSensorModel`: a number for every joint, or a list of
  one number per joint (record order). A table not given: that hardware is off (no table).

In a data set's configuration any number may be a range ``[low, high]`` (low <= high), drawn
uniformly for each run from the run's ``hardware`` stream, one value per joint for a joint
model's field (:meth:`HardwareConfig.draw`; a list of two numbers is a range there, so per-joint
values of a two-joint robot are written as ranges ``[[v1, v1], [v2, v2]]``). Both ends are
checked like a value, so every drawn value is allowed.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.aaria.hardware_toml import (
    IMU_TABLE,
    SENSORS,
    WHOLE_COUNTS,
    Range,
    TableReader,
    field_of,
)
from aaria_pin.core.imu_noise import ADIS16485, ImuNoiseModel, noise_attributes
from aaria_pin.core.imu_presets import imu_preset
from aaria_pin.core.joint_sensors import (
    JOINT_MODELS,
    ActuatorModel,
    ControllerModel,
    CurrentSensorModel,
    EncoderModel,
    JointModel,
    TorqueSensorModel,
    joint_model_attributes,
)
from aaria_pin.errors import AariaError, ParameterError

__all__ = [
    "HARDWARE_TABLES",
    "HARDWARE_VALUES",
    "JOINT_MODELS",
    "LEGACY_IMU_TABLE",
    "Hardware",
    "HardwareConfig",
    "Range",
    "hardware_leaves",
    "hardware_run_options",
    "imu_model_option",
    "load_hardware",
]

LEGACY_IMU_TABLE = "noise"
"""The IMU table of the configurations written before issue 24 (read as ``[imu]``)."""
HARDWARE_TABLES = (IMU_TABLE, *JOINT_MODELS)
"""The tables of a hardware file, in the order their ranges are drawn (``noise``, the older
name of ``imu``, in its place)."""
HARDWARE_VALUES = "hardware_values"
"""A data set run's table of the values drawn from the config's ranges (float64; the file's
attribute ``hardware_names`` names each by its attribute path, ``encoder/noise/0``)."""

Pick = Callable[[str, float, float, int | None], Any]
"""What becomes of a range ``[low, high]`` at a key: (path, low, high, joints or None)."""


@dataclass(frozen=True)
class Hardware:
    """A run's hardware: its IMU model and its joint models (None: none, no table).

    Attributes:
        imu: the IMU model
        encoder: the joint encoders
        torque_sensor: the joint torque sensors
        actuator: the joints' motors and gearboxes
        controller: the joint controller of a closed-loop drive (``--drive pd``,
            ``computed-torque``)
        current_sensor: the motor current sensors (with an actuator)
    """

    imu: ImuNoiseModel = ADIS16485
    encoder: EncoderModel | None = None
    torque_sensor: TorqueSensorModel | None = None
    actuator: ActuatorModel | None = None
    controller: ControllerModel | None = None
    current_sensor: CurrentSensorModel | None = None

    def options(self) -> dict[str, Any]:
        """The run options (:class:`~aaria_pin.core.run.RunSettings` fields) they set."""
        return {
            "noise_model": self.imu,
            "encoder": self.encoder,
            "torque_sensor": self.torque_sensor,
            "actuator": self.actuator,
            "controller": self.controller,
            "current_sensor": self.current_sensor,
        }

    def attributes(self) -> dict[str, Any]:
        """What a run records of them: ``noise_parameters``, ``encoder``, ... (those on)."""
        return {
            "noise_parameters": noise_attributes(self.imu),
            **joint_model_attributes(self),
        }


def hardware_leaves(attributes: Any, prefix: str = "") -> dict[str, float]:
    """Every number of nested attributes by its path (``encoder/noise/0``, ``a/b``)."""
    items = attributes.items() if isinstance(attributes, Mapping) else enumerate(attributes)
    leaves: dict[str, float] = {}
    for key, value in items:
        path = f"{prefix}{key}"
        if isinstance(value, Mapping | list | tuple):
            leaves.update(hardware_leaves(value, f"{path}/"))
        elif isinstance(value, int | float) and not isinstance(value, bool):
            leaves[path] = float(value)
    return leaves


@dataclass(frozen=True)
class HardwareConfig:
    """The hardware tables of a file, checked: numbers, per-joint lists and (data sets) ranges.

    Attributes:
        tables: the tables as read (:data:`HARDWARE_TABLES`), keys in their model's field order
        imu_model: the IMU model of the ``--imu-model`` flag: the base of ``[imu]``'s values,
            over its ``preset`` (None: the preset, else the ADIS16485)
        where: the file, as messages name it
        parameter: the parameter a message names (``hardware``, ``config``)
    """

    tables: Mapping[str, Any] = field(default_factory=dict)
    imu_model: ImuNoiseModel | None = None
    where: str = "hardware"
    parameter: str = "hardware"

    @classmethod
    def from_mapping(
        cls,
        data: Mapping[str, Any],
        where: str = "hardware",
        parameter: str = "hardware",
        ranges: bool = False,
        imu_model: ImuNoiseModel | None = None,
    ) -> HardwareConfig:
        """The hardware tables of a parsed TOML file (other keys: the caller's; refused here).

        Args:
            data: the file's tables (only :data:`HARDWARE_TABLES` and ``noise``)
            where: the file, for messages
            parameter: the parameter messages name
            ranges: whether a number may be a range ``[low, high]`` (a data set's config)
            imu_model: the ``--imu-model`` flag's model

        Raises:
            ParameterError: an unknown table or key, a value of the wrong type, a range with
                low > high (or given where none is allowed), or a value its model refuses.
        """
        reading = TableReader(where, parameter)
        known = (IMU_TABLE, LEGACY_IMU_TABLE, *JOINT_MODELS)
        unknown = sorted(set(data) - set(known))
        if unknown:
            raise reading.refused(unknown[0], data[unknown[0]], "one of " + ", ".join(known))
        if IMU_TABLE in data and LEGACY_IMU_TABLE in data:
            raise reading.refused(
                LEGACY_IMU_TABLE, "a table", "[imu] or the older [noise], not both"
            )
        tables: dict[str, Any] = {}
        for name in known:
            if name in data:
                table = IMU_TABLE if name == LEGACY_IMU_TABLE else name
                tables[name] = reading.table(name, data[name], table, ranges)
        config = cls(tables, imu_model, where, parameter)
        config.hardware(lambda path, low, high, n: low, 1)  # both ends checked by their models
        config.hardware(lambda path, low, high, n: high, 1)
        return config

    def with_imu_model(self, model: ImuNoiseModel | None) -> HardwareConfig:
        """The same tables over another ``--imu-model`` (None: keep this one's)."""
        return self if model is None else dataclasses.replace(self, imu_model=model)

    @property
    def ranged(self) -> bool:
        """Whether any value is a range (drawn per run)."""
        return bool(_ranges(self.tables))

    def as_dict(self) -> dict[str, Any]:
        """The tables as plain values (a data set's ``hardware`` attribute)."""
        return _plain(self.tables)

    def options(self, base_imu: ImuNoiseModel = ADIS16485) -> dict[str, Any]:
        """The run options of the tables given and of ``--imu-model`` (ranges refused).

        A table not given sets nothing, so a re-made run (``--from``) keeps its stored model.

        Args:
            base_imu: the model ``[imu]``'s values go over when neither ``--imu-model`` nor a
                preset is given (a re-made run's stored model)
        """
        built = self.hardware(_no_range, 0, base_imu).options()
        imu_given = self.imu_model is not None or self.imu_table is not None
        given = {"noise_model"} if imu_given else set()
        given |= set(self.tables) & set(JOINT_MODELS)
        return {key: value for key, value in built.items() if key in given}

    def nominal(self, joints: int) -> Hardware:
        """The hardware with every range at its middle (a data set's file attributes)."""
        return self.hardware(
            lambda path, low, high, n: _counted(path, _sized(0.5 * (low + high), n)), joints
        )

    def ends(self, joints: int) -> tuple[Hardware, Hardware]:
        """The hardware with every range at its low end, and at its high end (per joint)."""
        return (
            self.hardware(lambda path, low, high, n: _sized(low, n), joints),
            self.hardware(lambda path, low, high, n: _sized(high, n), joints),
        )

    def draw(self, rng: np.random.Generator, joints: int) -> Hardware:
        """One run's hardware: each range drawn uniformly, per joint for a joint model's field.

        The draws follow :data:`HARDWARE_TABLES`, then each model's field order, so a run's
        values are a pure function of its generator (a data set's ``hardware`` stream).
        """
        return self.hardware(
            lambda path, low, high, n: _counted(path, rng.uniform(low, high, n)), joints
        )

    def ranged_names(self, joints: int) -> tuple[str, ...]:
        """The attribute paths (:func:`hardware_leaves`) of the values a run draws.

        A path one end of its range does not record (an IMU term at its off value is left out
        of ``noise_parameters``) is one too; a run that does not record it stores NaN there.
        """
        low, high = (hardware_leaves(h.attributes()) for h in self.ends(joints))
        names = {**dict.fromkeys(low), **dict.fromkeys(high)}  # a term off is not recorded
        return tuple(name for name in names if low.get(name) != high.get(name))

    def run_hardware(self, seed: int, run: int, joints: int) -> Hardware:
        """Run ``run``'s hardware in a data set of seed ``seed``.

        Each range is drawn from the run's ``hardware`` stream
        (:class:`~aaria_pin.core.seeds.RunSeeds`); without ranges every run has the same.
        """
        from aaria_pin.core.seeds import RunSeeds

        if not self.ranged:
            return self.nominal(joints)
        return self.draw(RunSeeds(seed, run).generator("hardware"), joints)

    def hardware(self, pick: Pick, joints: int, base_imu: ImuNoiseModel = ADIS16485) -> Hardware:
        """The models of the tables, each range replaced by ``pick(path, low, high, n)``.

        Raises:
            ParameterError: a value its model refuses, naming the key (``FILE: table.key ...``).
        """
        imu = self.imu_model or base_imu
        values: dict[str, Any] = {}
        for name, table in self.tables.items():
            per_joint = joints if name in JOINT_MODELS else None
            values[name] = _resolved(table, pick, per_joint, name)
        if self.imu_table is not None:
            imu = self._imu(values[self.imu_table], imu, self.imu_table)
        models = {name: self._joint(name, values[name]) for name in JOINT_MODELS if name in values}
        return Hardware(imu, **models)  # type: ignore[arg-type]

    @property
    def imu_table(self) -> str | None:
        """The IMU table as the file names it: ``imu``, the older ``noise``, or None."""
        return next((name for name in (IMU_TABLE, LEGACY_IMU_TABLE) if name in self.tables), None)

    def _imu(self, values: Mapping[str, Any], base: ImuNoiseModel, name: str) -> ImuNoiseModel:
        if "preset" in values and self.imu_model is None:
            base = imu_preset(values["preset"])
        changes = {k: v for k, v in values.items() if k not in ("preset", *SENSORS)}
        for sensor in SENSORS:
            if sensor in values:
                with self.naming(f"{name}.{sensor}"):
                    changes[sensor] = dataclasses.replace(getattr(base, sensor), **values[sensor])
        with self.naming(name):
            return dataclasses.replace(base, **changes)

    def _joint(self, name: str, values: Mapping[str, Any]) -> JointModel:
        plain = {
            key: float(v) if np.ndim(v) == 0 else tuple(float(x) for x in v)
            for key, v in values.items()
        }
        with self.naming(name):
            return JOINT_MODELS[name](**plain)

    def naming(self, path: str) -> _Naming:
        """A context that re-raises a model's refusal as ``WHERE: PATH.MESSAGE``."""
        return _Naming(self, path)


class _Naming:
    """Re-raise a model's :class:`AariaError` as one line naming the file and the key."""

    def __init__(self, config: HardwareConfig, path: str) -> None:
        self.config, self.path = config, path

    def __enter__(self) -> None:
        return None

    def __exit__(self, kind: object, exc: BaseException | None, trace: object) -> None:
        if isinstance(exc, AariaError) and not str(exc).startswith(f"{self.config.where}: "):
            message = " ".join(str(exc).split())
            raise ParameterError(
                f"{self.config.where}: {self.path}.{message}",
                parameter=self.config.parameter,
                value=exc.value,
                element=f"{self.path}.{exc.parameter}",
            ) from None


def load_hardware(
    path: str | Path, parameter: str = "hardware", imu_model: ImuNoiseModel | None = None
) -> HardwareConfig:
    """A hardware file (``aaria simulate --hardware FILE``): its tables, no ranges.

    Raises:
        InputFileError: the file is missing, unreadable, not UTF-8 or not TOML.
        ParameterError: see :meth:`HardwareConfig.from_mapping` (``parameter``).
    """
    from aaria_pin.aaria.randomize import read_config_file
    from aaria_pin.files.paths import existing_input

    file = existing_input(Path(path), None, parameter.replace("_", " "))
    return HardwareConfig.from_mapping(
        read_config_file(file), str(file), parameter, ranges=False, imu_model=imu_model
    )


def imu_model_option(value: str | Path, parameter: str = "imu_model") -> ImuNoiseModel:
    """The IMU model of ``--imu-model NAME|FILE.toml``: a preset, or a file's ``[imu]`` table.

    Raises:
        ParameterError: an unknown preset, or a file with other tables or refused values.
        InputFileError: a file that cannot be read as TOML.
    """
    text = str(value)
    if not (text.lower().endswith(".toml") or Path(text).is_file()):
        return imu_preset(text)
    config = load_hardware(text, parameter)
    other = [name for name in config.tables if name != config.imu_table]
    if other or config.imu_table is None:
        shown = other[0] if other else "(no [imu] table)"
        reader = TableReader(config.where, config.parameter)
        raise reader.refused(shown, "a table", "an [imu] table only (an IMU model file)")
    return config.hardware(_no_range, 0).imu


def hardware_run_options(
    imu_model: str | Path | None,
    hardware_file: str | Path | None,
    stored: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """The run options ``--imu-model`` and ``--hardware`` set (nothing when neither is given).

    Args:
        imu_model: a preset name or an IMU model file (:func:`imu_model_option`)
        hardware_file: a hardware file (:func:`load_hardware`): the tables it gives
        stored: the attributes of the run re-made (``--from``): its IMU model is the base of
            the file's ``[imu]`` values when no preset is named; what neither option sets
            stays as stored

    Raises:
        ParameterError, InputFileError: as :func:`imu_model_option`, :func:`load_hardware`.
    """
    from aaria_pin.core.run.settings import stored_hardware

    model = None if imu_model is None else imu_model_option(imu_model)
    if hardware_file is None:
        return {} if model is None else {"noise_model": model}
    config = load_hardware(hardware_file, imu_model=model)
    base = ADIS16485 if stored is None else stored_hardware(stored)["noise_model"]
    return config.options(base)


def _no_range(path: str, low: float, high: float, joints: int | None) -> Any:
    raise ParameterError(
        f"{path} is a range; allowed: a number", parameter=path
    )  # pragma: no cover


def _counted(path: str, value: Any) -> Any:
    """A drawn value as its field takes it: whole counts for an encoder's resolution."""
    return np.rint(value) if field_of(path) in WHOLE_COUNTS else value


def _sized(value: float, joints: int | None) -> Any:
    return value if joints is None else np.full(joints, value)


def _resolved(table: Mapping[str, Any], pick: Pick, joints: int | None, path: str) -> Any:
    out: dict[str, Any] = {}
    for key, value in table.items():
        where = f"{path}.{key}"
        if isinstance(value, Mapping):
            out[key] = _resolved(value, pick, None, where)
        elif isinstance(value, Range):
            out[key] = pick(where, value.low, value.high, joints)
        elif joints is not None and isinstance(value, list):
            out[key] = np.array(
                [pick(f"{where}[{i}]", v.low, v.high, None) if isinstance(v, Range) else v
                 for i, v in enumerate(value)]
            )  # fmt: skip
        else:
            out[key] = value
    return out


def _ranges(table: Any) -> list[Range]:
    if isinstance(table, Range):
        return [table]
    if isinstance(table, Mapping):
        return [r for value in table.values() for r in _ranges(value)]
    if isinstance(table, list):
        return [r for value in table for r in _ranges(value)]
    return []


def _plain(value: Any) -> Any:
    if isinstance(value, Mapping):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple | np.ndarray):
        return [_plain(v) for v in value]
    return value
