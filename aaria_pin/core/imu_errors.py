"""The IMU errors drawn once per run, and how they turn exact signals into sensed ones.

Per IMU and sensor (gyroscope ``g``, accelerometer ``a``), before the white noise, the in-run
bias, saturation and quantisation of :func:`~aaria_pin.core.imu_noise.add_imu_noise`::

    ω' = M_g·ω + k2_g∘ω² + G·f + b0_g + b_RW,g(t)
    f' = M_a·f + k2_a∘f²        + b0_a + b_RW,a(t)
    M  = (I + diag(s))·C·R·A

with ω and f the exact signals at the IMU's sampling instants (:mod:`~aaria_pin.core.imu_timing`).
Each term is drawn from its own child of the run's IMU sensor-error stream
(:func:`~aaria_pin.core.seeds.sensor_sequence` part ``imu``; term ``name`` is its child
``TERMS.index(name)``),
for every record slot (rows of empty slots are then zeroed), only when it is on:

* scale ``s``: ``N(0, scale_error²)`` per axis; ``imu_error_scale`` S × 6;
* cross-axis ``C``: ``I`` plus off-diagonals ``N(0, cross_axis²)``; ``imu_error_cross_axis``
  S × 2 × 3 × 3;
* misalignment ``R·A``: ``R = exp([θ]×)``, ``θ ~ N(0, misalignment² I)``, then the fixed
  ``alignment`` ``A``; ``imu_error_misalignment`` S × 2 × 3 × 3;
* with any of those three, the product ``M``: ``imu_error_matrix`` S × 2 × 3 × 3;
* g-sensitivity ``G``: entries ``N(0, g_sensitivity²)``; ``imu_error_g_sensitivity`` S × 3 × 3;
* non-linearity ``k2 = ±1.5·nonlinearity/range``, sign uniform per axis;
  ``imu_error_nonlinearity`` S × 6;
* turn-on bias ``b0``: ``N(0, bias_offset²)`` per axis; ``imu_error_bias_offset`` S × 6;
* time offset ``δ = time_offset + N(0, time_offset_sigma²)`` per IMU; ``imu_error_time_offset`` S;
* jitter ``ε``: ``N(0, jitter²)`` per sample and IMU; ``imu_error_jitter`` T × S;
* bias random walk ``b_k = b_{k-1} + K·w_k/√rate`` (``b_{-1} = 0``);
  ``imu_error_bias_random_walk`` T × (S·6), slot by slot ``[wx wy wz fx fy fz]``;
* decimation: the filter's white noise, standard normals at ``D·rate`` (not stored: re-drawn
  from the seed).

The ``2`` axis of a matrix table is (gyroscope, accelerometer); six columns are
``[wx wy wz fx fy fz]``. Every table is float64. A run whose every term is off draws nothing.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from aaria_pin.core.imu_model import ImuNoiseModel, SensorNoise
from aaria_pin.core.imu_timing import (
    decimation_filter,
    filtered_white_noise,
    sampled_signals,
)
from aaria_pin.core.se3 import Array

__all__ = ["TERMS", "ImuErrors", "draw_imu_errors", "imu_error_shapes"]

TERMS = (
    "scale",
    "cross_axis",
    "misalignment",
    "g_sensitivity",
    "nonlinearity",
    "bias_offset",
    "time_offset",
    "jitter",
    "bias_random_walk",
    "decimation",
)
"""The drawn terms; term ``name`` draws from child ``TERMS.index(name)`` of the IMU stream
(file format: a new term goes at the end)."""

_SENSORS = ("gyro", "accel")


def _rotation(theta: Array) -> Array:
    """``exp([θ]×)`` of rotation vectors, (..., 3) → (..., 3, 3) (Rodrigues)."""
    angle = np.linalg.norm(theta, axis=-1)
    k = theta / np.where(angle > 0.0, angle, 1.0)[..., None]
    zero = np.zeros_like(angle)
    x, y, z = k[..., 0], k[..., 1], k[..., 2]
    skew = np.stack([zero, -z, y, z, zero, -x, -y, x, zero], axis=-1).reshape(*angle.shape, 3, 3)
    sin, cos = np.sin(angle)[..., None, None], np.cos(angle)[..., None, None]
    return np.eye(3) + sin * skew + (1.0 - cos) * (skew @ skew)


@dataclass(frozen=True)
class ImuErrors:
    """The IMU errors of one run: the model and every value drawn for it.

    Attributes:
        model: the IMU model
        rate: the run's sample rate [Hz]
        slots: the record slots of the IMUs that exist, in the order of the exact signals
        tables: the drawn values by record name (``imu_error_*``, float64, empty slots zero)
        decimation_rng: the generator of the decimation filter's white noise (None: off)
    """

    model: ImuNoiseModel
    rate: float
    slots: tuple[int, ...]
    tables: dict[str, Array] = field(default_factory=dict)
    decimation_rng: np.random.Generator | None = None

    @property
    def noise_model(self) -> ImuNoiseModel:
        """The model the white noise, in-run bias and quantisation are then made with.

        With decimation the white noise comes filtered from :meth:`sensed` (its density is
        then 0 here, so the run's noise generator draws the numbers it always does).
        """
        if self.decimation_rng is None:
            return self.model
        model = self.model
        gyro = replace(model.gyro, noise_density=0.0)
        return replace(model, gyro=gyro, accel=replace(model.accel, noise_density=0.0))

    def _per_imu(self, name: str) -> Array | None:
        table = self.tables.get(f"imu_error_{name}")
        return None if table is None else table[list(self.slots)]

    def sensed(self, exact: Array, start: int = 0) -> Array:
        """The exact signals of samples ``start`` … as the IMUs sense them, before the noise.

        Args:
            exact: exact signals of the existing IMUs, (m, n_imu, 6) [rad/s, m/s²]; with a
                timing term the whole run (``start`` 0)
            start: the index of the first sample in the run

        Returns:
            A new (m, n_imu, 6) float64 array.
        """
        m = exact.shape[0]
        out = np.array(exact, dtype=np.float64)
        model = self.model
        if model.timing:
            taps = decimation_filter(model.decimation, model.decimation_order)
            offsets = self.tables.get("imu_error_time_offset")
            jitter = self.tables.get("imu_error_jitter")
            out = sampled_signals(
                out,
                self.rate,
                np.zeros(len(self.slots)) if offsets is None else offsets[list(self.slots)],
                None if jitter is None else jitter[:, list(self.slots)],
                taps,
                model.decimation,
            )
        truth = out.copy()
        matrix = self._per_imu("matrix")
        if matrix is not None:
            for s in range(2):
                block = truth[..., 3 * s : 3 * s + 3]
                out[..., 3 * s : 3 * s + 3] = np.einsum("iab,tib->tia", matrix[:, s], block)
        for name in ("nonlinearity", "bias_offset"):
            values = self._per_imu(name)
            if values is not None:
                out += values * truth**2 if name == "nonlinearity" else values
        sensitivity = self._per_imu("g_sensitivity")
        if sensitivity is not None:
            out[..., :3] += np.einsum("iab,tib->tia", sensitivity, truth[..., 3:])
        walk = self.tables.get("imu_error_bias_random_walk")
        if walk is not None:
            out += walk[start : start + m].reshape(m, -1, 6)[:, list(self.slots)]
        if self.decimation_rng is not None:
            density = np.repeat([model.gyro.noise_density, model.accel.noise_density], 3)
            shape = (out.shape[0], out.shape[1])
            out += filtered_white_noise(
                self.decimation_rng,
                shape,
                density,
                self.rate,
                model.decimation,
                model.decimation_order,
            )
        return out


def _term_rng(parent: np.random.SeedSequence, name: str) -> np.random.Generator:
    key = (*parent.spawn_key, TERMS.index(name))
    return np.random.default_rng(np.random.SeedSequence(parent.entropy, spawn_key=key))


def _sensor_values(sensors: tuple[SensorNoise, SensorNoise], name: str) -> Array:
    return np.array([getattr(s, name) for s in sensors], dtype=np.float64)


_SHAPES = {  # each table's shape for T samples and S slots (in draw order)
    "scale": lambda t, s: (s, 6),
    "cross_axis": lambda t, s: (s, 2, 3, 3),
    "misalignment": lambda t, s: (s, 2, 3, 3),
    "matrix": lambda t, s: (s, 2, 3, 3),
    "g_sensitivity": lambda t, s: (s, 3, 3),
    "nonlinearity": lambda t, s: (s, 6),
    "bias_offset": lambda t, s: (s, 6),
    "time_offset": lambda t, s: (s,),
    "jitter": lambda t, s: (t, s),
    "bias_random_walk": lambda t, s: (t, 6 * s),
}


def _tables_on(model: ImuNoiseModel) -> list[str]:
    """The tables (names without ``imu_error_``) a run of ``model`` draws, in draw order."""
    sensors = (model.gyro, model.accel)
    on = {
        "scale": any(s.scale_error for s in sensors),
        "cross_axis": any(s.cross_axis for s in sensors),
        "misalignment": any(s.misalignment or s.alignment is not None for s in sensors),
        "matrix": any(s.matrix_terms for s in sensors),
        "g_sensitivity": bool(model.gyro.g_sensitivity),
        "nonlinearity": any(s.nonlinearity for s in sensors),
        "bias_offset": any(s.bias_offset for s in sensors),
        "time_offset": bool(model.time_offset or model.time_offset_sigma),
        "jitter": bool(model.jitter),
        "bias_random_walk": any(s.bias_random_walk for s in sensors),
    }
    return [name for name in _SHAPES if on[name]]


def imu_error_shapes(
    model: ImuNoiseModel, samples: int, n_slots: int
) -> dict[str, tuple[int, ...]]:
    """The ``imu_error_*`` tables a run of ``model`` records and their shapes (a layout's).

    Args:
        model: the IMU model (with noise on; a run without noise records none)
        samples: T, the run's samples
        n_slots: S, the record's IMU slots

    Returns:
        ``{"imu_error_matrix": (S, 2, 3, 3), ...}``, in the record's order.
    """
    return {f"imu_error_{name}": _SHAPES[name](samples, n_slots) for name in _tables_on(model)}


def _matrices(
    parent: np.random.SeedSequence, model: ImuNoiseModel, on: list[str], n_slots: int
) -> dict[str, Array]:
    """The axis matrices' tables: scale, cross-axis, misalignment and their product."""
    sensors = (model.gyro, model.accel)
    tables: dict[str, Array] = {}
    scale = np.ones((n_slots, 2, 3))
    cross = np.broadcast_to(np.eye(3), (n_slots, 2, 3, 3)).copy()
    rotation = cross.copy()
    if "scale" in on:
        sigma = _sensor_values(sensors, "scale_error")[:, None]
        drawn = _term_rng(parent, "scale").standard_normal((n_slots, 2, 3)) * sigma
        scale += drawn
        tables["scale"] = drawn.reshape(n_slots, 6)
    if "cross_axis" in on:
        drawn = _term_rng(parent, "cross_axis").standard_normal((n_slots, 2, 6))
        rows, cols = np.nonzero(~np.eye(3, dtype=bool))
        cross[:, :, rows, cols] += drawn * _sensor_values(sensors, "cross_axis")[:, None]
        tables["cross_axis"] = cross
    if "misalignment" in on:
        sigma = _sensor_values(sensors, "misalignment")
        if sigma.any():
            theta = _term_rng(parent, "misalignment").standard_normal((n_slots, 2, 3))
            rotation = _rotation(theta * sigma[:, None])
        for s, sensor in enumerate(sensors):
            if sensor.alignment is not None:
                rotation[:, s] = rotation[:, s] @ np.asarray(sensor.alignment)
        tables["misalignment"] = rotation
    if "matrix" in on:
        tables["matrix"] = scale[..., :, None] * cross @ rotation
    return tables


def draw_imu_errors(
    model: ImuNoiseModel,
    sequence: np.random.SeedSequence,
    samples: int,
    rate: float,
    slots: tuple[int, ...],
    n_slots: int,
) -> ImuErrors | None:
    """The run's IMU errors, drawn from ``sequence`` (None when every term is off).

    Args:
        model: the IMU model
        sequence: the run's IMU sensor-error stream
            (:func:`~aaria_pin.core.seeds.sensor_sequence` part ``imu``)
        samples: T, the run's samples
        rate: the run's sample rate [Hz]
        slots: the record slots of the IMUs that exist
        n_slots: S, the record's IMU slots

    Returns:
        The errors, their tables named ``imu_error_*`` (module docstring,
        :func:`imu_error_shapes`).
    """
    if not model.new_terms or not slots:
        return None
    on = _tables_on(model)
    sensors = (model.gyro, model.accel)
    tables = _matrices(sequence, model, on, n_slots)
    per_axis = np.repeat
    if "g_sensitivity" in on:
        rng = _term_rng(sequence, "g_sensitivity")
        tables["g_sensitivity"] = rng.standard_normal((n_slots, 3, 3)) * model.gyro.g_sensitivity
    if "nonlinearity" in on:
        signs = _term_rng(sequence, "nonlinearity").choice([-1.0, 1.0], (n_slots, 6))
        nonlinearity = per_axis(_sensor_values(sensors, "nonlinearity"), 3)
        tables["nonlinearity"] = (
            signs * 1.5 * nonlinearity / per_axis(_sensor_values(sensors, "range"), 3)
        )
    if "bias_offset" in on:
        offset = per_axis(_sensor_values(sensors, "bias_offset"), 3)
        drawn = _term_rng(sequence, "bias_offset").standard_normal((n_slots, 6))
        tables["bias_offset"] = drawn * offset
    if "time_offset" in on:
        drawn = _term_rng(sequence, "time_offset").standard_normal(n_slots)
        tables["time_offset"] = model.time_offset + model.time_offset_sigma * drawn
    if "jitter" in on:
        rng = _term_rng(sequence, "jitter")
        tables["jitter"] = rng.standard_normal((samples, n_slots)) * model.jitter
    if "bias_random_walk" in on:
        walk = per_axis(_sensor_values(sensors, "bias_random_walk"), 3)
        steps = _term_rng(sequence, "bias_random_walk").standard_normal((samples, n_slots, 6))
        tables["bias_random_walk"] = np.cumsum(steps * (walk / np.sqrt(rate)), axis=0)
    empty = np.setdiff1d(np.arange(n_slots), slots)
    for name, table in tables.items():
        if name in ("jitter", "bias_random_walk"):
            table[:, empty] = 0.0
        else:
            table[empty] = 0.0
    if "bias_random_walk" in tables:  # stored T × (S·6), slot by slot, as a series table is
        tables["bias_random_walk"] = tables["bias_random_walk"].reshape(samples, 6 * n_slots)
    decimation = _term_rng(sequence, "decimation") if model.decimation > 1 else None
    return ImuErrors(
        model,
        rate,
        tuple(slots),
        {f"imu_error_{name}": np.ascontiguousarray(tables[name], np.float64) for name in on},
        decimation,
    )
