"""IMU device presets: data-sheet parts by name (CONTRACT STUB: only the ADIS16485 so far)."""

from __future__ import annotations

from aaria_pin.core.imu_noise import ADIS16485, ImuNoiseModel
from aaria_pin.errors import ParameterError

__all__ = ["DEFAULT_IMU_MODEL", "IMU_PRESETS", "imu_preset"]

DEFAULT_IMU_MODEL = "adis16485"
"""The preset every run uses unless told otherwise (the Aaria paper's part)."""

IMU_PRESETS: dict[str, ImuNoiseModel] = {"adis16485": ADIS16485}
"""The device presets by name (lower case)."""


def imu_preset(name: str) -> ImuNoiseModel:
    """The preset ``name`` (case-insensitive).

    Raises:
        ParameterError: an unknown preset (parameter ``imu_model``).
    """
    key = str(name).lower()
    if key not in IMU_PRESETS:
        raise ParameterError(
            parameter="imu_model", value=name, allowed=", ".join(sorted(IMU_PRESETS))
        )
    return IMU_PRESETS[key]
