"""IMU device presets: data-sheet parts by name, each with the data-sheet rows it was made from.

Every preset's numbers come from its data sheet (:data:`PRESET_ROWS`: name, value, unit and the
table it is in). A term the data sheet does not specify is off (0) in the preset. Conventions
(``docs/guide/imu.md``):

* a data sheet's typical ``±x`` tolerance (scale factor, cross-axis, turn-on offset) is taken as
  the 1σ of the per-run draw;
* noise densities are one-sided (the Allan ARW/VRW is ``N/√2``, :mod:`aaria_pin.core.imu_noise`);
* the in-run bias stability ``b`` is the σ of the Gauss–Markov bias (T = 100 s), as the
  ADIS16485 of 0.3 has it;
* the resolution is the part's widest output word (ADIS16470: 32-bit outputs, ICM-42688-P:
  the 19/18-bit FIFO words) so that quantisation does not swamp the noise (notes 0.3);
* a part whose noise differs by axis (BMI088, ICM-42688-P: z noisier) uses the x/y value.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from aaria_pin.core.imu_datasheets import DATASHEET_ROWS, PRESET_ROWS, PRESET_SOURCES
from aaria_pin.core.imu_model import STANDARD_GRAVITY, ImuNoiseModel, SensorNoise
from aaria_pin.errors import ParameterError

__all__ = [
    "ADIS16485",
    "DATASHEET_ROWS",
    "DEFAULT_IMU_MODEL",
    "IMU_PRESETS",
    "MODEL_CHOICES",
    "MODEL_FIELDS",
    "PRESET_ROWS",
    "PRESET_SOURCES",
    "SENSOR_FIELDS",
    "imu_model_toml",
    "imu_preset",
]

_DEG = np.pi / 180.0
_G = STANDARD_GRAVITY
_DEG_H = _DEG / 3600.0  # °/h in rad/s
_DEG_G = _DEG / _G  # °/s per g in rad/s per m/s²

ADIS16485 = ImuNoiseModel(
    gyro=SensorNoise(
        range=450.0 * _DEG,  # ±450 °/s
        lsb=0.02 * _DEG,  # 0.02 °/s per LSB
        noise_density=0.0066 * _DEG,  # 0.0066 °/s/√Hz
        bias_stability=6.25 * _DEG / 3600.0,  # 6.25 °/h
        random_walk=0.3 * _DEG / 60.0,  # 0.3 °/√h; √h = 60 √s
    ),
    accel=SensorNoise(
        range=5.0 * STANDARD_GRAVITY,  # ±5 g
        lsb=0.25e-3 * STANDARD_GRAVITY,  # 0.25 mg per LSB
        noise_density=0.067e-3 * STANDARD_GRAVITY,  # 0.067 mg/√Hz
        bias_stability=32e-6 * STANDARD_GRAVITY,  # 32 µg
        random_walk=0.023 / 60.0,  # 0.023 m/s/√h
    ),
    bandwidth_hz=330.0,
    internal_rate_hz=2460.0,
    bias_correlation_time=100.0,
)
"""The ADIS16485 of the data sheet (:data:`DATASHEET_ROWS`), in SI units: the 0.3 numbers."""


def _sensor(**values: Any) -> SensorNoise:
    """A sensor's terms; ``random_walk`` (reference only) 0 where the data sheet gives none."""
    return SensorNoise(**{"random_walk": 0.0, "bias_stability": 0.0, **values})


