"""A rigid body carried by hand, with IMUs on it: the simulated recording of a rigid-body fit.

:func:`hand_motion` draws a smooth random motion, band-limited as a hand's (sums of sinusoids
of 0.2–3 Hz): the body's ZYX angles (ψ about z, θ about y, φ about x, ``R_WB = Rz·Ry·Rx``) and
its position, each a sum of sinusoids, so the angular velocity, angular acceleration and
linear acceleration are exact (closed form, no numerical derivative). :func:`simulate_rigid_body`
samples the exact signals of IMUs at known mounts on the body, each at its own rate, start and
time offset, and adds the IMU noise of :mod:`~aaria_pin.core.imu_noise` (and, when asked, the
per-run errors of :mod:`~aaria_pin.core.imu_errors`): a :class:`~aaria_pin.core.recording.
RecordedRun` as a recording of the real body would be, the truth in the mounts.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from aaria_pin.core.imu_errors import draw_imu_errors
from aaria_pin.core.imu_model import STANDARD_GRAVITY, ImuNoiseModel
from aaria_pin.core.imu_noise import add_imu_noise
from aaria_pin.core.recording import STREAM_COLUMNS, RecordedRun, SensorStream
from aaria_pin.core.rotations import elementary
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = [
    "BodyState",
    "HandMotion",
    "ImuMount",
    "default_pair",
    "exact_imu_signals",
    "hand_motion",
    "relative_pose",
    "simulate_rigid_body",
]

GRAVITY = np.array([0.0, 0.0, -STANDARD_GRAVITY])
"""Gravity in the world frame [m/s²] (z up)."""


@dataclass(frozen=True)
class BodyState:
    """The body's motion at some instants.

    Attributes:
        rotation: (n, 3, 3) ``R_WB`` (body axes in the world)
        angular_velocity: (n, 3) ω in the body frame [rad/s]
        angular_acceleration: (n, 3) dω/dt in the body frame [rad/s²]
        acceleration: (n, 3) the body origin's acceleration in the world frame [m/s²]
    """

    rotation: Array
    angular_velocity: Array
    angular_acceleration: Array
    acceleration: Array


@dataclass(frozen=True)
class HandMotion:
    """A smooth random motion: six channels (ψ, θ, φ [rad], x, y, z [m]), sums of sinusoids.

    Channel ``c`` is ``Σ_k amplitude[c, k]·sin(2π·frequency[c, k]·t + phase[c, k])``.

    Attributes:
        frequency: (6, K) [Hz]
        amplitude: (6, K) [rad, m]
        phase: (6, K) [rad]
    """

    frequency: Array
    amplitude: Array
    phase: Array

    def _channels(self, t: Array, derivative: int) -> Array:
        """The channels' ``derivative``-th time derivative at ``t``, (n, 6)."""
        w = 2.0 * np.pi * self.frequency  # (6, K)
        angle = w[None] * t[:, None, None] + self.phase[None]
        wave = (
            np.sin(angle)
            if derivative == 0
            else np.cos(angle)
            if derivative == 1
            else -np.sin(angle)
        )
        return np.asarray(np.sum(self.amplitude * w**derivative * wave, axis=2))

    def state(self, times: Array) -> BodyState:
        """The body's rotation, angular velocity and acceleration, and acceleration at ``times``."""
        t = np.asarray(times, dtype=np.float64)
        (psi, theta, phi), (dpsi, dth, dphi) = (
            self._channels(t, 0)[:, :3].T,
            self._channels(t, 1)[:, :3].T,
        )
        ddpsi, ddth, ddphi = self._channels(t, 2)[:, :3].T
        s_th, c_th, s_ph, c_ph = np.sin(theta), np.cos(theta), np.sin(phi), np.cos(phi)
        omega = np.stack(
            [
                dphi - dpsi * s_th,
                dth * c_ph + dpsi * c_th * s_ph,
                -dth * s_ph + dpsi * c_th * c_ph,
            ],
            axis=1,
        )
        alpha = np.stack(
            [
                ddphi - ddpsi * s_th - dpsi * dth * c_th,
                ddth * c_ph
                - dth * dphi * s_ph
                + ddpsi * c_th * s_ph
                - dpsi * dth * s_th * s_ph
                + dpsi * dphi * c_th * c_ph,
                -ddth * s_ph
                - dth * dphi * c_ph
                + ddpsi * c_th * c_ph
                - dpsi * dth * s_th * c_ph
                - dpsi * dphi * c_th * s_ph,
            ],
            axis=1,
        )
        rotation = elementary(2, psi) @ elementary(1, theta) @ elementary(0, phi)
        return BodyState(rotation, omega, alpha, self._channels(t, 2)[:, 3:])


