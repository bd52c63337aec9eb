from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.core.profiles import ramp_profile, trapezoid_profile
from aaria_pin.errors import ParameterError


@pytest.mark.parametrize("target", [np.radians(60.0), np.radians(-30.0), 0.0])
def test_ramp_waits_moves_at_the_speed_and_holds(target: float) -> None:
    speed = np.radians(40.0)
    t = np.linspace(0, 6, 6001)
    q, qd, _ = ramp_profile(target, speed, t)
    assert np.all(q[t <= 2.0] == 0.0)
    end = 2.0 + abs(target) / speed
    np.testing.assert_allclose(q[t >= end], target)
    inside = (t > 2.01) & (t < end - 0.01)
    np.testing.assert_allclose(qd[inside], np.sign(target) * speed)
    np.testing.assert_allclose(
        np.diff(q)[inside[1:]] / np.diff(t)[0], qd[1:][inside[1:]], atol=1e-9
    )


@pytest.mark.parametrize(
    ("target", "speed", "acceleration"),
    [
        (np.radians(90.0), np.radians(40.0), np.radians(80.0)),  # trapezoid
        (np.radians(-10.0), np.radians(40.0), np.radians(80.0)),  # triangle, negative
        (0.0, 1.0, 1.0),
    ],
)
def test_trapezoid_limits_and_derivatives(target: float, speed: float, acceleration: float) -> None:
    t = np.linspace(0, 8, 80001)
    q, qd, qdd = trapezoid_profile(target, speed, acceleration, t)
    assert np.all(np.abs(qd) <= speed + 1e-12) and np.all(np.abs(qdd) <= acceleration + 1e-12)
    assert q[0] == 0.0 and q[-1] == pytest.approx(target, abs=1e-12)
    dt = t[1] - t[0]
    np.testing.assert_allclose(np.diff(q) / dt, (qd[1:] + qd[:-1]) / 2, atol=acceleration * dt)
    np.testing.assert_allclose(np.cumsum(qdd[1:]) * dt, qd[1:], atol=2 * acceleration * dt)


def test_bad_speeds() -> None:
    with pytest.raises(ParameterError, match="speed"):
        ramp_profile(1.0, 0.0, [0.0])
    with pytest.raises(ParameterError, match="acceleration"):
        trapezoid_profile(1.0, 1.0, -1.0, [0.0])
