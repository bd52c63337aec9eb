"""Slowly varying IMU biases, estimated with the kinematic fit by variable projection.

An IMU's bias wanders (the Gauss–Markov in-run bias of :mod:`~aaria_pin.core.imu_noise`): a fit
that takes it for white noise puts it into the lengths. On random arm 0 of ``aaria dataset
--seed 41`` (ADIS16485 noise, 30 s at 200 Hz) the tool tip ended 28 mm off, 37 mm with only the
slow part of the noise (the noise minus its 2 s running mean: 25 mm): an accelerometer bias of
3e-4 m/s² is what a length error of 3 cm makes when the base's angular acceleration is
0.01 rad/s², the only motion some lengths show.

Each channel's bias is a cubic B-spline of time (:func:`bias_basis`) whose knots are as far apart
as the bias model makes them worth: where the bias random walk over a knot interval equals the
white noise averaged over it (:func:`knot_spacing`; ADIS16485 at 200 Hz: 10.5 s for the
accelerometers, 19 s for the gyroscopes). The biases enter the residual linearly, so they are
not parameters of the Levenberg–Marquardt: for given geometric parameters their best values
are a linear least-squares solution, and the fit minimises what is left (Golub and Pereyra's
variable projection; :class:`BiasModel`): per measured IMU channel the residual and its
Jacobian lose their component in the spline space, and the base IMU's biases (inputs of the
model: a bias ``b`` of its specific force moves every predicted accelerometer by ``Rᵢ(t)ᵀb``)
span a few more columns, orthogonalised against the first. The parameters' covariance from the
projected Jacobian is their covariance with the biases unknown (marginalised).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from aaria_pin.apps.identify.geometry_signals import signal_weights
from aaria_pin.core.imu_noise import ADIS16485
from aaria_pin.core.se3 import Array

__all__ = ["BiasModel", "bias_basis", "knot_spacing"]

_RANK = 1e-6  # a base-bias column whose part outside the channel biases' space is below this share


def knot_spacing(noise_parameters: Any, rate: float) -> tuple[float, float]:
    """The bias splines' knot spacing of the gyroscopes and the accelerometers [s].

    The Gauss–Markov bias of stability ``b`` and correlation time ``T`` walks at
    ``q = b·√(2/T)`` per √s; over an interval ``Δ`` it moves ``q·√Δ`` while the white noise of
    per-sample level ``σ`` averages to ``σ/√(rate·Δ)``: the two are equal at
    ``Δ = σ / (q·√rate)``. A model without in-run bias gives an infinite spacing (one constant
    per channel: a turn-on bias).

    Args:
        noise_parameters: the record's ``noise_parameters`` (else ADIS16485's)
        rate: the sample rate [Hz]
    """
    parameters = noise_parameters if isinstance(noise_parameters, dict) else {}
    levels = 1.0 / signal_weights(rate, noise_parameters)  # the white noise's, per sample
    correlation = float(parameters.get("bias_correlation_time_s", ADIS16485.bias_correlation_time))
    spacings = []
    for level, (sensor, units, model) in zip(
        levels[::3],
        (("gyro", "rad_s", ADIS16485.gyro), ("accel", "m_s2", ADIS16485.accel)),
        strict=True,
    ):
        stability = float(parameters.get(f"{sensor}_bias_stability_{units}", model.bias_stability))
        walk = stability * np.sqrt(2.0 / max(correlation, 1e-9))
        spacings.append(float(level) / (walk * np.sqrt(rate)) if walk > 0 else np.inf)
    return spacings[0], spacings[1]


def bias_basis(time: Array, start: float, end: float, spacing: float) -> Array:
    """The cubic B-spline basis of a bias over ``[start, end]``, evaluated at ``time`` (T × k).

    ``floor((end - start) / spacing)`` equal knot intervals (clamped ends); a run shorter than
    one spacing has one constant column.
    """
    intervals = int(np.floor((end - start) / spacing)) if np.isfinite(spacing) else 0
    if intervals < 1 or end <= start:
        return np.ones((time.size, 1))
    from scipy.interpolate import BSpline

    inner = np.linspace(start, end, intervals + 1)
    knots = np.concatenate([[start] * 3, inner, [end] * 3])
    clipped = np.clip(time, start, end)
    return np.asarray(BSpline.design_matrix(clipped, knots, 3).toarray())


def _orthonormal(basis: Array) -> Array:
    """An orthonormal basis (T × k) of the columns' span."""
    q, _ = np.linalg.qr(basis)
    return np.asarray(q)


@dataclass(frozen=True)
class BiasModel:
    """The bias splines of one fit's samples: project residuals and Jacobians off their span.

    Attributes:
        gyro: orthonormal basis of a gyroscope channel's bias at the samples, T × kg
        accel: the same for an accelerometer channel, T × ka
        accel_raw: the accelerometers' B-spline basis itself (the base IMU's bias), T × ka
    """

    gyro: Array
    accel: Array
    accel_raw: Array

    @classmethod
    def at(cls, time: Array, span: tuple[float, float], spacings: tuple[float, float]) -> BiasModel:
        """The bias model at the sample times ``time`` of a run over ``span`` [s]."""
        gyro = bias_basis(time, span[0], span[1], spacings[0])
        accel = bias_basis(time, span[0], span[1], spacings[1])
        return cls(_orthonormal(gyro), _orthonormal(accel), accel)

    def _channels(self, values: Array) -> Array:
        """``values`` (T × S × 6 × ...) less their part in each channel's bias space."""
        out = np.array(values, dtype=float, copy=True)
        for basis, channels in ((self.gyro, slice(0, 3)), (self.accel, slice(3, 6))):
            part = out[:, :, channels]
            coefficients = np.tensordot(basis.T, part, axes=(1, 0))
            out[:, :, channels] = part - np.tensordot(basis, coefficients, axes=(1, 0))
        return out

    def base_space(self, sensitivity: Array, weights: Array) -> Array | None:
        """The base IMU's accelerometer bias columns, off the channel biases' span, orthonormal.

        Args:
            sensitivity: per base accelerometer axis (last axis) the change of the predicted
                signals per unit of it, T × S × 6 × 3
            weights: the six signals' weights

        Returns:
            (T·S·6) × k orthonormal columns, or None when nothing is left.
        """
        raw = self.accel_raw
        spread = (sensitivity * weights[:, None])[..., None] * raw[:, None, None, None, :]
        spread = spread.reshape(*spread.shape[:3], -1)
        largest = float(np.sqrt(np.max(np.sum(spread**2, axis=(0, 1, 2)))))
        columns = self._channels(spread).reshape(-1, spread.shape[-1])
        gram = columns.T @ columns
        eigenvalues, vectors = np.linalg.eigh(gram)
        kept = eigenvalues > (_RANK * max(largest, 1e-300)) ** 2
        if not kept.any():
            return None
        return np.asarray(columns @ (vectors[:, kept] / np.sqrt(eigenvalues[kept])))

    def project(self, values: Array, base: Array | None) -> Array:
        """Weighted residuals (T × S × 6) or Jacobian (T × S × 6 × n) off every bias's span.

        Returns:
            The projection, flattened to (T·S·6) or (T·S·6) × n.
        """
        out = self._channels(values)
        flat = out.reshape(-1) if out.ndim == 3 else out.reshape(-1, out.shape[-1])
        if base is not None:
            flat = flat - base @ (base.T @ flat)
        return flat
