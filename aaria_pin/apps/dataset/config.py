"""A data set's configuration file: the ranges of the random parts and the run's hardware.

``aaria dataset --config FILE`` reads a TOML file whose top-level keys are those of
:class:`~aaria_pin.aaria.randomize.RandomConfig` (ranges ``[low, high]``, choices, probabilities;
missing keys keep their defaults) and, optionally, the hardware tables of
:mod:`aaria_pin.aaria.hardware`: ``[imu]`` (``preset`` and the IMU model's fields, sub-tables
``[imu.gyro]`` and ``[imu.accel]``; the older ``[noise]`` table reads as ``[imu]``),
``[encoder]``, ``[torque_sensor]`` and ``[actuator]``. In them any number may be a range
``[low, high]``, drawn for each run from its ``hardware`` stream (per joint for a joint model's
field), so a data set spans sensor qualities::

    a = [0.5, 0.9]            # link lengths [m]

    [imu]
    preset = "bmi088"

    [imu.gyro]
    noise_density = [1.0e-4, 3.0e-4]    # [rad/s/sqrt(Hz)], drawn per run

    [encoder]
    counts_per_revolution = 4096.0

Every value is checked for its type before use: a range given as text (``a = "long"``) is
refused naming the key, and a file that is not UTF-8 is refused in one line.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from aaria_pin.aaria.hardware import HARDWARE_TABLES, LEGACY_IMU_TABLE, HardwareConfig
from aaria_pin.aaria.randomize import RandomConfig, config_from_mapping, read_config_file
from aaria_pin.core.imu_noise import ImuNoiseModel
from aaria_pin.errors import ParameterError

__all__ = ["load_dataset_config"]


def load_dataset_config(
    path: str | Path | None, imu_model: ImuNoiseModel | None = None
) -> tuple[RandomConfig, HardwareConfig]:
    """Read a data set's configuration file (see the module docstring).

    Args:
        path: the TOML file (None: the defaults)
        imu_model: the ``--imu-model`` flag's model (the base of the ``[imu]`` values)

    Returns:
        The ranges of the random parts, and the hardware tables (ranges allowed).

    Raises:
        InputFileError: the file is missing, unreadable, not UTF-8 or not TOML.
        ParameterError: an unknown key, a value of the wrong type, or out of its allowed set.
    """
    if path is None:
        return RandomConfig(), HardwareConfig({}, imu_model, "config", "config")
    file = Path(path)
    data = read_config_file(file)
    tables = {key: data.pop(key) for key in (*HARDWARE_TABLES, LEGACY_IMU_TABLE) if key in data}
    _check_value_types(data, str(file))
    hardware = HardwareConfig.from_mapping(tables, str(file), "config", True, imu_model)
    return config_from_mapping(data, str(file)), hardware


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


def _refused(name: str, value: Any, allowed: str, element: str) -> ParameterError:
    """``NAME is VALUE; allowed: ALLOWED`` of ``parameter`` ``config``, ``element`` the key."""
    return ParameterError(
        f"{name} is {value!r}; allowed: {allowed}",
        parameter="config",
        value=value,
        element=element,
    )
