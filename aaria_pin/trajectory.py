"""Trajectories as arrays over time: joint motions and the prescribed motion of the base.

Everything here is computed for the whole time grid at once. Sine motions follow Simulink's
Sine Wave block, ``x(t) = A·sin(w·t + phase) + bias`` with w in rad/s, and their exact first
and second derivatives.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin._se3 import Array
from aaria_pin.errors import ParameterError

__all__ = [
    "MAX_DURATION",
    "MAX_RATE",
    "MAX_SAMPLES",
    "BaseMotion",
    "JointTrajectory",
    "gimbal_xyz_motion",
    "sample_times",
    "sine_motion",
]

MAX_DURATION = 86_400.0
"""Longest run [s]."""
MAX_RATE = 100_000.0
"""Highest sample rate [Hz]."""
MAX_SAMPLES = 2_000_000
"""Most samples in one run (memory: about 1.2 kB per sample for the whole record)."""


def sample_times(duration: float, rate: float) -> Array:
    """The time grid of a run: from 0 to ``duration`` inclusive in steps of ``1/rate``.

    Like Simulink's fixed-step output, a run of duration D at rate f has ``round(D·f) + 1``
    samples.

    Args:
        duration: run length [s], 0 < duration <= 86,400
        rate: sample rate [Hz], 0 < rate <= 100,000

    Returns:
        Sample times [s].

    Raises:
        ParameterError: a value outside those limits, or more than 2,000,000 samples.
    """
    if not (np.isfinite(duration) and 0 < duration <= MAX_DURATION):
        raise ParameterError(
            f"duration {duration!r} s; allowed: 0 < duration <= {MAX_DURATION:g} s"
        )
    if not (np.isfinite(rate) and 0 < rate <= MAX_RATE):
        raise ParameterError(f"rate {rate!r} Hz; allowed: 0 < rate <= {MAX_RATE:g} Hz")
    n = round(duration * rate) + 1
    if n > MAX_SAMPLES:
        raise ParameterError(
            f"duration × rate gives {n} samples; allowed: at most {MAX_SAMPLES} per run"
        )
    if n < 2:
        raise ParameterError(f"duration {duration} s at {rate} Hz gives 1 sample; allowed: >= 2")
    return np.arange(n) / rate


def sine_motion(
    amplitude: ArrayLike, bias: ArrayLike, frequency: ArrayLike, phase: ArrayLike, time: Array
) -> tuple[Array, Array, Array]:
    """Sine motions and their exact derivatives, one column per motion.

    Args:
        amplitude: amplitudes, shape (k,) [rad or m]
        bias: offsets, shape (k,) [rad or m]
        frequency: angular frequencies, shape (k,) [rad/s]
        phase: phases, shape (k,) [rad]
        time: sample times, shape (T,) [s]

    Returns:
        Value, first and second time derivative, each shape (T, k).
    """
    A = np.asarray(amplitude, dtype=float)
    w = np.asarray(frequency, dtype=float)
    angle = np.outer(time, w) + np.asarray(phase, dtype=float)
    s, c = np.sin(angle), np.cos(angle)
    return A * s + np.asarray(bias, dtype=float), A * w * c, -A * w * w * s


@dataclass(frozen=True)
class JointTrajectory:
    """Joint values over time, one column per actuated joint in model order.

    Attributes:
        time: sample times, shape (T,) [s]
        q: joint values, shape (T, n) [rad or m]
        qd: joint velocities, shape (T, n) [rad/s or m/s]
        qdd: joint accelerations, shape (T, n) [rad/s² or m/s²]
    """

    time: Array
    q: Array
    qd: Array
    qdd: Array


@dataclass(frozen=True)
class BaseMotion:
    """Prescribed motion of the base frame in the world, over time.

    Attributes:
        position: base origin in the world, shape (T, 3) [m]
        velocity: its velocity, world axes, shape (T, 3) [m/s]
        acceleration: its acceleration, world axes, shape (T, 3) [m/s²]
        rotation: ``R_world_base``, shape (T, 3, 3)
        omega: angular velocity in base axes, shape (T, 3) [rad/s]
        omega_dot: its time derivative, base axes, shape (T, 3) [rad/s²]
    """

    position: Array
    velocity: Array
    acceleration: Array
    rotation: Array
    omega: Array
    omega_dot: Array

    @classmethod
    def resting(cls, n_samples: int) -> BaseMotion:
        """A base at rest at the world origin, world-aligned."""
        zeros = np.zeros((n_samples, 3))
        rotation = np.broadcast_to(np.eye(3), (n_samples, 3, 3)).copy()
        return cls(zeros, zeros.copy(), zeros.copy(), rotation, zeros.copy(), zeros.copy())

    def T_world_base(self) -> Array:
        """Base poses, shape (T, 4, 4)."""
        T = np.zeros((self.position.shape[0], 4, 4))
        T[:, :3, :3] = self.rotation
        T[:, :3, 3] = self.position
        T[:, 3, 3] = 1.0
        return T


def _rot(axis: int, angle: Array) -> Array:
    c, s = np.cos(angle), np.sin(angle)
    R = np.zeros((angle.shape[0], 3, 3))
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    R[:, axis, axis] = 1.0
    R[:, i, i], R[:, i, j], R[:, j, i], R[:, j, j] = c, -s, s, c
    return R


def gimbal_xyz_motion(
    angles: Array, rates: Array, accelerations: Array
) -> tuple[Array, Array, Array]:
    """Rotation, body angular velocity and its derivative of an X-Y-Z gimbal.

    The gimbal turns about x, then the new y, then the newer z:
    ``R = Rx(ax) · Ry(ay) · Rz(az)``.

    Args:
        angles: gimbal angles (ax, ay, az), shape (T, 3) [rad]
        rates: their derivatives, shape (T, 3) [rad/s]
        accelerations: their second derivatives, shape (T, 3) [rad/s²]

    Returns:
        ``R_world_base`` (T, 3, 3), angular velocity (T, 3) [rad/s] and angular acceleration
        (T, 3) [rad/s²], both in the rotated (body) axes.
    """
    Rx, Ry, Rz = (_rot(k, angles[:, k]) for k in range(3))
    ex, ey, ez = np.eye(3)
    # body-axis unit vectors of the three gimbal axes: Rzᵀ·Ryᵀ·ex, Rzᵀ·ey, ez
    u_z = np.broadcast_to(ez, angles.shape)
    u_y = np.einsum("tji,j->ti", Rz, ey)
    Ry_ex = np.einsum("tji,j->ti", Ry, ex)
    u_x = np.einsum("tji,tj->ti", Rz, Ry_ex)
    x_dot, y_dot, z_dot = rates.T[:, :, None]
    omega = u_x * x_dot + u_y * y_dot + u_z * z_dot
    # d/dt Rᵀ(θ) = -θ̇ [axis]× Rᵀ for a rotation about a fixed axis
    du_y = -np.cross(ez, u_y) * z_dot
    du_x = -np.cross(ez, u_x) * z_dot - np.einsum("tji,tj->ti", Rz, np.cross(ey, Ry_ex)) * y_dot
    x_dd, y_dd, z_dd = accelerations.T[:, :, None]
    omega_dot = u_x * x_dd + u_y * y_dd + u_z * z_dd + du_x * x_dot + du_y * y_dot
    return Rx @ Ry @ Rz, omega, omega_dot
