"""Noise model of an inertial measurement unit, after the Analog Devices ADIS16485.

:func:`add_imu_noise` turns exact IMU signals (angular velocity and specific force) into
measurements: white noise plus a slowly wandering bias, saturated to the sensor's range and
quantised to its resolution. :func:`allan_deviation` is the usual check of such noise, and
:func:`noise_attributes` flattens a model into numbers that can be stored next to a data set.

Noise convention: the noise density ``N`` is a one-sided spectral density, so white noise sampled
at ``rate`` Hz (bandwidth ``rate/2``) has a per-sample standard deviation ``N·√(rate/2)``, and its
Allan deviation at averaging time ``τ`` is ``N/√(2τ)``: the random walk coefficient is ``N/√2``.
For the ADIS16485 that gives 0.28 °/√h and 0.028 m/s/√h against the data sheet's 0.3 °/√h and
0.023 m/s/√h, so the two data-sheet figures agree under this convention.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = [
    "ADIS16485",
    "BIAS_KNOTS_PER_CORRELATION_TIME",
    "DATASHEET_ROWS",
    "SKIP_BLOCK",
    "STANDARD_GRAVITY",
    "ImuNoiseModel",
    "ImuNoiseStream",
    "SensorNoise",
    "add_imu_noise",
    "allan_deviation",
    "noise_attributes",
]

BIAS_KNOTS_PER_CORRELATION_TIME = 200
"""Knots of the bias process per correlation time (see :func:`add_imu_noise`)."""

SKIP_BLOCK = 2**20
"""Standard normals per block when :class:`ImuNoiseStream` skips a run's white noise (8 MiB)."""

STANDARD_GRAVITY = 9.80665
"""Standard gravity, the data sheet's g [m/s²]."""

_DEG = np.pi / 180.0


def _check(name: str, value: float, allow_zero: bool = False) -> None:
    ok = value >= 0.0 if allow_zero else value > 0.0
    if not (np.isfinite(value) and ok):
        bound = ">= 0" if allow_zero else "> 0"
        raise ParameterError(
            f"{name} is {value!r}; allowed: a finite number {bound}",
            parameter=name,
            value=value,
            allowed=f"a finite number {bound}",
        )


@dataclass(frozen=True)
class SensorNoise:
    """Noise parameters of one sensor type (gyroscope or accelerometer), per axis, SI units.

    The unit ``u`` is rad/s for a gyroscope and m/s² for an accelerometer.

    Attributes:
        range: full scale, the output saturates at ±range [u]
        lsb: quantisation step, one least significant bit [u]
        noise_density: white noise density [u/√Hz]
        bias_stability: in-run bias stability, the bias's standard deviation (1σ) [u]
        random_walk: angle [rad/√s] or velocity [m/s/√s] random walk as listed in the data sheet;
            kept for reference, the white noise is generated from ``noise_density``
    """

    range: float
    lsb: float
    noise_density: float
    bias_stability: float
    random_walk: float

    def __post_init__(self) -> None:
        for f in fields(self):
            _check(f.name, getattr(self, f.name), allow_zero=f.name not in ("range", "lsb"))


@dataclass(frozen=True)
class ImuNoiseModel:
    """Noise model of a six-axis IMU.

    Attributes:
        gyro: gyroscope noise [rad/s]
        accel: accelerometer noise [m/s²]
        bandwidth_hz: sensor bandwidth [Hz]; kept for reference, no filter is applied
        internal_rate_hz: internal sample rate [Hz]; kept for reference
        bias_correlation_time: correlation time of the Gauss–Markov bias [s]
    """

    gyro: SensorNoise
    accel: SensorNoise
    bandwidth_hz: float = 330.0
    internal_rate_hz: float = 2460.0
    bias_correlation_time: float = 100.0

    def __post_init__(self) -> None:
        for name in ("bandwidth_hz", "internal_rate_hz", "bias_correlation_time"):
            _check(name, getattr(self, name))


DATASHEET_ROWS: tuple[tuple[str, float, str], ...] = (
    ("gyro range", 450.0, "+/- deg/s"),
    ("gyro resolution", 0.02, "deg/s per LSB"),
    ("gyro rate noise density", 0.0066, "deg/s/sqrt(Hz)"),
    ("gyro in-run bias stability", 6.25, "deg/h (1 sigma)"),
    ("gyro angle random walk", 0.3, "deg/sqrt(h)"),
    ("accel range", 5.0, "+/- g"),
    ("accel resolution", 0.25, "mg per LSB"),
    ("accel noise density", 0.067, "mg/sqrt(Hz)"),
    ("accel in-run bias stability", 32.0, "ug (1 sigma)"),
    ("accel velocity random walk", 0.023, "m/s/sqrt(h)"),
    ("bandwidth", 330.0, "Hz"),
    ("internal sample rate", 2460.0, "SPS"),
)
"""ADIS16485 data-sheet values in their original units: (name, value, unit) rows."""

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
"""The ADIS16485 of the data sheet (:data:`DATASHEET_ROWS`), in SI units."""


def _check_rate(rate: float) -> None:
    if not (np.isfinite(rate) and rate > 0.0):
        raise ParameterError(
            f"sample rate is {rate!r} Hz; allowed: a finite rate > 0",
            parameter="rate",
            value=rate,
            allowed="a finite rate > 0 Hz",
        )