def hand_motion(
    seed: int = 0,
    angular_rate: float | Sequence[float] = 1.0,
    acceleration: float = 2.0,
    travel: float = 0.5,
    band: tuple[float, float] = (0.2, 3.0),
    components: int = 6,
) -> HandMotion:
    """A random hand-like motion: smooth turns and translations, band-limited.

    Each channel is ``components`` sinusoids of frequencies drawn uniformly in ``band``, random
    phases, and amplitudes of random weights scaled to the RMS asked for.

    Args:
        seed: the random seed
        angular_rate: the RMS rate of each Euler angle (z, y, x), one value or three [rad/s]
            (0 for an axis: the body does not turn about it)
        acceleration: the RMS acceleration of each position channel [m/s²]
        travel: the largest excursion of each position channel [m] (amplitudes scaled down
            to it)
        band: the lowest and highest frequency [Hz]
        components: the sinusoids per channel

    Returns:
        The motion.

    Raises:
        ParameterError: a band not ``0 < low < high``, or fewer than one component.
    """
    low, high = band
    if not 0.0 < low < high or components < 1:
        raise ParameterError(
            f"hand motion band is {band} with {components} components; allowed: "
            "0 < low < high, components >= 1",
            parameter="band",
        )
    rng = np.random.default_rng(seed)
    frequency = rng.uniform(low, high, (6, components))
    phase = rng.uniform(0.0, 2.0 * np.pi, (6, components))
    weight = rng.uniform(0.5, 1.0, (6, components))
    rms = np.sqrt(np.sum(weight**2, axis=1, keepdims=True) / 2.0)
    rates = np.broadcast_to(np.asarray(angular_rate, dtype=np.float64), (3,))
    derivative = weight / rms  # each channel's derivative amplitudes, RMS 1
    w = 2.0 * np.pi * frequency
    amplitude = np.empty((6, components))
    amplitude[:3] = rates[:, None] * derivative[:3] / w[:3]
    position = acceleration * derivative[3:] / w[3:] ** 2
    scale = np.minimum(1.0, travel / np.sum(position, axis=1, keepdims=True))
    amplitude[3:] = position * scale
    return HandMotion(frequency, amplitude, phase)


@dataclass(frozen=True)
class ImuMount:
    """An IMU on the body: where it sits and how it samples.

    Attributes:
        name: the IMU's name (its stream's)
        rotation: (3, 3) ``R_BI``, the IMU's axes in the body frame
        position: (3,) the IMU's origin in the body frame [m]
        rate: its sample rate [Hz]
        time_offset: the sample stamped ``t`` is the signal at ``t + time_offset`` [s]
        start: its first stamp [s]
    """

    name: str
    rotation: Array
    position: Array
    rate: float = 200.0
    time_offset: float = 0.0
    start: float = 0.0


