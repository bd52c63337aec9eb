"""The checks of a hardware TOML file's tables (:mod:`aaria_pin.aaria.hardware`) as read.

:class:`TableReader` checks each table's keys against its model's fields and each value's
type: a number, a range ``[low, high]`` (:class:`Range`, where ranges are allowed: a data set's
configuration), a list of per-joint values (a joint model), a text field as is. The values
themselves are checked by their models when they are built.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any, NamedTuple

import numpy as np

from aaria_pin.core.imu_noise import ImuNoiseModel, SensorNoise
from aaria_pin.core.imu_presets import IMU_PRESETS
from aaria_pin.core.joint_sensors import JOINT_MODELS
from aaria_pin.errors import ParameterError

__all__ = ["IMU_TABLE", "NOT_DRAWN", "SENSORS", "WHOLE_COUNTS", "Range", "TableReader", "field_of"]

IMU_TABLE = "imu"
SENSORS = ("gyro", "accel")
"""The sub-tables of ``[imu]``: the fields of :class:`~aaria_pin.core.imu_noise.SensorNoise`."""


class Range(NamedTuple):
    """A range ``[low, high]`` of a data set's configuration, drawn per run."""

    low: float
    high: float


class TableReader:
    """Checks the tables of one file, naming it and the parameter at fault in its messages.

    Args:
        where: the file, as messages name it
        parameter: the parameter a message names (``hardware``, ``config``)
    """

    def __init__(self, where: str, parameter: str) -> None:
        self.where, self.parameter = where, parameter

    def refused(self, path: str, value: Any, allowed: str) -> ParameterError:
        """``WHERE: PATH is VALUE; allowed: ALLOWED`` (parameter :attr:`parameter`)."""
        return ParameterError(
            f"{self.where}: {path} is {value!r}; allowed: {allowed}",
            parameter=self.parameter,
            value=value,
            element=path,
        )

    def table(self, name: str, data: Any, table: str, ranges: bool) -> dict[str, Any]:
        """One table checked: its keys, and each value's type (a number, a range, a list)."""
        if not isinstance(data, Mapping):
            raise self.refused(name, data, f"a table [{name}]")
        if table == IMU_TABLE:
            return self._imu_table(name, data, ranges)
        return self._values(name, data, JOINT_MODELS[table], ranges, per_joint=True)

    def _imu_table(self, name: str, data: Mapping[str, Any], ranges: bool) -> dict[str, Any]:
        model_keys = [f.name for f in dataclasses.fields(ImuNoiseModel)]
        keys = ["preset", *model_keys] if name == IMU_TABLE else model_keys
        self._known(name, data, keys)
        out: dict[str, Any] = {}
        if "preset" in data:
            preset = data["preset"]
            if not isinstance(preset, str) or preset.lower() not in IMU_PRESETS:
                raise self.refused(f"{name}.preset", preset, ", ".join(sorted(IMU_PRESETS)))
            out["preset"] = preset.lower()
        top = {k: v for k, v in data.items() if k not in ("preset", *SENSORS)}
        out.update(self._values(name, top, ImuNoiseModel, ranges, per_joint=False))
        for sensor in SENSORS:
            if sensor in data:
                where = f"{name}.{sensor}"
                if not isinstance(data[sensor], Mapping):
                    raise self.refused(where, data[sensor], f"a table [{where}]")
                out[sensor] = self._values(where, data[sensor], SensorNoise, ranges, False)
        return out

    def _known(self, name: str, data: Mapping[str, Any], keys: list[str]) -> None:
        unknown = sorted(set(data) - set(keys))
        if unknown:
            raise ParameterError(
                f"{self.where}: unknown key {name}.{unknown[0]}; allowed: {', '.join(keys)}",
                parameter=self.parameter,
                value=unknown[0],
                element=name,
            )

    def _values(
        self, name: str, data: Mapping[str, Any], model: type, ranges: bool, per_joint: bool
    ) -> dict[str, Any]:
        """A model's values in its field order, each a number, a range or (joints) a list."""
        names = [f.name for f in dataclasses.fields(model) if f.name not in SENSORS]
        self._known(name, data, names)
        defaults = {f.name: f.default for f in dataclasses.fields(model)}
        out: dict[str, Any] = {}
        for key in names:
            if key not in data:
                continue
            value, path = data[key], f"{name}.{key}"
            default = defaults[key]
            if isinstance(default, str) or (isinstance(default, bool) and not per_joint):
                out[key] = value  # checked by the model
            elif ranges and _range_given(value):
                out[key] = self._range(path, value)
            elif _is_number(value):
                out[key] = float(value)
            elif per_joint and isinstance(value, list) and value:
                out[key] = [
                    self._joint_entry(f"{path}[{i}]", v, ranges) for i, v in enumerate(value)
                ]
            elif not per_joint and not _range_given(value) and isinstance(value, list):
                out[key] = value  # a matrix or vector field: checked by the model
            else:
                allowed = "a number" + (", a range [low, high]" if ranges else "")
                raise self.refused(
                    path, value, allowed + (", or one per joint" if per_joint else "")
                )
        return out

    def _joint_entry(self, path: str, value: Any, ranges: bool) -> Any:
        if ranges and _range_given(value):
            return self._range(path, value)
        if _is_number(value):
            return float(value)
        raise self.refused(path, value, "a number" + (" or a range [low, high]" if ranges else ""))

    def _range(self, path: str, value: list[Any]) -> Range:
        if field_of(path) in NOT_DRAWN:
            raise self.refused(path, value, "a whole number (a filter setting is not drawn)")
        low, high = float(value[0]), float(value[1])
        if not (np.isfinite(low) and np.isfinite(high) and low <= high):
            raise self.refused(path, value, "a range [low, high] of finite numbers, low <= high")
        return Range(low, high)


NOT_DRAWN = ("decimation", "decimation_order")
"""The IMU fields a data set's config may not give as a range (whole-number filter settings)."""

WHOLE_COUNTS = ("counts_per_revolution", "counts_per_metre")
"""The fields a range draws as whole numbers (an encoder has a whole number of counts)."""


def field_of(path: str) -> str:
    """The field a value's path names: ``encoder.noise[2]`` → ``noise``."""
    return path.rsplit(".", 1)[-1].split("[", 1)[0]


def _is_number(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _range_given(value: Any) -> bool:
    """A TOML value written as a range: a list of two numbers."""
    return isinstance(value, list) and len(value) == 2 and all(_is_number(v) for v in value)
