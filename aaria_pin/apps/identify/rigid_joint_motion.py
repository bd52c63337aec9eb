"""Two rigid bodies joined by a joint, an IMU on each: the simulated recording of a joint fit.

Body 1 is carried by hand (:func:`~aaria_pin.apps.identify.rigid_motion.hand_motion`); body 2
turns (revolute) or slides (prismatic) on it by a smooth random joint motion. The signals are
closed form: body 2's angular velocity ``ω_2 = R_12ᵀ·ω_1 + q̇·a`` and the specific force of its
IMU from the IMU's path ``y(t)`` in body 1's frame (``ÿ + 2ω×ẏ + α×y + ω×(ω×y)``), as
:func:`~aaria_pin.apps.identify.rigid_joint.identify_joint` is checked against.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from aaria_pin.apps.identify.rigid_motion import (
    GRAVITY,
    HandMotion,
    ImuMount,
    exact_imu_signals,
    hand_motion,
)
from aaria_pin.core.imu_model import ImuNoiseModel
from aaria_pin.core.imu_noise import add_imu_noise
from aaria_pin.core.recording import STREAM_COLUMNS, RecordedRun, SensorStream
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = ["JOINT_TYPES", "UnknownJoint", "simulate_jointed_bodies"]

JOINT_TYPES = ("revolute", "prismatic")
"""The joints :func:`simulate_jointed_bodies` makes and :func:`identify_joint` tells apart."""


@dataclass(frozen=True)
class UnknownJoint:
    """The joint between body 1 and body 2 (body 2's frame is body 1's at joint value 0).

    Attributes:
        kind: ``revolute`` or ``prismatic``
        axis: (3,) unit axis in body 1's frame
        point: (3,) a point on the axis in body 1's frame [m] (revolute)
        rate: the joint rate's RMS [rad/s or m/s]
    """

    kind: str
    axis: Array
    point: Array
    rate: float = 1.0


def _joint_motion(seed: int, rate: float, t: Array) -> tuple[Array, Array, Array]:
    """A smooth random joint value, rate and acceleration: five sinusoids of 0.2–2 Hz.

    ``rate`` is the RMS of the joint rate [rad/s or m/s].
    """
    rng = np.random.default_rng([seed, 27])
    freq = 2.0 * np.pi * rng.uniform(0.2, 2.0, 5)
    phase = rng.uniform(0.0, 2.0 * np.pi, 5)
    scale = rate / np.sqrt(5 / 2.0) / freq
    angle = freq[None] * t[:, None] + phase[None]
    return (
        (scale * np.sin(angle)).sum(1),
        (scale * freq * np.cos(angle)).sum(1),
        -(scale * freq**2 * np.sin(angle)).sum(1),
    )


def _axis_rotation(axis: Array, angle: Array) -> Array:
    """Rotations by ``angle`` about one unit axis, (n, 3, 3)."""
    from scipy.spatial.transform import Rotation

    return np.asarray(Rotation.from_rotvec(angle[:, None] * axis[None]).as_matrix())


def _body_two_signals(
    motion: HandMotion, joint: UnknownJoint, mount: ImuMount, t: Array, seed: int
) -> Array:
    """The exact signals of an IMU on body 2, (n, 6)."""
    state = motion.state(t)
    w1, a1 = state.angular_velocity, state.angular_acceleration
    q, qd, qdd = _joint_motion(seed, joint.rate, t)
    axis = np.asarray(joint.axis, dtype=np.float64)
    x = np.asarray(mount.position, dtype=np.float64)
    n = t.size
    if joint.kind == "revolute":
        turn = _axis_rotation(axis, q)  # R_12
        c = np.asarray(joint.point, dtype=np.float64)
        y = c + np.einsum("nij,j->ni", turn, x - c)
        y_rate = qd[:, None] * np.cross(axis, y - c)
        y_accel = qdd[:, None] * np.cross(axis, y - c) + qd[:, None] * np.cross(axis, y_rate)
        w1_in_2 = np.einsum("nji,nj->ni", turn, w1)
        w2 = w1_in_2 + qd[:, None] * axis
    else:
        turn = np.broadcast_to(np.eye(3), (n, 3, 3))
        y = x + q[:, None] * axis
        y_rate, y_accel = qd[:, None] * axis, qdd[:, None] * axis
        w2 = w1
    force_1 = (
        np.einsum("nji,nj->ni", state.rotation, state.acceleration - GRAVITY)
        + np.cross(a1, y)
        + np.cross(w1, np.cross(w1, y))
        + 2.0 * np.cross(w1, y_rate)
        + y_accel
    )
    force_2 = np.einsum("nji,nj->ni", turn, force_1)
    r_t = np.asarray(mount.rotation, dtype=np.float64).T
    return np.concatenate([w2 @ r_t.T, force_2 @ r_t.T], axis=1)


def simulate_jointed_bodies(
    joint: UnknownJoint,
    mounts: tuple[ImuMount, ImuMount],
    duration: float = 20.0,
    model: ImuNoiseModel | None = None,
    seed: int = 0,
) -> RecordedRun:
    """A recording of an IMU on body 1 (``mounts[0]``) and one on body 2 (``mounts[1]``).

    Args:
        joint: the joint (its frame: body 1's)
        mounts: the IMUs on body 1 and on body 2 (body 2's frame at joint value 0)
        duration: the span of stamps [s]
        model: the IMU noise model (None: exact)
        seed: the seed of the motions and of the noise

    Returns:
        Two ``imu`` streams.

    Raises:
        ParameterError: an unknown joint kind.
    """
    if joint.kind not in JOINT_TYPES:
        raise ParameterError(parameter="kind", value=joint.kind, allowed=", ".join(JOINT_TYPES))
    motion = hand_motion(seed)
    streams = []
    for k, mount in enumerate(mounts):
        stamps = mount.start + np.arange(int(np.floor(duration * mount.rate)) + 1) / mount.rate
        at = stamps + mount.time_offset
        if k == 0:
            signals = exact_imu_signals(motion, mount, at)
        else:
            signals = _body_two_signals(motion, joint, mount, at, seed)
        if model is not None:
            rng = np.random.default_rng([seed, 28, k])
            signals = add_imu_noise(signals[:, None], mount.rate, rng, model)[:, 0]
        streams.append(SensorStream(mount.name, "imu", stamps, signals, STREAM_COLUMNS["imu"]))
    return RecordedRun(streams, source="simulated jointed bodies")