def relative_pose(a: ImuMount, b: ImuMount) -> tuple[Array, Array, float]:
    """B's pose in A's frame and B's time offset to A: what :func:`identify_rigid` estimates.

    Returns:
        ``R_AB`` (3, 3) (``v_A = R_AB·v_B``), B's origin in A's frame (3,) [m], and
        ``δ_B - δ_A`` [s] (B's sample stamped ``t`` is A's instant ``t + δ``).
    """
    ra, rb = np.asarray(a.rotation), np.asarray(b.rotation)
    position = ra.T @ (np.asarray(b.position) - np.asarray(a.position))
    return ra.T @ rb, position, b.time_offset - a.time_offset


def default_pair(rate_b: float = 200.0, time_offset: float = 0.0) -> tuple[ImuMount, ImuMount]:
    """Two IMUs 200 mm apart on a stick, B turned: the pair of issue 26's Must-show.

    Args:
        rate_b: B's sample rate [Hz] (A samples at 200 Hz)
        time_offset: B's time offset [s]
    """
    turned = elementary(2, 2.0) @ elementary(1, -0.5) @ elementary(0, 0.3)
    a = ImuMount("imu_a", np.eye(3), np.zeros(3))
    b = ImuMount("imu_b", turned, np.array([0.16, 0.11, 0.04]), rate_b, time_offset, 0.013)
    return a, b


def exact_imu_signals(motion: HandMotion, mount: ImuMount, times: Array) -> Array:
    """The exact ``[wx wy wz fx fy fz]`` of a mounted IMU at body instants ``times``, (n, 6)."""
    state = motion.state(times)
    omega, alpha = state.angular_velocity, state.angular_acceleration
    p = np.asarray(mount.position, dtype=np.float64)
    body_force = np.einsum("nji,nj->ni", state.rotation, state.acceleration - GRAVITY)
    lever = np.cross(alpha, p) + np.cross(omega, np.cross(omega, p))
    r_t = np.asarray(mount.rotation, dtype=np.float64).T
    return np.concatenate([omega @ r_t.T, (body_force + lever) @ r_t.T], axis=1)


def simulate_rigid_body(
    mounts: Sequence[ImuMount],
    duration: float = 20.0,
    motion: HandMotion | None = None,
    model: ImuNoiseModel | None = None,
    seed: int = 0,
    sensor_errors: bool = False,
) -> RecordedRun:
    """A recording of IMUs on a rigid body carried by hand (no truth in it: the mounts are).

    Args:
        mounts: the IMUs (names unique)
        duration: each IMU's span of stamps [s]
        motion: the body's motion (None: :func:`hand_motion` of ``seed``)
        model: the IMU noise model (None: exact signals)
        seed: the seed of the motion and of each IMU's noise
        sensor_errors: also the per-run errors of the model (scale, cross-axis, misalignment,
            turn-on bias, …; :func:`~aaria_pin.core.imu_errors.draw_imu_errors`)

    Returns:
        One ``imu`` stream per mount.

    Raises:
        ParameterError: a duration not > 0.
    """
    if not duration > 0.0:
        raise ParameterError(parameter="duration", value=duration, allowed="> 0 s")
    motion = hand_motion(seed) if motion is None else motion
    children = np.random.SeedSequence([seed, 26]).spawn(len(mounts))
    streams = []
    for mount, child in zip(mounts, children, strict=True):
        stamps = mount.start + np.arange(int(np.floor(duration * mount.rate)) + 1) / mount.rate
        signals = exact_imu_signals(motion, mount, stamps + mount.time_offset)
        if model is not None:
            noise_seq, error_seq = child.spawn(2)
            errors = None
            if sensor_errors:
                errors = draw_imu_errors(model, error_seq, stamps.size, mount.rate, (0,), 1)
            exact = signals[:, None, :]
            if errors is not None:
                exact = errors.sensed(exact)
            used = model if errors is None else errors.noise_model
            rng = np.random.default_rng(noise_seq)
            signals = add_imu_noise(exact, mount.rate, rng, used)[:, 0]
        streams.append(SensorStream(mount.name, "imu", stamps, signals, STREAM_COLUMNS["imu"]))
    return RecordedRun(streams, source="simulated rigid body")
