"""The measured signals the kinematic fit takes: spline derivatives, smoothing, noise weights.

Joint velocities and accelerations are the derivatives of a quintic spline through the encoder
values; on noisy records the base IMU's signals, inputs of the model, are smoothed and
differentiated with windows the data choose (:func:`smoothed`); each signal is weighted by
1 / its noise level (:func:`signal_weights`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from aaria_pin.core.imu_noise import ADIS16485
from aaria_pin.core.se3 import Array

__all__ = [
    "derivatives",
    "rounding_level",
    "sample_derivatives",
    "signal_weights",
    "smoothed",
    "uniform_time",
]

_WINDOWS = (0.25, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0)  # [s] smoothing windows tried on noisy base signals


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


def smoothed(time: Array, values: Array, level: float, deriv: int) -> Array:
    """Noisy samples smoothed (``deriv`` 0) or differentiated (1), the window chosen by the data.

    A Savitzky–Golay cubic per column over the longest of the windows :data:`_WINDOWS` whose
    estimate agrees with every shorter window's within :data:`_AGREE` times the shorter one's
    noise (Lepski's rule: the noise of each window's estimate is known from the white noise
    ``level`` and the filter's coefficients; a longer window is taken until it starts to bend
    the motion). Against the noise-free derivative of random arm 16's base gyroscope (ADIS16485
    noise, 30 s at 200 Hz, true RMS 0.10, 0.0095, 0.0040 rad/s²): one fixed 0.5 s window left
    2.0e-3 rad/s² RMS on each axis, a smoothing spline with the noise's smoothness
    (``s = n·level²``) 1.5e-3, 4.4e-4, 6.4e-4, this rule 1.1e-3, 3.4e-4, 2.8e-4; that arm's
    tool tip went from 0.42 m to 8 cm (the base's small rotations carry the lengths its
    joints' own motion does not show: what is left is the noise's limit, not the filter's).

    Args:
        time: sample times [s]
        values: T × C samples
        level: the white noise's per-sample standard deviation [units of values]
        deriv: 0 (smoothed values) or 1 (their time derivative)

    Returns:
        T × C, smoothed values or derivatives [units (per second)].
    """
    step = float(np.median(np.diff(time)))
    samples = values.shape[0]
    longest = samples if samples % 2 else samples - 1
    sizes = sorted({min(max(5, 2 * round(w / step / 2) + 1), longest) for w in _WINDOWS})
    if sizes[0] < 5:
        if deriv == 0:
            return values.copy()
        (derivative,) = derivatives(time, values, 1)
        return derivative
    return _lepski(values, sizes, 3, deriv, step, level)


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
