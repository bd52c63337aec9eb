"""The measured signals the kinematic fit takes: spline derivatives, smoothing, noise weights.

Joint velocities and accelerations are the derivatives of a quintic spline through the encoder
values; on noisy records the base IMU's angular velocity, an input of the model, is
differentiated by a filter without bias (:func:`noisy_derivative`); each signal is weighted by
1 / its noise level (:func:`signal_weights`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from aaria_pin.core.imu_noise import ADIS16485
from aaria_pin.core.se3 import Array

__all__ = [
    "clipped_samples",
    "derivatives",
    "noisy_derivative",
    "rounding_level",
    "sample_derivatives",
    "signal_weights",
    "uniform_time",
]

_DERIVATIVE_WINDOWS = (0.25, 0.5, 1.0, 1.5, 2.0, 3.0)  # [s] the base rates' derivative filters


_AGREE = 2.0  # a longer window agrees when within this many of the shorter one's noise σ


_ROUNDED_SIZES = (7, 11, 15, 21, 31, 41, 61, 81)  # [samples] quintic windows on float32 values


def uniform_time(time: Array) -> Array:
    """The sample times rebuilt from the first, the last and the sample index, when they fit.

    A data set stores its time in float32 by default: at t = 30 s the stored times are rounded
    to 1.9e-6 s, 4e-4 of a 5 ms step, and a spline's second derivative through the joint values
    at those times carries that jitter (measured on random arm 11, 30 s at 200 Hz: joint
    acceleration error RMS 0.061 rad/s², against 1.9e-10 on the float64 times). When every
    stored time is within 4 float32 roundings of the even grid from the first to the last, the
    grid is the time axis; any other time axis (a recording with its own jitter) is kept.
    """
    if time.size < 3:
        return time
    grid = np.linspace(time[0], time[-1], time.size)
    tolerance = 4.0 * float(np.spacing(np.float32(np.max(np.abs(time)))))
    return grid if float(np.max(np.abs(grid - time))) <= tolerance else time


def rounding_level(values: Array) -> Array | None:
    """Per column, the standard deviation of float32 storage rounding; None if not float32.

    Values that float32 holds exactly were stored in float32: their rounding is uniform over
    one float32 spacing at the column's largest magnitude, ``spacing / √12`` (at most).
    """
    if not np.array_equal(values, values.astype(np.float32)):
        return None
    largest = np.maximum(np.max(np.abs(values), axis=0), 1e-30).astype(np.float32)
    return np.spacing(largest).astype(float) / np.sqrt(12.0)


def sample_derivatives(time: Array, values: Array, order: int) -> list[Array]:
    """The first ``order`` derivatives of noise-free sampled values, storage rounding smoothed.

    Values stored exactly (float64) go through a quintic interpolating spline
    (:func:`derivatives`). Float32 values carry a rounding noise of ~1e-7 relative, and an
    interpolating spline's second derivative multiplies it by ~1/step²: on random arm 11 (30 s
    at 200 Hz, even time grid) joint accelerations 1.3e-3 rad/s² off. They go through quintic
    Savitzky–Golay filters instead, per column the longest window of
    :data:`_ROUNDED_SIZES` that agrees with every shorter one (:func:`_lepski`, the rounding
    level as the noise): 5e-6 rad/s² on that arm.
    """
    level = rounding_level(values)
    if level is None or values.shape[0] <= _ROUNDED_SIZES[0]:
        return derivatives(time, values, order)
    step = float(np.median(np.diff(time)))
    longest = values.shape[0] if values.shape[0] % 2 else values.shape[0] - 1
    sizes = sorted({min(n, longest) for n in _ROUNDED_SIZES})
    return [_lepski(values, sizes, 5, k, step, level) for k in range(1, order + 1)]


def _lepski(
    values: Array, sizes: list[int], polyorder: int, deriv: int, step: float, level: Array | float
) -> Array:
    """Per column, the longest Savitzky–Golay window agreeing with every shorter one.

    Args:
        values: T × C samples
        sizes: window lengths [samples], odd, increasing
        polyorder: the filters' polynomial order
        deriv: the derivative order (0: smoothed values)
        step: the sample spacing [s]
        level: the white noise's per-sample standard deviation, one or per column [units of
            values]
    """
    from scipy.signal import savgol_coeffs, savgol_filter

    estimates = [
        np.asarray(savgol_filter(values, n, polyorder, deriv=deriv, delta=step, axis=0))
        for n in sizes
    ]
    gains = [
        float(np.linalg.norm(savgol_coeffs(n, polyorder, deriv=deriv, delta=step))) for n in sizes
    ]
    levels = np.broadcast_to(np.asarray(level, dtype=float), (values.shape[1],))
    out = np.empty_like(values, dtype=float)
    for column in range(values.shape[1]):
        noise = [gain * float(levels[column]) for gain in gains]
        chosen = 0
        for k in range(1, len(sizes)):
            agree = all(
                np.sqrt(np.mean((estimates[k][:, column] - estimates[j][:, column]) ** 2))
                <= _AGREE * noise[j]
                for j in range(k)
            )
            if not agree:
                break
            chosen = k
        out[:, column] = estimates[chosen][:, column]
    return out


def derivatives(time: Array, values: Array, order: int) -> list[Array]:
    """The first ``order`` derivatives of sampled values by a quintic interpolating spline."""
    from scipy.interpolate import make_interp_spline

    spline = make_interp_spline(time, values, k=5 if time.size > 5 else time.size - 1, axis=0)
    return [spline.derivative(k)(time) for k in range(1, order + 1)]


def noisy_derivative(time: Array, values: Array, level: float) -> Array:
    """The time derivative of noisy samples, per column the window that errs least.

    The base IMU's angular velocity is an input of the model; the error of its derivative
    enters every prediction over the whole run. Its two parts act differently: a filter's
    bias (bending the motion) moves the lengths in proportion to ``bias / signal``, its noise
    shrinks them in proportion to ``(noise / signal)²`` (errors in the regressor: the
    attenuation of least squares). Per column, quintic Savitzky–Golay filters over the windows
    :data:`_DERIVATIVE_WINDOWS` are compared: a window's noise is known (its coefficients times
    ``level``), its bias is what its estimate differs from the shortest's beyond their
    difference's noise (averaged over the run); the window of the smallest
    ``bias/signal + (noise/signal)²`` is taken. The first version smoothed the base's signals
    with the longest cubic window (up to 4 s) agreeing with the shorter ones within the
    noise: on random arm 0 of ``aaria dataset --seed 41`` with the noise taken off the IMUs but
    the noisy path kept, the tool tip ended 35 mm off (a bias), and with a fixed 1 s quintic
    window and ADIS16485 noise on the base gyroscope only, 23 mm (the attenuation; 2 s: 1 mm).

    Args:
        time: sample times [s], evenly spaced
        values: T × C samples
        level: the white noise's per-sample standard deviation [units of values]

    Returns:
        T × C derivatives [units per second].
    """
    from scipy.signal import savgol_coeffs, savgol_filter

    step = float(np.median(np.diff(time)))
    samples = values.shape[0]
    sizes = sorted(
        {2 * round(w / step / 2) + 1 for w in _DERIVATIVE_WINDOWS} & set(range(7, samples + 1, 2))
    )
    if not sizes:
        (derivative,) = derivatives(time, values, 1)
        return derivative
    estimates = [
        np.asarray(savgol_filter(values, n, 5, deriv=1, delta=step, axis=0)) for n in sizes
    ]
    coefficients = [savgol_coeffs(n, 5, deriv=1, delta=step, use="dot") for n in sizes]
    out = np.empty_like(values, dtype=float)
    for column in range(values.shape[1]):
        noise = [float(np.linalg.norm(c)) * level for c in coefficients]
        signal = np.sqrt(max(float(np.mean(estimates[0][:, column] ** 2)) - noise[0] ** 2, 1e-300))
        biases, scores = [0.0], [(noise[0] / signal) ** 2]
        for k in range(1, len(sizes)):
            # the bias grows as the window's sixth power: each window's is the shorter one's
            # plus what the two differ by beyond the noise of their difference (less two
            # standard errors of that noise's mean square over the run)
            pad = (sizes[k] - sizes[k - 1]) // 2
            spread = float(np.linalg.norm(coefficients[k] - np.pad(coefficients[k - 1], pad)))
            expected = (spread * level) ** 2 * (1.0 + 2.0 * np.sqrt(2.0 * sizes[k] / samples))
            excess = float(np.mean((estimates[k][:, column] - estimates[k - 1][:, column]) ** 2))
            biases.append(biases[-1] + np.sqrt(max(excess - expected, 0.0)))
            scores.append(biases[-1] / signal + (noise[k] / signal) ** 2)
        out[:, column] = estimates[int(np.argmin(scores))][:, column]
    return out


def signal_weights(rate: float, noise_parameters: Any = None) -> Array:
    """1 / each signal's per-sample noise level at the record's rate (gyroscope, accelerometer).

    The level is the white noise's ``density·√(rate/2)`` and the quantisation's ``lsb/√12``
    added in quadrature, from the record's ``noise_parameters`` (the noise it was simulated
    with) or else ADIS16485's: on noise-free records only the ratio of the two matters. (The
    first version converted the gyroscope's density, already in rad/s/√Hz, from degrees again:
    the gyroscopes weighed 57 times too much, the accelerometers that carry the lengths too
    little; with ADIS16485 noise 10 of 20 random arms were within 1 cm.)
    """
    parameters = noise_parameters if isinstance(noise_parameters, dict) else {}
    levels = []
    for sensor, units, model in (
        ("gyro", "rad_s", ADIS16485.gyro),
        ("accel", "m_s2", ADIS16485.accel),
    ):
        density = float(
            parameters.get(f"{sensor}_noise_density_{units}_sqrtHz", model.noise_density)
        )
        lsb = float(parameters.get(f"{sensor}_lsb_{units}", model.lsb))
        level = np.hypot(density * np.sqrt(rate / 2.0), lsb / np.sqrt(12.0))
        levels += [1.0 / level] * 3
    return np.array(levels)


FLAT_TOP = 3
"""Samples in a row at a channel's extreme that make a flat top (a clipped channel)."""


