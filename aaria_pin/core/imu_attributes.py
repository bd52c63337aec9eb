"""An IMU model read back from a run's ``noise_parameters`` attribute (CONTRACT STUB).

The inverse of :func:`~aaria_pin.core.imu_noise.noise_attributes`: a key a file does not have
(written before the term existed) keeps the ADIS16485 value (the new terms: off).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

from aaria_pin.core.imu_noise import ADIS16485, ImuNoiseModel, noise_attributes

__all__ = ["noise_model_from_attributes"]


def noise_model_from_attributes(stored: Mapping[str, Any] | None) -> ImuNoiseModel:
    """The IMU model a run's ``noise_parameters`` record (None or empty: the ADIS16485)."""
    if not stored:
        return ADIS16485
    sensors: dict[str, dict[str, float]] = {"gyro": {}, "accel": {}}
    top: dict[str, float] = {}
    default_keys = noise_attributes(ADIS16485)
    for key in default_keys:
        if key not in stored:
            continue
        value = float(stored[key])
        sensor = key.split("_", 1)[0]
        if sensor in sensors:
            field_name = next(
                f.name
                for f in dataclasses.fields(getattr(ADIS16485, sensor))
                if key.startswith(f"{sensor}_{f.name}_")
            )
            sensors[sensor][field_name] = value
        else:
            top[{"bias_correlation_time_s": "bias_correlation_time"}.get(key, key)] = value
    return dataclasses.replace(
        ADIS16485,
        gyro=dataclasses.replace(ADIS16485.gyro, **sensors["gyro"]),
        accel=dataclasses.replace(ADIS16485.accel, **sensors["accel"]),
        **top,
    )
