"""The parameters of an IMU's error model: per sensor type (:class:`SensorNoise`) and per IMU.

Every term is in SI units and every term added in 0.4 is off (0) by default, so a model made
with the fields of 0.3 measures as 0.3 did, bit for bit. The error equation and how each term
is drawn are in :mod:`aaria_pin.core.imu_errors` and ``docs/guide/imu.md``; the unit ``u`` is
rad/s for a gyroscope and m/s² for an accelerometer.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from aaria_pin.errors import ParameterError

__all__ = [
    "DECIMATION_ORDERS",
    "ROTATION_TOLERANCE",
    "STANDARD_GRAVITY",
    "ImuNoiseModel",
    "SensorNoise",
    "check_rotation",
]

STANDARD_GRAVITY = 9.80665
"""Standard gravity, the data sheet's g [m/s²]."""

ROTATION_TOLERANCE = 1e-9
"""How far a given alignment matrix may be from a rotation: ``|RᵀR - I|`` and ``|det R - 1|``."""

DECIMATION_ORDERS = (1, 2, 3)
"""Decimation filters: ``order`` cascaded D-sample moving averages (1 boxcar, 2 Bartlett)."""


def _check(name: str, value: float, allow_zero: bool = False, below: float | None = None) -> None:
    """Refuse a value that is not finite, or not > 0 (>= 0 with ``allow_zero``), or >= ``below``."""
    ok = value >= 0.0 if allow_zero else value > 0.0
    if below is not None:
        ok = ok and value < below
    if not (np.isfinite(value) and ok):
        bound = ">= 0" if allow_zero else "> 0"
        if below is not None:
            bound += f" and < {below:g}"
        raise ParameterError(
            f"{name} is {value!r}; allowed: a finite number {bound}",
            parameter=name,
            value=value,
            allowed=f"a finite number {bound}",
        )


