"""The simulated pair of bodies joined by a joint: body 2's IMU against its pose's derivatives."""

from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.apps.identify.rigid_joint_motion import (
    UnknownJoint,
    _axis_rotation,
    _body_two_signals,
    _joint_motion,
    simulate_jointed_bodies,
)
from aaria_pin.apps.identify.rigid_motion import GRAVITY, ImuMount, hand_motion
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


def test_the_recording_has_both_imus_at_their_rates() -> None:
    run = simulate_jointed_bodies(UnknownJoint("revolute", AXIS, POINT), (MOUNT_A, MOUNT_B), 2.0)
    assert [s.name for s in run.streams] == ["a", "b"]
    assert run.stream("b").rate == pytest.approx(250.0)
    assert run.stream("a").values.shape == (401, 6)


def test_an_unknown_joint_kind_is_one_line() -> None:
    with pytest.raises(ParameterError) as caught:
        simulate_jointed_bodies(UnknownJoint("spherical", AXIS, POINT), (MOUNT_A, MOUNT_B))
    assert caught.value.parameter == "kind"
