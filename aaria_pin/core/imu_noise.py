"""Noise of an inertial measurement unit: white noise, in-run bias, saturation, quantisation.

:func:`add_imu_noise` turns exact IMU signals (angular velocity and specific force) into
measurements: white noise plus a slowly wandering bias, saturated to the sensor's range and
quantised to its resolution. :func:`noise_attributes` flattens a model into numbers that can be
stored next to a data set. The model's parameters are :mod:`~aaria_pin.core.imu_model`'s, the
parts :mod:`~aaria_pin.core.imu_presets`' (the ADIS16485 by default); the terms drawn once per
run (scale, axes, turn-on bias, time offset, …) are applied before this noise by
:mod:`~aaria_pin.core.imu_errors`. :func:`~aaria_pin.core.allan.allan_deviation` (re-exported
here) is the usual check of the noise.

Noise convention: the noise density ``N`` is a one-sided spectral density, so white noise sampled
at ``rate`` Hz (bandwidth ``rate/2``) has a per-sample standard deviation ``N·√(rate/2)``, and its
Allan deviation at averaging time ``τ`` is ``N/√(2τ)``: the random walk coefficient is ``N/√2``.
For the ADIS16485 that gives 0.28 °/√h and 0.028 m/s/√h against the data sheet's 0.3 °/√h and
0.023 m/s/√h, so the two data-sheet figures agree under this convention.
"""

from __future__ import annotations

from dataclasses import fields
from typing import Any

import numpy as np

from aaria_pin.core.allan import allan_deviation, check_rate
from aaria_pin.core.imu_model import STANDARD_GRAVITY, ImuNoiseModel, SensorNoise
from aaria_pin.core.imu_presets import ADIS16485, DATASHEET_ROWS
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = [
    "ADIS16485",
    "BIAS_KNOTS_PER_CORRELATION_TIME",
    "DATASHEET_ROWS",
    "MODEL_ATTRIBUTE_KEYS",
    "SKIP_BLOCK",
    "STANDARD_GRAVITY",
    "ImuNoiseModel",
    "ImuNoiseStream",
    "SensorNoise",
    "add_imu_noise",
    "allan_deviation",
    "attribute_key",
    "noise_attributes",
]

BIAS_KNOTS_PER_CORRELATION_TIME = 200
"""Knots of the bias process per correlation time (see :func:`add_imu_noise`)."""

SKIP_BLOCK = 2**20
"""Standard normals per block when :class:`ImuNoiseStream` skips a run's white noise (8 MiB)."""


def _per_axis(model: ImuNoiseModel, name: str) -> Array:
    """One parameter of the model for the six axes ``[wx wy wz fx fy fz]``."""
    return np.repeat([getattr(model.gyro, name), getattr(model.accel, name)], 3)


def _normals(rng: np.random.Generator, shape: int | tuple[int, ...]) -> Array:
    """``rng.standard_normal(shape)``, bit for bit, through a compiled ziggurat.

    :func:`aaria_pin.core._normal_kernel.standard_normal` (numba imported on first use): 1.7 ms
    instead of 7 ms for the 840,000 white-noise numbers of 10,000 samples of 14 IMUs.
    """
    from aaria_pin.core._normal_kernel import standard_normal as compiled

    return compiled(rng, shape)