def flat_tops(signals: Array) -> Array:
    """The samples at which some channel holds its extreme for :data:`FLAT_TOP` samples or more.

    Args:
        signals: T × ... channels (each column's own largest and smallest value)
    """
    flat = signals.reshape(signals.shape[0], -1)
    out = np.zeros(flat.shape[0], dtype=bool)
    if flat.shape[0] < FLAT_TOP:
        return out
    varies = flat.max(axis=0) > flat.min(axis=0)  # a constant channel (a still axis): not clipped
    for extreme in (flat.max(axis=0), flat.min(axis=0)):
        at = (flat == extreme) & varies & (extreme != 0.0)  # (zero: a channel at rest)
        # a run of FLAT_TOP samples at the extreme: every window of that length all True
        windows = np.lib.stride_tricks.sliding_window_view(at, FLAT_TOP, axis=0)
        starts = np.asarray(windows.all(axis=-1), dtype=bool)
        for shift in range(FLAT_TOP):
            out[shift : shift + starts.shape[0]] |= starts.any(axis=1)
    return out


def clipped_samples(imu: Array, noise_parameters: Any) -> Array:
    """The samples at which some IMU channel is at its range (clipped), a boolean per sample.

    A clipped signal is not the model's: on run 12 of ``aaria dataset -n 40 --seed 2033``
    (ADIS16485, ±5 g) 52 samples of 6001 at the range kept the fit at 2.5 noise floors, the same
    from the true table (not a local minimum), the tool tip 25 mm off. A channel is at its range
    within one least significant bit, from the record's ``noise_parameters``; where they give no
    range (a recording without ``--imu-model``), a channel is clipped where it holds its run's
    largest or smallest value for :data:`FLAT_TOP` samples in a row or more (a saturated
    converter repeats its full-scale code; a noisy signal at a peak does not).

    Args:
        imu: the record's IMU signals, T × S × 6 [rad/s, m/s²]
        noise_parameters: the record's ``noise_parameters`` (None: no model)
    """
    parameters = noise_parameters if isinstance(noise_parameters, dict) else {}
    out = np.zeros(imu.shape[0], dtype=bool)
    for sensor, units, channels in (("gyro", "rad_s", slice(0, 3)), ("accel", "m_s2", slice(3, 6))):
        limit = parameters.get(f"{sensor}_range_{units}")
        if limit is None or not np.isfinite(float(limit)) or float(limit) <= 0:
            out |= flat_tops(np.asarray(imu[:, :, channels], dtype=float))
            continue
        lsb = float(noise_parameters.get(f"{sensor}_lsb_{units}", 0.0) or 0.0)
        level = float(limit) - max(lsb, 1e-6 * float(limit))
        out |= np.any(np.abs(imu[:, :, channels]) >= level, axis=(1, 2))
    return out
