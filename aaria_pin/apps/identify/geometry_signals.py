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

__all__ = ["derivatives", "signal_weights", "smoothed"]

_WINDOWS = (0.25, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0)  # [s] smoothing windows tried on noisy base signals


_AGREE = 2.0  # a longer window agrees when within this many of the shorter one's noise σ


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
    from scipy.signal import savgol_coeffs, savgol_filter

    step = float(np.median(np.diff(time)))
    samples = values.shape[0]
    longest = samples if samples % 2 else samples - 1
    sizes = sorted({min(max(5, 2 * round(w / step / 2) + 1), longest) for w in _WINDOWS})
    if sizes[0] < 5:
        if deriv == 0:
            return values.copy()
        (derivative,) = derivatives(time, values, 1)
        return derivative
    estimates = [
        np.asarray(savgol_filter(values, n, 3, deriv=deriv, delta=step, axis=0)) for n in sizes
    ]
    noise = [
        level * float(np.linalg.norm(savgol_coeffs(n, 3, deriv=deriv, delta=step))) for n in sizes
    ]
    out = np.empty_like(values, dtype=float)
    for column in range(values.shape[1]):
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