def _checked_signals(signals: Array) -> Array:
    """Exact IMU signals as a finite float64 (T, n_imu, 6) array (T, n_imu >= 1)."""
    try:
        exact = np.asarray(signals, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError(
            f"IMU signals of type {type(signals).__name__} are not numeric; allowed: a real array",
            parameter="signals",
        ) from None
    if exact.ndim != 3 or exact.shape[2] != 6 or 0 in exact.shape:
        raise ParameterError(
            f"IMU signals have shape {exact.shape}; allowed: (T, n_imu, 6) with T, n_imu >= 1",
            parameter="signals",
        )
    if not np.all(np.isfinite(exact)):
        index = tuple(int(i) for i in np.argwhere(~np.isfinite(exact))[0])
        raise ParameterError(
            f"IMU signal at index {index} is {exact[index]!r}; allowed: finite values",
            parameter="signals",
        )
    return exact


def _bias_step(rate: float, model: ImuNoiseModel) -> int:
    """Samples between two knots of the bias process (see :func:`add_imu_noise`)."""
    return max(1, int(rate * model.bias_correlation_time / BIAS_KNOTS_PER_CORRELATION_TIME))


class _BiasKnots:
    """The knots of a run's bias drawn in time order, a few at a time (constant memory).

    The Gauss–Markov recursion ``b[k] = w[k] + φ·b[k-1]`` runs knot by knot (one row of
    n_imu·6 values per step: 22 steps for 10 s at 100 Hz, at most one per sample below
    ``200/T`` Hz); it gives the numbers of ``scipy.signal.lfilter([1], [1, -φ])``, bit for bit,
    without importing scipy.signal (0.1 s of a short run's start-up). Only the last knot's
    value is kept between draws (the recursion's state), so the knots of a run drawn in any
    number of draws are, element for element, those drawn in one: the standard normals come
    from ``rng`` in the same order and every operation is per element, in the same order.

    Args:
        rng: random number generator, positioned where the run's knots begin
        n_imu: the number of IMUs
        rate: sample rate [Hz]
        model: noise model
    """

    def __init__(
        self, rng: np.random.Generator, n_imu: int, rate: float, model: ImuNoiseModel
    ) -> None:
        self.step = _bias_step(rate, model)
        dt_over_T = self.step / (rate * model.bias_correlation_time)
        self._rng = rng
        self._n_imu = n_imu
        self._phi = float(np.exp(-dt_over_T))
        self._innovation = np.sqrt(-np.expm1(-2.0 * dt_over_T))  # √(1 - φ²): variance 1
        self._stability = np.tile(_per_axis(model, "bias_stability"), n_imu)
        self._drawn = 0
        self._last: Array | None = None  # the last knot drawn, before the stability scale

    def draw(self, count: int) -> Array:
        """The next ``count`` knots of the bias, (count, n_imu·6) [rad/s, m/s²]."""
        bias = _normals(self._rng, (count, self._n_imu, 6)).reshape(count, -1)
        first = 1 if self._drawn == 0 else 0  # knot 0: the stationary draw itself
        bias[first:] *= self._innovation
        if first == 0 and count and self._last is not None:
            bias[0] += self._phi * self._last
        for k in range(1, count):
            bias[k] += self._phi * bias[k - 1]
        if count:
            self._last = bias[-1].copy()
        self._drawn += count
        bias *= self._stability
        return bias


def _knot_count(samples: int, step: int) -> int:
    """Knots of the bias of a run of ``samples``: the last sample lies before the last knot."""
    return (samples - 1) // step + 2


def _bias_knots(
    rng: np.random.Generator, samples: int, n_imu: int, rate: float, model: ImuNoiseModel
) -> Array:
    """The bias on its knots for a run of ``samples``, (knots, n_imu·6) [rad/s, m/s²]."""
    knots = _BiasKnots(rng, n_imu, rate, model)
    return knots.draw(_knot_count(samples, knots.step))


def _measure(
    measured: Array,
    exact: Array,
    bias: Array,
    start: int,
    rate: float,
    model: ImuNoiseModel,
) -> None:
    """Standard normals to measurements of samples ``start`` … in place, (m, n_imu·6).

    ``measured`` holds the white noise's standard normals on entry. Every operation is per
    element (the bias between two knots is ``b[k] + (b[k+1] - b[k])·r/step`` for sample
    ``k·step + r``), so a run measured in pieces is bit for bit the run measured whole. One
    compiled pass (``_kinematics_kernel.measure_noise``) does it: 0.9 ms against 4.3 ms for
    the array code it replaced (10,000 samples of 14 IMUs), whose operations it repeats in
    order (the tests hold it equal to that array code, ``tests/core/test_trajectory_kernels.py``).
    """
    from aaria_pin.core._kinematics_kernel import measure_noise

    n, columns = measured.shape
    n_imu = columns // 6
    measure_noise(
        measured,
        np.ascontiguousarray(exact, dtype=np.float64).reshape(n, -1),
        np.ascontiguousarray(bias),
        np.ascontiguousarray(bias[1:] - bias[:-1]),
        start,
        _bias_step(rate, model),
        np.tile(_per_axis(model, "noise_density"), n_imu) * np.sqrt(rate / 2.0),
        np.tile(_per_axis(model, "range"), n_imu),
        np.tile(_per_axis(model, "lsb"), n_imu),
    )


def add_imu_noise(
    signals: Array, rate: float, rng: np.random.Generator, model: ImuNoiseModel = ADIS16485
) -> Array:
    """Exact IMU signals to measurements: white noise, bias, saturation and quantisation.

    Per axis, ``measured = quantise(clip(exact + white + bias, ±range))``:

    * white noise: i.i.d. Gaussian, standard deviation ``noise_density·√(rate/2)``, so that
      the Allan deviation at averaging time ``τ`` is ``noise_density/√(2τ)``;
    * bias: first-order Gauss–Markov process ``b[k+1] = φ·b[k] + w[k]`` with
      ``T = model.bias_correlation_time``, ``w ~ N(0, σ²(1-φ²))``, ``σ = bias_stability``,
      starting from its stationary distribution ``N(0, σ²)``, so it is stationary with standard
      deviation ``σ`` and autocorrelation ``exp(-|Δt|/T)``; each IMU and axis has its own bias.
      It is drawn on knots ``step = max(1, ⌊rate·T/200⌋)`` samples apart,
      ``φ = exp(-step/(rate·T))``,
      and interpolated linearly between them: a bias that wanders over 100 s needs no fresh
      random number every millisecond, and at rates up to ``200/T`` Hz every sample is a knot;
    * saturation to ``±range``, then rounding to the nearest multiple of ``lsb``.

    Random numbers are drawn from ``rng`` in a fixed order (white noise as one ``(T, n_imu, 6)``
    standard-normal array, then the bias knots), so the same seed gives the same measurements.
    :class:`ImuNoiseStream` gives the same measurements a piece of the run at a time.

    Args:
        signals: exact signals, shape (T, n_imu, 6), rows ``[wx wy wz fx fy fz]``: angular
            velocity [rad/s] then specific force [m/s²]
        rate: sample rate [Hz]
        rng: random number generator
        model: noise model

    Returns:
        Measurements, a new float64 array of the same shape; ``signals`` is not modified.

    Raises:
        ParameterError: the rate is not finite and > 0, or the signals are not a finite
            (T, n_imu, 6) array with T, n_imu >= 1.
    """
    check_rate(rate)
    exact = _checked_signals(signals)
    n, n_imu = exact.shape[:2]
    measured = _normals(rng, exact.shape).reshape(n, -1)
    bias = _bias_knots(rng, n, n_imu, rate, model)
    _measure(measured, exact, bias, 0, rate, model)
    return measured.reshape(exact.shape)


class ImuNoiseStream:
    """The measurements of :func:`add_imu_noise` for a long run, one piece of time at a time.

    The pieces, given in time order, get bit for bit the numbers :func:`add_imu_noise` gives
    the whole run with the same generator: the white noise is drawn from ``rng`` piece by piece
    (a ``Generator`` drawing ``standard_normal(n1)`` then ``standard_normal(n2)`` gives the
    numbers of ``standard_normal(n1 + n2)``, checked by the tests), and the bias knots, which
    :func:`add_imu_noise` draws *after* the whole run's white noise, come from a copy of
    ``rng`` that first draws (and drops) the whole run's white noise in blocks of at most
    :data:`SKIP_BLOCK` numbers. Skipping costs one more white-noise draw of the run (0.5 s
    for 2 million samples of 14 IMUs through the compiled draw, 0.8 s through numpy's, measured
    on one core) and keeps the seed's numbers those of every earlier version. The knots are
    then drawn as the pieces need them, keeping only the recursion's last knot and those the
    current piece spans: a run whose every sample is a knot (below ``200/T`` Hz, e.g. a day at
    3.9 Hz: 336,962 knots of 14 IMUs, 226 MB) no longer holds them all.

    Args:
        samples: T, the run's number of samples
        n_imu: the number of IMUs
        rate: sample rate [Hz]
        rng: random number generator (drawn from as the pieces come)
        model: noise model

    Raises:
        ParameterError: the rate is not finite and > 0, or ``samples`` or ``n_imu`` < 1.
    """

    def __init__(
        self,
        samples: int,
        n_imu: int,
        rate: float,
        rng: np.random.Generator,
        model: ImuNoiseModel = ADIS16485,
    ) -> None:
        import copy

        check_rate(rate)
        if samples < 1 or n_imu < 1:
            raise ParameterError(
                f"noise stream of {samples} samples and {n_imu} IMUs; allowed: both >= 1",
                parameter="samples",
            )
        self.samples, self.n_imu, self.rate, self.model = samples, n_imu, rate, model
        self._rng = rng
        ahead = copy.deepcopy(rng)
        remaining = samples * n_imu * 6
        while remaining > 0:
            remaining -= _normals(ahead, min(remaining, SKIP_BLOCK)).size
        self._knots = _BiasKnots(ahead, n_imu, rate, model)
        self._window = np.empty((0, n_imu * 6))  # knots from index self._window_first on
        self._window_first = 0
        self._next = 0

    def _bias_window(self, start: int, stop: int) -> tuple[Array, int]:
        """The knots samples ``start`` … ``stop - 1`` lie between, and the first one's index."""
        step = self._knots.step
        first, last = start // step, (stop - 1) // step + 1
        held = self._window[first - self._window_first :]
        missing = last + 1 - (first + held.shape[0])
        if missing > 0:
            held = np.concatenate([held, self._knots.draw(missing)])
        self._window, self._window_first = held, first
        return held[: last + 1 - first], first

    def measure(self, signals: Array, start: int) -> Array:
        """Measurements of the exact signals of samples ``start`` … ``start + m - 1``.

        Args:
            signals: exact signals of the piece, (m, n_imu, 6) [rad/s, m/s²]
            start: index of its first sample; pieces come in order, without gaps

        Returns:
            Measurements, a new float64 (m, n_imu, 6) array.

        Raises:
            ParameterError: a piece out of order, past the run's end, or not finite
                (m, n_imu, 6) signals.
        """
        exact = _checked_signals(signals)
        n = exact.shape[0]
        if start != self._next or exact.shape[1] != self.n_imu or start + n > self.samples:
            raise ParameterError(
                f"noise piece of {n} samples × {exact.shape[1]} IMUs at sample {start}; "
                f"allowed: {self.n_imu} IMUs, starting at sample {self._next}, ending by "
                f"sample {self.samples}",
                parameter="start",
            )
        measured = _normals(self._rng, exact.shape).reshape(n, -1)
        bias, first = self._bias_window(start, start + n)
        # The piece's sample i = k·step + r is sample i - first·step of the window: the same
        # knot offset k - first and the same r, so the same numbers.
        _measure(measured, exact, bias, start - first * self._knots.step, self.rate, self.model)
        self._next = start + n
        return measured.reshape(exact.shape)


_UNITS = {"gyro": "rad_s", "accel": "m_s2"}
_WALK_UNITS = {"gyro": "rad_sqrts", "accel": "m_s_sqrts"}


def attribute_key(sensor: str, name: str) -> str:
    """The attribute key of field ``name`` of sensor ``sensor`` (``gyro``/``accel``), unit in it.

    E.g. ``gyro_noise_density_rad_s_sqrtHz``, ``accel_bias_random_walk_m_s2_sqrts``.
    """
    u = _UNITS[sensor]
    unit = {
        "range": u,
        "lsb": u,
        "noise_density": f"{u}_sqrtHz",
        "bias_stability": u,
        "random_walk": _WALK_UNITS[sensor],
        "scale_error": "frac",
        "nonlinearity": "frac_fs",
        "cross_axis": "frac",
        "misalignment": "rad",
        "alignment": "matrix",
        "g_sensitivity": "rad_s_per_m_s2",
        "bias_offset": u,
        "bias_random_walk": f"{u}_sqrts",
    }[name]
    return f"{sensor}_{name}_{unit}"


MODEL_ATTRIBUTE_KEYS = {
    "bandwidth_hz": "bandwidth_hz",
    "internal_rate_hz": "internal_rate_hz",
    "bias_correlation_time": "bias_correlation_time_s",
    "time_offset": "time_offset_s",
    "time_offset_sigma": "time_offset_sigma_s",
    "jitter": "jitter_s",
    "decimation": "decimation",
    "decimation_order": "decimation_order",
}
"""The attribute key of each per-IMU field of :class:`ImuNoiseModel` (unit in the key)."""


_OLD_FIELDS = ("range", "lsb", "noise_density", "bias_stability", "random_walk")
_OLD_MODEL_FIELDS = ("bandwidth_hz", "internal_rate_hz", "bias_correlation_time")
_OFF_VALUES = {"decimation": 1, "decimation_order": 1}  # the off value of a 0.4 field, if not 0


def noise_attributes(model: ImuNoiseModel = ADIS16485, every: bool = False) -> dict[str, Any]:
    """The model's parameters as a flat dictionary, SI units in the keys (for HDF5 attributes).

    The 13 fields of 0.3 are always recorded; a field added in 0.4 is recorded when it is not
    its off value (0; 1 for ``decimation`` and ``decimation_order``; None for ``alignment``,
    recorded as its nine numbers row by row), so a run whose new terms are all off records
    exactly what it did in 0.3, and a key left out reads back as off
    (:func:`~aaria_pin.core.imu_attributes.noise_model_from_attributes`). Keys:
    :func:`attribute_key`, :data:`MODEL_ATTRIBUTE_KEYS`.

    Args:
        model: noise model
        every: record the fields that are off too (the data card lists every term)

    Returns:
        ``{"gyro_range_rad_s": ..., "accel_noise_density_m_s2_sqrtHz": ..., ...}``.
    """
    attributes: dict[str, Any] = {}
    for sensor in ("gyro", "accel"):
        noise: SensorNoise = getattr(model, sensor)
        for f in fields(noise):
            value = getattr(noise, f.name)
            if f.name not in _OLD_FIELDS and not value and not (every and value is not None):
                continue
            if f.name == "alignment":
                value = [float(v) for row in value for v in row]
            attributes[attribute_key(sensor, f.name)] = (
                value if f.name == "alignment" else float(value)
            )
    for name, key in MODEL_ATTRIBUTE_KEYS.items():
        value = getattr(model, name)
        if every or name in _OLD_MODEL_FIELDS or value != _OFF_VALUES.get(name, 0):
            attributes[key] = float(value)
    return attributes
