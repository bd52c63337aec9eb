"""Point-to-point joint motions over time: the wrist report's ramp and a smooth trapezoid.

The report's simulation: each joint waits ``start`` seconds, then moves at a constant speed to its
target and holds; the direction follows the target's sign. That ramp has infinite acceleration at
its corners, so for torques use :func:`trapezoid_profile`: the same start and top speed, with the
speed reached and shed at a limited acceleration (a triangle when the move is too short to
reach the top speed).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = ["ramp_profile", "trapezoid_profile"]


def _check(speed: float, acceleration: float | None = None) -> None:
    if not (np.isfinite(speed) and speed > 0):
        raise ParameterError(parameter="speed", value=speed, allowed="> 0")
    if acceleration is not None and not (np.isfinite(acceleration) and acceleration > 0):
        raise ParameterError(parameter="acceleration", value=acceleration, allowed="> 0")


def ramp_profile(
    target: float, speed: float, time: ArrayLike, start: float = 2.0
) -> tuple[Array, Array, Array]:
    """The report's ramp: hold at 0 until ``start``, move at ``speed`` to ``target``, hold.

    Args:
        target: final joint value [rad]
        speed: joint speed [rad/s]
        time: sample times [s]
        start: when the motion starts [s]

    Returns:
        Joint value, velocity and acceleration over time (the acceleration is zero between the
        corners, where it is infinite).
    """
    _check(speed)
    t = np.asarray(time, dtype=float)
    sign = np.sign(target)
    end = start + abs(target) / speed
    moving = (t > start) & (t < end)
    q = sign * np.clip(speed * (t - start), 0.0, abs(target))
    return q, np.where(moving, sign * speed, 0.0), np.zeros_like(t)


def trapezoid_profile(
    target: float, speed: float, acceleration: float, time: ArrayLike, start: float = 2.0
) -> tuple[Array, Array, Array]:
    """A smooth move to ``target``: accelerate, cruise at ``speed``, decelerate, hold.

    Args:
        target: final joint value [rad]
        speed: top joint speed [rad/s]
        acceleration: acceleration limit [rad/s²]
        time: sample times [s]
        start: when the motion starts [s]

    Returns:
        Joint value, velocity and acceleration over time.
    """
    _check(speed, acceleration)
    t = np.asarray(time, dtype=float) - start
    distance, sign = abs(target), np.sign(target)
    top = min(speed, np.sqrt(distance * acceleration))  # a triangle if the top is not reached
    ramp = top / acceleration
    cruise = (distance - top * ramp) / top if top > 0 else 0.0
    t1, t2, t3 = ramp, ramp + cruise, 2 * ramp + cruise
    q = np.zeros_like(t)
    qd = np.zeros_like(t)
    qdd = np.zeros_like(t)
    a = (t > 0) & (t <= t1)
    q[a], qd[a], qdd[a] = 0.5 * acceleration * t[a] ** 2, acceleration * t[a], acceleration
    c = (t > t1) & (t <= t2)
    q[c], qd[c] = 0.5 * top * ramp + top * (t[c] - t1), top
    d = (t > t2) & (t < t3)
    left = t3 - t[d]
    q[d], qd[d], qdd[d] = (
        distance - 0.5 * acceleration * left**2,
        acceleration * left,
        -acceleration,
    )
    q[t >= t3] = distance
    return sign * q, sign * qd, sign * qdd
