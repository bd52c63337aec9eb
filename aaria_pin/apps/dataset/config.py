"""A data set's configuration file: the ranges of the random parts and the IMU noise model.

``aaria dataset --config FILE`` reads a TOML file whose top-level keys are those of
:class:`~aaria_pin.aaria.randomize.RandomConfig` (ranges ``[low, high]``, choices, probabilities;
missing keys keep their defaults) and, optionally, a ``[noise]`` table of the IMU noise model
(:class:`~aaria_pin.core.imu_noise.ImuNoiseModel`: ``bandwidth_hz``, ``internal_rate_hz``,
``bias_correlation_time``, and the sub-tables ``[noise.gyro]`` and ``[noise.accel]`` with the
fields of :class:`~aaria_pin.core.imu_noise.SensorNoise`: ``range``, ``lsb``,
``noise_density``, ``bias_stability``, ``random_walk``, SI units per axis). A noise key not
given keeps the ADIS16485 data-sheet value (:data:`~aaria_pin.core.imu_noise.ADIS16485`)::

    a = [0.5, 0.9]            # link lengths [m]

    [noise]
    bias_correlation_time = 50.0

    [noise.gyro]
    noise_density = 2.0e-4    # [rad/s/sqrt(Hz)]

Every value is checked for its type before use: a range given as text (``a = "long"``) is
refused naming the key, and a file that is not UTF-8 is refused in one line.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from aaria_pin.aaria.randomize import (
    RandomConfig,
    config_from_mapping,
    read_config_file,
    refuse_unknown_keys,
)
from aaria_pin.core.imu_noise import ADIS16485, ImuNoiseModel, SensorNoise
from aaria_pin.errors import AariaError, ParameterError

__all__ = ["NOISE_TABLE", "load_dataset_config", "noise_model_from_mapping"]

NOISE_TABLE = "noise"
"""The TOML table of the IMU noise model in a data set's configuration."""

_SENSORS = ("gyro", "accel")


def load_dataset_config(
    path: str | Path | None,
) -> tuple[RandomConfig, ImuNoiseModel]:
    """Read a data set's configuration file (see the module docstring).

    Args:
        path: the TOML file (None: the defaults)

    Returns:
        The ranges of the random parts, and the IMU noise model.

    Raises:
        InputFileError: the file is missing, unreadable, not UTF-8 or not TOML.
        ParameterError: an unknown key, a value of the wrong type, or out of its allowed set.
    """
    if path is None:
        return RandomConfig(), ADIS16485
    file = Path(path)
    data = read_config_file(file)
    noise = data.pop(NOISE_TABLE, {})
    _check_value_types(data, str(file))
    return config_from_mapping(data, str(file)), noise_model_from_mapping(noise, str(file))


def _check_value_types(data: Mapping[str, Any], where: str) -> None:
    """Refuse a value whose type its key cannot take (text for a range, a number for a flag)."""
    defaults = {
        item.name: getattr(RandomConfig(), item.name) for item in dataclasses.fields(RandomConfig)
    }
    for key, value in data.items():
        if key not in defaults:
            continue  # named by config_from_mapping
        default = defaults[key]
        if isinstance(default, bool):
            if not isinstance(value, bool):
                raise _refused(f"{where}: {key}", value, "true or false", key)
            continue
        numbers = isinstance(value, list) and all(
            isinstance(v, int | float) and not isinstance(v, bool) for v in value
        )
        if not numbers:
            example = "[" + ", ".join(f"{v:g}" for v in default) + "]"
            raise _refused(f"{where}: {key}", value, f"a list of numbers, e.g. {example}", key)


def noise_model_from_mapping(data: Any, where: str = "config") -> ImuNoiseModel:
    """An IMU noise model from a ``[noise]`` table; keys not given keep ADIS16485's values.

    Raises:
        ParameterError: not a table, an unknown key, or a value that is not a finite number
            of its allowed range.
    """
    if not isinstance(data, Mapping):
        raise _refused(f"{where}: {NOISE_TABLE}", data, f"a table [{NOISE_TABLE}]", NOISE_TABLE)
    model_keys = [f.name for f in dataclasses.fields(ImuNoiseModel)]
    refuse_unknown_keys(data, model_keys, f"{where}: {NOISE_TABLE}")
    changes: dict[str, Any] = {}
    for key, value in data.items():
        name = f"{NOISE_TABLE}.{key}"
        if key in _SENSORS:
            changes[key] = _sensor(getattr(ADIS16485, key), value, f"{where}: {name}")
        else:
            changes[key] = _number(value, f"{where}: {name}")
    try:
        return dataclasses.replace(ADIS16485, **changes)
    except AariaError as exc:
        raise ParameterError(
            f"{where}: {NOISE_TABLE}.{exc}",
            parameter="config",
            value=exc.value,
            element=NOISE_TABLE,
        ) from None


def _sensor(base: SensorNoise, data: Any, where: str) -> SensorNoise:
    if not isinstance(data, Mapping):
        raise _refused(where, data, "a table of its noise parameters", where)
    refuse_unknown_keys(data, [f.name for f in dataclasses.fields(SensorNoise)], where)
    values = {key: _number(value, f"{where}.{key}") for key, value in data.items()}
    try:
        return dataclasses.replace(base, **values)
    except AariaError as exc:
        raise ParameterError(
            f"{where}.{exc}", parameter="config", value=exc.value, element=where
        ) from None


def _number(value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise _refused(where, value, "a number", where)
    return float(value)


def _refused(name: str, value: Any, allowed: str, element: str) -> ParameterError:
    """``NAME is VALUE; allowed: ALLOWED`` of ``parameter`` ``config``, ``element`` the key."""
    return ParameterError(
        f"{name} is {value!r}; allowed: {allowed}",
        parameter="config",
        value=value,
        element=element,
    )
