"""Two bodies joined by an unknown joint, an IMU on each: the joint's type, axis and place.

The joint found from the two IMUs (ADIS16485 noise, 20 s, seeds not used while developing)
against the joint the recording was made with.
"""

from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.apps.identify.rigid_joint import JointFit, identify_chain, identify_joint
from aaria_pin.apps.identify.rigid_joint_motion import UnknownJoint, simulate_jointed_bodies
from aaria_pin.apps.identify.rigid_motion import ImuMount
from aaria_pin.core.imu_presets import imu_preset
from aaria_pin.core.rotations import elementary
from aaria_pin.errors import ParameterError

AXIS = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
POINT = np.array([0.25, 0.05, -0.02])
MOUNT_A = ImuMount("a", elementary(2, 0.4), np.array([0.0, 0.02, 0.01]))
MOUNT_B = ImuMount(
    "b", elementary(0, -1.0) @ elementary(2, 2.0), np.array([0.45, -0.05, 0.03]), rate=250.0
)


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
    assert "not determined" in fit.lines()[3]


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
    run = simulate_jointed_bodies(UnknownJoint("revolute", AXIS, POINT), (MOUNT_A, MOUNT_B), 2.0)
    arrays = {s.name: (s.time, s.values) for s in run.streams}
    late = {"a": arrays["a"], "b": (arrays["b"][0] + 50.0, arrays["b"][1])}
    with pytest.raises(ParameterError, match="share 0 samples") as caught:
        identify_joint(late, "a", "b")
    assert caught.value.parameter == "imu"


def test_a_chain_is_its_joints_in_a_row() -> None:
    run = simulate_jointed_bodies(
        UnknownJoint("revolute", AXIS, POINT), (MOUNT_A, MOUNT_B), 6.0, imu_preset("adis16485"), 56
    )
    fits = identify_chain(run, ["a", "b"])
    assert [(f.imu_a, f.imu_b, f.kind) for f in fits] == [("a", "b", "revolute")]
    assert fits[0].axis_sigma.max() < np.radians(0.05)
    with pytest.raises(ParameterError) as caught:
        identify_chain(run, ["a"])
    assert caught.value.parameter == "imus"