def _per_axis(model: ImuNoiseModel, name: str) -> Array:
    """One parameter of the model for the six axes ``[wx wy wz fx fy fz]``."""
    return np.repeat([getattr(model.gyro, name), getattr(model.accel, name)], 3)


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
        bias = self._rng.standard_normal((count, self._n_imu, 6)).reshape(count, -1)
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
    _check_rate(rate)
    exact = _checked_signals(signals)
    n, n_imu = exact.shape[:2]
    measured = rng.standard_normal(exact.shape).reshape(n, -1)
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
    :data:`SKIP_BLOCK` numbers. Skipping costs one more white-noise draw of the run (about
    1.5 s for 2 million samples of 14 IMUs, against about 4 s for the run itself) and keeps the
    seed's numbers those of every earlier version. The knots are then drawn as the pieces need
    them, keeping only the recursion's last knot and those the current piece spans: a run
    whose every sample is a knot (below ``200/T`` Hz, e.g. a day at 3.9 Hz: 336,962 knots of
    14 IMUs, 226 MB) no longer holds them all.

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

        _check_rate(rate)
        if samples < 1 or n_imu < 1:
            raise ParameterError(
                f"noise stream of {samples} samples and {n_imu} IMUs; allowed: both >= 1",
                parameter="samples",
            )
        self.samples, self.n_imu, self.rate, self.model = samples, n_imu, rate, model
        self._rng = rng
        ahead = copy.deepcopy(rng)
        remaining = samples * n_imu * 6
        block = np.empty(min(remaining, SKIP_BLOCK))
        while remaining > 0:
            part = block[: min(remaining, SKIP_BLOCK)]
            ahead.standard_normal(out=part)
            remaining -= part.size
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
        measured = self._rng.standard_normal(exact.shape).reshape(n, -1)
        bias, first = self._bias_window(start, start + n)
        # The piece's sample i = k·step + r is sample i - first·step of the window: the same
        # knot offset k - first and the same r, so the same numbers.
        _measure(measured, exact, bias, start - first * self._knots.step, self.rate, self.model)
        self._next = start + n
        return measured.reshape(exact.shape)


def noise_attributes(model: ImuNoiseModel = ADIS16485) -> dict[str, float]:
    """The model's parameters as a flat dictionary, SI units in the keys (for HDF5 attributes).

    Args:
        model: noise model

    Returns:
        ``{"gyro_range_rad_s": ..., "accel_noise_density_m_s2_sqrtHz": ..., ...}``.
    """
    units = {"gyro": ("rad_s", "rad_sqrts"), "accel": ("m_s2", "m_s_sqrts")}
    attributes: dict[str, float] = {}
    for sensor, (u, walk) in units.items():
        noise: SensorNoise = getattr(model, sensor)
        for name, unit in (
            ("range", u),
            ("lsb", u),
            ("noise_density", f"{u}_sqrtHz"),
            ("bias_stability", u),
            ("random_walk", walk),
        ):
            attributes[f"{sensor}_{name}_{unit}"] = float(getattr(noise, name))
    attributes["bandwidth_hz"] = float(model.bandwidth_hz)
    attributes["internal_rate_hz"] = float(model.internal_rate_hz)
    attributes["bias_correlation_time_s"] = float(model.bias_correlation_time)
    return attributes


def allan_deviation(x: Array, rate: float, taus: Array) -> Array:
    """Overlapping Allan deviation of a rate signal.

    With ``θ`` the cumulative integral of ``x`` (``θ_0 = 0``, N + 1 values) and ``m = τ·rate``
    samples per cluster, ``σ²(τ) = Σ_k (θ_{k+2m} - 2θ_{k+m} + θ_k)² / (2τ²(N + 1 - 2m))``.

    Args:
        x: 1-D rate signal (N samples) [u]
        rate: sample rate [Hz]
        taus: averaging times [s], each rounded to a whole number m >= 1 of samples with
            2m <= N; the value returned is for ``m/rate``

    Returns:
        Allan deviation at each averaging time [u], shape of ``taus``.

    Raises:
        ParameterError: the rate, the signal or an averaging time is out of range.
    """
    _check_rate(rate)
    signal = np.asarray(x, dtype=np.float64)
    if signal.ndim != 1 or not np.all(np.isfinite(signal)):
        raise ParameterError(
            f"Allan deviation signal has shape {signal.shape}; allowed: a finite 1-D array",
            parameter="x",
        )
    n = signal.size
    theta = np.concatenate(([0.0], np.cumsum(signal) / rate))
    tau_array = np.asarray(taus, dtype=np.float64)
    out = np.empty(tau_array.shape)
    for index, tau in np.ndenumerate(tau_array):
        m = int(np.rint(tau * rate)) if np.isfinite(tau) else 0
        if m < 1 or 2 * m > n:
            raise ParameterError(
                f"averaging time {tau!r} s is {m} samples; allowed: 1 to {n // 2} samples "
                f"({1.0 / rate:g} to {(n // 2) / rate:g} s)",
                parameter="taus",
            )
        d = theta[2 * m :] - 2.0 * theta[m:-m] + theta[: -2 * m]
        out[index] = np.sqrt(np.mean(d * d) / 2.0) * rate / m
    return out
