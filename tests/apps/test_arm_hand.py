"""ZYZ hand angles of the pick-place arm, gimbal lock included."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from aaria_pin.apps.arm.hand import downward_grasp, hand_angles, hand_rotation
from aaria_pin.core.rotations import matrix_from_angles
from aaria_pin.errors import ParameterError

angle = st.floats(-np.pi, np.pi)


@settings(max_examples=400, deadline=None)
@given(angle, st.floats(0.0, np.pi), angle, angle)
def test_round_trip(phi: float, theta: float, psi: float, heading: float) -> None:
    R = hand_rotation([phi, theta, psi], heading)
    result = hand_angles(R, heading)
    np.testing.assert_allclose(hand_rotation(result.angles, heading), R, atol=1e-9)


@settings(max_examples=300, deadline=None)
@given(angle, st.sampled_from([0.0, np.pi]), st.floats(-1e-9, 1e-9), angle, angle, angle)
def test_gimbal_lock_keeps_the_previous_roll(
    phi: float, lock: float, tiny: float, psi: float, heading: float, previous_psi: float
) -> None:
    theta = abs(lock - abs(tiny))
    R = hand_rotation([phi, theta, psi], heading)
    plain = hand_angles(R, heading)
    assert plain.locked
    np.testing.assert_allclose(hand_rotation(plain.angles, heading), R, atol=1e-8)
    kept = hand_angles(R, heading, previous=[0.0, theta, previous_psi])
    assert kept.angles[2] == pytest.approx(previous_psi, abs=1e-12)
    assert abs(kept.angles[0]) <= np.pi + 1e-12
    np.testing.assert_allclose(hand_rotation(kept.angles, heading), R, atol=1e-8)


def test_downward_grasp_points_down_with_the_finger_at_yaw() -> None:
    for yaw in np.linspace(-3, 3, 13):
        R = downward_grasp(yaw)
        np.testing.assert_allclose(R[:, 2], [0, 0, -1], atol=1e-15)
        np.testing.assert_allclose(R[:, 0], [np.cos(yaw), np.sin(yaw), 0], atol=1e-15)
        h = hand_angles(R, heading=0.4)
        assert h.locked and h.angles[1] == pytest.approx(0.0, abs=1e-12)
        # θ = 0: R = Rz(0.4)·Rx(π)·Rz(φ + ψ), so φ + ψ = 0.4 - yaw
        expected = np.angle(np.exp(1j * (0.4 - yaw)))
        assert np.angle(np.exp(1j * (h.angles[0] + h.angles[2]))) == pytest.approx(expected)
        np.testing.assert_allclose(
            matrix_from_angles(h.angles, "ZYZ"),
            matrix_from_angles([expected, 0, 0], "ZYZ"),
            atol=1e-12,
        )


def test_unwraps_towards_previous() -> None:
    R = downward_grasp(0.0)
    h = hand_angles(R, heading=3.0, previous=[6.0, 0.0, 0.0])
    assert abs(h.angles[0] - 6.0) <= np.pi
    np.testing.assert_allclose(hand_rotation(h.angles, 3.0), R, atol=1e-12)


def test_not_a_rotation_is_refused() -> None:
    with pytest.raises(ParameterError, match="not a rotation"):
        hand_angles(np.diag([1.0, 1.0, -1.0]), 0.0)
    with pytest.raises(ParameterError, match="previous hand angles"):
        hand_angles(np.eye(3), 0.0, previous=[0.0, np.nan, 0.0])