IMU_PRESETS: dict[str, ImuNoiseModel] = {
    "adis16485": ADIS16485,
    "adis16470": ImuNoiseModel(
        gyro=_sensor(
            range=2000.0 * _DEG,
            lsb=0.1 * _DEG / 65536,
            noise_density=0.008 * _DEG,
            bias_stability=8.0 * _DEG_H,
        ),
        accel=_sensor(
            range=40.0 * _G,
            lsb=1.25e-3 * _G / 65536,
            noise_density=0.1e-3 * _G,
            bias_stability=13e-6 * _G,
        ),
        bandwidth_hz=720.0,
        internal_rate_hz=2000.0,
        decimation_order=2,
    ),
    "bmi088": ImuNoiseModel(
        gyro=_sensor(
            range=2000.0 * _DEG,
            lsb=_DEG / 16.384,
            noise_density=0.014 * _DEG,
            bias_offset=1.0 * _DEG,
            scale_error=0.01,
            nonlinearity=0.0005,
            cross_axis=0.01,
            g_sensitivity=0.1 * _DEG_G,
        ),
        accel=_sensor(
            range=6.0 * _G,
            lsb=_G / 5460.0,
            noise_density=160e-6 * _G,
            bias_offset=20e-3 * _G,
            nonlinearity=0.005,
            cross_axis=0.005,
            misalignment=0.5 * _DEG,
        ),
        bandwidth_hz=40.0,
        internal_rate_hz=100.0,
        decimation_order=3,
    ),
    "icm42688p": ImuNoiseModel(
        gyro=_sensor(
            range=2000.0 * _DEG,
            lsb=2000.0 * _DEG / 2**18,
            noise_density=0.0028 * _DEG,
            bias_offset=0.5 * _DEG,
            scale_error=0.005,
            nonlinearity=0.001,
            cross_axis=0.0125,
        ),
        accel=_sensor(
            range=16.0 * _G,
            lsb=_G / 8192.0,
            noise_density=65e-6 * _G,
            bias_offset=20e-3 * _G,
            scale_error=0.005,
            nonlinearity=0.001,
            cross_axis=0.01,
        ),
        bandwidth_hz=498.0,
        internal_rate_hz=1000.0,
        decimation_order=3,
    ),
    "mpu6050": ImuNoiseModel(
        gyro=_sensor(
            range=250.0 * _DEG,
            lsb=_DEG / 131.0,
            noise_density=0.005 * _DEG,
            bias_offset=20.0 * _DEG,
            scale_error=0.03,
            nonlinearity=0.002,
            cross_axis=0.02,
            g_sensitivity=0.1 * _DEG_G,
        ),
        accel=_sensor(
            range=2.0 * _G,
            lsb=_G / 16384.0,
            noise_density=400e-6 * _G,
            bias_offset=50e-3 * _G,
            scale_error=0.03,
            nonlinearity=0.005,
            cross_axis=0.02,
        ),
        bandwidth_hz=256.0,
        internal_rate_hz=8000.0,
        decimation_order=3,
    ),
}
"""The device presets by name (lower case); see :data:`PRESET_ROWS` for their sources."""

DEFAULT_IMU_MODEL = "adis16485"
"""The preset every run uses unless told otherwise (the Aaria paper's part)."""


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


SENSOR_FIELDS: dict[str, tuple[str, str]] = {
    "range": ("{u}", "full scale, the output saturates at +/-range"),
    "lsb": ("{u}", "quantisation step, one LSB"),
    "noise_density": ("{u}/sqrt(Hz)", "white noise density, one-sided (ADEV N/sqrt(2 tau))"),
    "bias_stability": ("{u}", "in-run bias instability: sigma of the Gauss-Markov bias"),
    "random_walk": ("{w}", "data-sheet ARW/VRW, kept for reference (0: not given)"),
    "scale_error": ("1", "scale-factor error per axis, 1 sigma, < 1"),
    "nonlinearity": ("1 (of FS)", "best-fit-line non-linearity, fraction of full scale, < 1"),
    "cross_axis": ("1", "cross-axis sensitivity, each off-diagonal, 1 sigma, < 1"),
    "misalignment": ("rad", "axis misalignment, random rotation angle per axis, 1 sigma"),
    "alignment": ("3 x 3", "a fixed rotation applied after the random one (rows)"),
    "g_sensitivity": ("rad/s per m/s^2", "gyroscope g-sensitivity, each entry, 1 sigma"),
    "bias_offset": ("{u}", "turn-on bias per axis, 1 sigma"),
    "bias_random_walk": ("{u}/sqrt(s)", "bias random walk K (ADEV K*sqrt(tau/3))"),
}
"""The unit and meaning of each :class:`SensorNoise` field (``{u}``: the sensor's unit)."""

