"""An IMU model read back from a run's ``noise_parameters`` attribute.

The inverse of :func:`~aaria_pin.core.imu_noise.noise_attributes`: a key a file does not have
(written before the term existed) keeps the ADIS16485 value (the new terms: off).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import numpy as np

from aaria_pin.core.imu_noise import (
    ADIS16485,
    MODEL_ATTRIBUTE_KEYS,
    ImuNoiseModel,
    attribute_key,
)

__all__ = ["noise_model_from_attributes"]


def _stored(value: Any, name: str) -> Any:
    """A stored attribute as its field takes it (a matrix's nine numbers as 3 × 3 rows)."""
    if name == "alignment":
        rows = np.asarray(value, dtype=np.float64).reshape(3, 3)
        return tuple(tuple(float(v) for v in row) for row in rows)
    return float(value)


def noise_model_from_attributes(stored: Mapping[str, Any] | None) -> ImuNoiseModel:
    """The IMU model a run's ``noise_parameters`` record (None or empty: the ADIS16485).

    Raises:
        ParameterError: a stored value out of its field's range (as :class:`ImuNoiseModel`).
    """
    if not stored:
        return ADIS16485
    sensors: dict[str, dict[str, Any]] = {"gyro": {}, "accel": {}}
    for sensor, values in sensors.items():
        for f in dataclasses.fields(getattr(ADIS16485, sensor)):
            key = attribute_key(sensor, f.name)
            if key in stored:
                values[f.name] = _stored(stored[key], f.name)
    top: dict[str, Any] = {}
    for name, key in MODEL_ATTRIBUTE_KEYS.items():
        if key in stored:
            value = float(stored[key])
            top[name] = int(value) if name.startswith("decimation") else value
    return dataclasses.replace(
        ADIS16485,
        gyro=dataclasses.replace(ADIS16485.gyro, **sensors["gyro"]),
        accel=dataclasses.replace(ADIS16485.accel, **sensors["accel"]),
        **top,
    )
