"""Two bodies joined by an unknown joint, an IMU on each: the joint's type, axis and place.

The simulated body 2 is checked against numerical derivatives of its pose; the joint found from
the two IMUs (ADIS16485 noise, 20 s, seeds not used while developing) against the joint the
recording was made with.
"""

from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.apps.identify.rigid_joint import (
    JointFit,
    UnknownJoint,
    _axis_rotation,
    _body_two_signals,
    _joint_motion,
    identify_joint,
    simulate_jointed_bodies,
)
from aaria_pin.apps.identify.rigid_motion import GRAVITY, ImuMount, hand_motion
from aaria_pin.core.imu_presets import imu_preset
from aaria_pin.core.rotations import elementary
from aaria_pin.errors import ParameterError

AXIS = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
POINT = np.array([0.25, 0.05, -0.02])
MOUNT_A = ImuMount("a", elementary(2, 0.4), np.array([0.0, 0.02, 0.01]))
MOUNT_B = ImuMount(
    "b", elementary(0, -1.0) @ elementary(2, 2.0), np.array([0.45, -0.05, 0.03]), rate=250.0
)


@pytest.mark.parametrize("kind", ["revolute", "prismatic"])
def test_body_two_is_its_pose_s_derivatives(kind: str) -> None:
    motion, seed, step = hand_motion(7), 7, 1e-3
    joint = UnknownJoint(kind, AXIS, POINT, 1.0 if kind == "revolute" else 0.1)
    t = np.linspace(2.0, 8.0, 31)

    def pose(at: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # IMU B's world position, R_WI
        state = motion.state(at)
        q = _joint_motion(seed, joint.rate, at)[0]
        x = MOUNT_B.position
        if kind == "revolute":
            turn = _axis_rotation(AXIS, q)
            y = POINT + np.einsum("nij,j->ni", turn, x - POINT)
        else:
            turn, y = np.broadcast_to(np.eye(3), (at.size, 3, 3)), x + q[:, None] * AXIS
        base = motion._channels(at, 0)[:, 3:]
        return base + np.einsum("nij,nj->ni", state.rotation, y), state.rotation @ turn @ (
            MOUNT_B.rotation
        )

    (before, r0), (here, rotation), (after, r1) = pose(t - step), pose(t), pose(t + step)
    accel = (after - 2 * here + before) / step**2
    force = np.einsum("nji,nj->ni", rotation, accel - GRAVITY)
    spin = np.einsum("nji,njk->nik", rotation, (r1 - r0) / (2 * step))
    omega = np.stack([spin[:, 2, 1], spin[:, 0, 2], spin[:, 1, 0]], axis=1)
    signals = _body_two_signals(motion, joint, MOUNT_B, t, seed)
    assert np.abs(signals[:, :3] - omega).max() < 3e-3  # of ~3 rad/s, the difference's error
    assert np.abs(signals[:, 3:] - force).max() < 5e-3  # of ~10 m/s²


def _joint_errors(fit: JointFit) -> tuple[float, float]:
    """Axis angle error [deg] in A's and B's frames (the sense is free)."""
    truth_a, truth_b = MOUNT_A.rotation.T @ AXIS, MOUNT_B.rotation.T @ AXIS
    return (
        float(np.degrees(np.arccos(min(1.0, abs(fit.axis_a @ truth_a))))),
        float(np.degrees(np.arccos(min(1.0, abs(fit.axis_b @ truth_b))))),
    )


@pytest.mark.parametrize("seed", [51, 52])
def test_a_revolute_joint_s_axis_and_place(seed: int) -> None:
    joint = UnknownJoint("revolute", AXIS, POINT)
    run = simulate_jointed_bodies(
        joint, (MOUNT_A, MOUNT_B), model=imu_preset("adis16485"), seed=seed
    )
    fit = identify_joint(run, "a", "b")
    assert fit.kind == "revolute"
    assert max(_joint_errors(fit)) < 0.05
    assert np.sign(fit.axis_a @ MOUNT_A.rotation.T @ AXIS) == np.sign(
        fit.axis_b @ MOUNT_B.rotation.T @ AXIS
    )  # one physical axis, one sense on both sides
    for point, mount in ((fit.point_a, MOUNT_A), (fit.point_b, MOUNT_B)):
        axis = mount.rotation.T @ AXIS
        error = point - mount.rotation.T @ (POINT - mount.position)
        assert np.linalg.norm(error - (error @ axis) * axis) < 1e-3  # across the axis ≤ 1 mm
    assert "not determined" in fit.lines()[2]


@pytest.mark.parametrize("seed", [53, 54])
def test_a_prismatic_joint_s_axis(seed: int) -> None:
    joint = UnknownJoint("prismatic", AXIS, np.zeros(3), rate=0.1)
    run = simulate_jointed_bodies(
        joint, (MOUNT_A, MOUNT_B), model=imu_preset("adis16485"), seed=seed
    )
    fit = identify_joint(run, "a", "b")
    assert fit.kind == "prismatic"
    assert max(_joint_errors(fit)) < 0.1


def test_a_joint_that_does_not_move_is_rigid() -> None:
    joint = UnknownJoint("revolute", AXIS, POINT, rate=0.0)
    run = simulate_jointed_bodies(joint, (MOUNT_A, MOUNT_B), model=imu_preset("adis16485"), seed=55)
    fit = identify_joint(run, "a", "b")
    assert fit.kind == "rigid"
    expected = MOUNT_A.rotation.T @ (MOUNT_B.position - MOUNT_A.position)
    assert np.linalg.norm(fit.point_a - expected) < 1e-3
    assert fit.lines()[1].startswith("  origin of b in a [mm]:")


def test_bad_joint_and_inputs_are_one_line() -> None:
    with pytest.raises(ParameterError) as caught:
        simulate_jointed_bodies(UnknownJoint("spherical", AXIS, POINT), (MOUNT_A, MOUNT_B))
    assert caught.value.parameter == "kind"
    run = simulate_jointed_bodies(UnknownJoint("revolute", AXIS, POINT), (MOUNT_A, MOUNT_B), 2.0)
    arrays = {s.name: (s.time, s.values) for s in run.streams}
    late = {"a": arrays["a"], "b": (arrays["b"][0] + 50.0, arrays["b"][1])}
    with pytest.raises(ParameterError, match="share 0 samples") as caught:
        identify_joint(late, "a", "b")
    assert caught.value.parameter == "imu"