def check_rotation(name: str, matrix: Any) -> np.ndarray:
    """``matrix`` as a 3 × 3 float64 rotation (``RᵀR = I``, ``det R = +1`` to 1e-9).

    Raises:
        ParameterError: not a finite 3 × 3 matrix, or not a rotation (parameter ``name``).
    """
    allowed = "a 3 × 3 rotation matrix (RᵀR = I and det R = +1, to 1e-9)"
    try:
        rotation = np.asarray(matrix, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError(parameter=name, value=matrix, allowed=allowed) from None
    if rotation.shape != (3, 3) or not np.isfinite(rotation).all():
        raise ParameterError(parameter=name, value=rotation, allowed=allowed)
    orthogonal = np.abs(rotation.T @ rotation - np.eye(3)).max() <= ROTATION_TOLERANCE
    if not (orthogonal and abs(np.linalg.det(rotation) - 1.0) <= ROTATION_TOLERANCE):
        raise ParameterError(parameter=name, value=rotation, allowed=allowed)
    return rotation


@dataclass(frozen=True)
class SensorNoise:
    """Error terms of one sensor type (gyroscope or accelerometer), per axis, SI units.

    The first five fields are those of 0.3; the others are off (0) by default. A "1σ" term is
    drawn per IMU per run from the run's IMU sensor-error stream
    (:mod:`~aaria_pin.core.imu_errors`).

    Attributes:
        range: full scale, the output saturates at ±range [u]
        lsb: quantisation step, one least significant bit [u]
        noise_density: white noise density, one-sided [u/√Hz]
        bias_stability: in-run bias instability, the σ of the Gauss–Markov bias (1σ) [u]
        random_walk: angle [rad/√s] or velocity [m/s/√s] random walk as listed in the data sheet;
            kept for reference, the white noise is generated from ``noise_density``
        scale_error: scale-factor error per axis, 1σ [1], < 1
        nonlinearity: best-fit-line non-linearity as a fraction of full scale [1], < 1: a
            quadratic term ``k2·x²`` per axis, ``k2 = 1.5·nonlinearity/range``, random sign
        cross_axis: cross-axis sensitivity, each off-diagonal of the axis matrix, 1σ [1]
        misalignment: axis-to-package misalignment, a random rotation ``exp([θ]×)``,
            ``θ ~ N(0, misalignment² I)`` [rad]
        alignment: a fixed rotation applied after the random one (None: identity), 3 × 3
        g_sensitivity: gyroscope linear-acceleration sensitivity, each entry of G, 1σ
            [rad/s per m/s²]; gyroscope only
        bias_offset: turn-on bias per axis, 1σ [u]
        bias_random_walk: bias (rate) random walk ``K``, Allan deviation ``K·√(τ/3)`` [u/√s]
    """

    range: float
    lsb: float
    noise_density: float
    bias_stability: float
    random_walk: float
    scale_error: float = 0.0
    nonlinearity: float = 0.0
    cross_axis: float = 0.0
    misalignment: float = 0.0
    alignment: Any = None  # a 3 × 3 rotation as rows of floats (tuples once checked), or None
    g_sensitivity: float = 0.0
    bias_offset: float = 0.0
    bias_random_walk: float = 0.0

    def __post_init__(self) -> None:
        for f in fields(self):
            if f.name == "alignment":
                continue
            below = 1.0 if f.name in ("scale_error", "nonlinearity", "cross_axis") else None
            _check(f.name, getattr(self, f.name), f.name not in ("range", "lsb"), below)
        if self.alignment is not None:
            rotation = check_rotation("alignment", self.alignment)
            object.__setattr__(self, "alignment", tuple(tuple(map(float, r)) for r in rotation))

    @property
    def matrix_terms(self) -> bool:
        """Whether the axis matrix is not the identity (scale, cross-axis or misalignment on)."""
        return bool(
            self.scale_error or self.cross_axis or self.misalignment or self.alignment is not None
        )


@dataclass(frozen=True)
class ImuNoiseModel:
    """Error model of a six-axis IMU.

    Attributes:
        gyro: gyroscope terms [rad/s]
        accel: accelerometer terms [m/s²] (its ``g_sensitivity`` must be 0)
        bandwidth_hz: sensor bandwidth [Hz]; kept for reference
        internal_rate_hz: internal sample rate [Hz]; kept for reference
        bias_correlation_time: correlation time of the Gauss–Markov bias [s]
        time_offset: a fixed offset of every IMU's sampling instants [s] (any sign)
        time_offset_sigma: a random offset per IMU per run, 1σ [s]
        jitter: sample-time jitter, i.i.d. per sample and IMU, 1σ [s]
        decimation: D >= 1: the IMU samples at D × the run's rate and outputs every D-th value
            of its filter (1: off)
        decimation_order: the filter, ``order`` cascaded D-sample moving averages
            (:data:`DECIMATION_ORDERS`: 1 boxcar, 2 Bartlett, 3 a smoother low-pass)
    """

    gyro: SensorNoise
    accel: SensorNoise
    bandwidth_hz: float = 330.0
    internal_rate_hz: float = 2460.0
    bias_correlation_time: float = 100.0
    time_offset: float = 0.0
    time_offset_sigma: float = 0.0
    jitter: float = 0.0
    decimation: int = 1
    decimation_order: int = 1

    def __post_init__(self) -> None:
        for name in ("bandwidth_hz", "internal_rate_hz", "bias_correlation_time"):
            _check(name, getattr(self, name))
        for name in ("time_offset_sigma", "jitter"):
            _check(name, getattr(self, name), allow_zero=True)
        if not np.isfinite(self.time_offset):
            raise ParameterError(
                parameter="time_offset", value=self.time_offset, allowed="a finite number [s]"
            )
        decimation = self.decimation
        try:
            whole = float(decimation).is_integer() and 1 <= decimation <= 4096
        except (TypeError, ValueError):
            whole = False
        if not whole or isinstance(decimation, bool):
            raise ParameterError(
                parameter="decimation", value=decimation, allowed="a whole number 1 to 4096"
            )
        object.__setattr__(self, "decimation", int(decimation))
        if self.decimation_order not in DECIMATION_ORDERS:
            raise ParameterError(
                parameter="decimation_order",
                value=self.decimation_order,
                allowed=", ".join(map(str, DECIMATION_ORDERS)),
            )
        object.__setattr__(self, "decimation_order", int(self.decimation_order))
        if self.accel.g_sensitivity != 0.0:
            raise ParameterError(
                f"accel.g_sensitivity is {self.accel.g_sensitivity!r}; allowed: 0 (a gyroscope "
                "term: set it in the gyro table)",
                parameter="g_sensitivity",
                value=self.accel.g_sensitivity,
                allowed="0 for an accelerometer",
            )

    @property
    def timing(self) -> bool:
        """Whether the IMU samples off the run's grid (time offset or jitter) or decimates."""
        return bool(self.time_offset or self.time_offset_sigma or self.jitter) or (
            self.decimation > 1
        )

    @property
    def needs_whole_run(self) -> bool:
        """Whether the run must be computed in one piece: timing terms or a bias random walk."""
        walk = self.gyro.bias_random_walk or self.accel.bias_random_walk
        return self.timing or bool(walk)

    @property
    def new_terms(self) -> bool:
        """Whether any term added in 0.4 is on (then the IMU sensor-error stream is drawn)."""
        per_sensor = ("nonlinearity", "g_sensitivity", "bias_offset", "bias_random_walk")
        sensors = (self.gyro, self.accel)
        on = any(s.matrix_terms or any(getattr(s, n) for n in per_sensor) for s in sensors)
        return on or self.timing