MODEL_FIELDS: dict[str, tuple[str, str]] = {
    "bandwidth_hz": ("Hz", "sensor bandwidth, reference only"),
    "internal_rate_hz": ("Hz", "internal sample rate, reference only"),
    "bias_correlation_time": ("s", "correlation time of the Gauss-Markov bias"),
    "time_offset": (
        "s",
        "fixed offset of every IMU's sampling instants (the sample stamped t "
        "is the signal at t + offset: a bus latency L is -L)",
    ),
    "time_offset_sigma": ("s", "random offset per IMU per run, 1 sigma"),
    "jitter": ("s", "sample-time jitter, 1 sigma per sample"),
    "decimation": ("1", "D: sample at D x the run's rate, filter, keep every D-th (1: off)"),
    "decimation_order": ("1", "filter: 1 boxcar, 2 Bartlett, 3 smoother low-pass"),
}
"""The unit and meaning of each per-IMU field of :class:`ImuNoiseModel`."""

_SENSOR_UNITS = {"gyro": ("rad/s", "rad/sqrt(s)"), "accel": ("m/s^2", "m/s/sqrt(s)")}


def _toml_value(value: Any) -> str:
    if isinstance(value, tuple):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, int):
        return str(value)
    return repr(float(value))


MODEL_CHOICES = ("bias_correlation_time", "decimation_order")
"""Fields a preset sets without a data-sheet row: the Gauss–Markov bias's correlation time
(100 s, the 0.3 model's) and the decimation filter (the part's kind of filter, docs)."""


def _field_sources(key: str) -> dict[str, str]:
    """Each field's data-sheet rows of preset ``key``, as one comment's text."""
    sources: dict[str, list[str]] = {}
    for quantity, value, unit, where, field in PRESET_ROWS[key]:
        sources.setdefault(field, []).append(f"{quantity}: {value:g} {unit} ({where})")
    return {field: "; ".join(rows) for field, rows in sources.items()}


def _source_comment(sources: dict[str, str], field: str, value: Any) -> str:
    """The comment line above a field: its data-sheet rows, or why it has none."""
    name = field.rsplit(".", 1)[-1]
    if field in sources:
        return f"# data sheet: {sources[field]}"
    if name in MODEL_CHOICES:
        return "# not a data-sheet value: the model's choice"
    if value is None or not value or (name == "decimation" and value == 1):
        return "# not specified by the data sheet: off"
    return "# not a data-sheet value"


def imu_model_toml(name: str) -> str:
    """The TOML text of preset ``name``: every field with its unit and its data-sheet source.

    ``[imu]`` names the preset and holds the per-IMU fields, ``[imu.gyro]`` and
    ``[imu.accel]`` the sensors'; :func:`imu_model_from_toml` reads it back to the preset. Above
    each field a comment gives the data-sheet rows it comes from (:data:`PRESET_ROWS`) or says
    that the data sheet does not specify it (the term is then off).

    Raises:
        ParameterError: an unknown preset (parameter ``imu_model``).
    """
    model = imu_preset(name)
    key = str(name).lower()
    sources = _field_sources(key)
    lines = [
        f"# IMU model {key}: {PRESET_SOURCES[key]}.",
        "# SI units; 0 turns a term off (range and lsb: not 0). Keys left out keep the preset's.",
        "# A data-sheet tolerance +/-x is drawn as 1 sigma = x (docs/guide/imu.md).",
        "",
        "[imu]",
        f'preset = "{key}"',
    ]
    for field_name, (unit, text) in MODEL_FIELDS.items():
        value = getattr(model, field_name)
        lines.append(_source_comment(sources, field_name, value))
        lines.append(f"{field_name} = {_toml_value(value)}  # [{unit}] {text}")
    for sensor in ("gyro", "accel"):
        u, w = _SENSOR_UNITS[sensor]
        lines += ["", f"[imu.{sensor}]"]
        noise: SensorNoise = getattr(model, sensor)
        for field_name, (unit, text) in SENSOR_FIELDS.items():
            value = getattr(noise, field_name)
            if field_name == "g_sensitivity" and sensor == "accel":
                continue
            lines.append(_source_comment(sources, f"{sensor}.{field_name}", value))
            shown = f"[{unit.format(u=u, w=w)}] {text}"
            if value is None:
                lines.append(f"# {field_name} = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]  # {shown}")
                continue
            lines.append(f"{field_name} = {_toml_value(value)}  # {shown}")
    return "\n".join(lines) + "\n"
