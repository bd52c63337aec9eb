"""The hand-carried rigid body of the rigid-pair fit and its IMUs' signals (issue 26).

The closed-form angular velocity and accelerations are checked against numerical derivatives of
the rotation and of the IMU's world position; the recording against the exact signals.
"""

from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.apps.identify.rigid_motion import (
    GRAVITY,
    ImuMount,
    default_pair,
    exact_imu_signals,
    hand_motion,
    relative_pose,
    simulate_rigid_body,
)
from aaria_pin.core.imu_presets import imu_preset
from aaria_pin.core.rotations import elementary
from aaria_pin.errors import ParameterError

STEP = 1e-4


def _unskew(m: np.ndarray) -> np.ndarray:
    return np.stack([m[:, 2, 1], m[:, 0, 2], m[:, 1, 0]], axis=1)


def test_angular_velocity_and_acceleration_are_the_rotation_s_derivatives() -> None:
    motion = hand_motion(5)
    t = np.linspace(1.0, 9.0, 801)
    state = motion.state(t)
    before, after = motion.state(t - STEP), motion.state(t + STEP)
    rotation_rate = (after.rotation - before.rotation) / (2 * STEP)
    omega = _unskew(np.einsum("nji,njk->nik", state.rotation, rotation_rate))
    alpha = (after.angular_velocity - before.angular_velocity) / (2 * STEP)
    assert np.abs(omega - state.angular_velocity).max() < 1e-5
    assert np.abs(alpha - state.angular_acceleration).max() < 1e-4  # of ~20 rad/s²


def test_the_motion_is_hand_like() -> None:
    motion = hand_motion(2, angular_rate=1.5, travel=0.5)
    state = motion.state(np.linspace(0.0, 20.0, 4001))
    rms = np.sqrt(np.mean(state.angular_velocity**2, axis=0))
    assert np.all((rms > 0.7) & (rms < 3.0))
    assert np.all(motion.frequency >= 0.2) and np.all(motion.frequency <= 3.0)
    assert np.all(np.sum(np.abs(motion.amplitude[3:]), axis=1) <= 0.5 + 1e-12)


def test_an_axis_at_rate_zero_does_not_turn() -> None:
    state = hand_motion(1, angular_rate=(1.0, 0.0, 0.0)).state(np.linspace(0.0, 5.0, 101))
    assert np.abs(state.angular_velocity[:, :2]).max() == 0.0


def test_imu_signals_are_its_world_motion_in_its_axes() -> None:
    motion = hand_motion(3)
    turned = elementary(0, 0.4) @ elementary(2, -1.1)
    mount = ImuMount("m", turned, np.array([0.2, -0.1, 0.05]))
    t = np.linspace(2.0, 8.0, 61)

    def place(times: np.ndarray) -> np.ndarray:  # the IMU's world position less the body's
        return np.asarray(motion.state(times).rotation @ mount.position)

    lever = (place(t + STEP) - 2 * place(t) + place(t - STEP)) / STEP**2
    state = motion.state(t)
    accel = state.acceleration + lever - GRAVITY
    imu_rotation = state.rotation @ turned  # R_WI
    expected_force = np.einsum("nji,nj->ni", imu_rotation, accel)
    expected_omega = state.angular_velocity @ turned
    signals = exact_imu_signals(motion, mount, t)
    assert np.abs(signals[:, :3] - expected_omega).max() < 1e-12
    assert np.abs(signals[:, 3:] - expected_force).max() < 1e-4


def test_a_recording_has_each_imu_at_its_rate_start_and_offset() -> None:
    a, b = default_pair(rate_b=250.0, time_offset=0.004)
    motion = hand_motion(4)
    run = simulate_rigid_body([a, b], duration=2.0, motion=motion)
    stream_b = run.stream("imu_b")
    assert stream_b.time[0] == pytest.approx(0.013)
    assert stream_b.rate == pytest.approx(250.0)
    assert run.stream("imu_a").rate == pytest.approx(200.0)
    expected = exact_imu_signals(motion, b, stream_b.time + 0.004)
    np.testing.assert_array_equal(stream_b.values, expected)


def test_noise_is_the_model_s() -> None:
    a, b = default_pair()
    model = imu_preset("adis16485")
    noisy = simulate_rigid_body([a, b], duration=5.0, model=model, seed=9)
    exact = simulate_rigid_body([a, b], duration=5.0, seed=9)
    error = noisy.stream("imu_a").values - exact.stream("imu_a").values
    white = np.array([model.gyro.noise_density, model.accel.noise_density]) * np.sqrt(100.0)
    measured = np.std(error, axis=0).reshape(2, 3).mean(axis=1)
    np.testing.assert_allclose(measured, white, rtol=0.1)


def test_relative_pose_is_b_in_a() -> None:
    a = ImuMount("a", elementary(2, 0.5), np.array([1.0, 0.0, 0.0]), time_offset=0.001)
    b = ImuMount("b", elementary(2, 0.5 + np.pi / 2), np.array([1.0, 2.0, 0.0]), time_offset=0.003)
    rotation, position, offset = relative_pose(a, b)
    np.testing.assert_allclose(rotation, elementary(2, np.pi / 2), atol=1e-15)
    np.testing.assert_allclose(position, [2 * np.sin(0.5), 2 * np.cos(0.5), 0.0], atol=1e-15)
    assert offset == pytest.approx(0.002)


def test_bad_motion_and_duration_are_one_line() -> None:
    with pytest.raises(ParameterError, match="allowed") as caught:
        hand_motion(0, band=(3.0, 0.2))
    assert caught.value.parameter == "band"
    with pytest.raises(ParameterError) as caught:
        simulate_rigid_body(default_pair(), duration=0.0)
    assert caught.value.parameter == "duration"
