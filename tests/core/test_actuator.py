"""The actuator model: armature, the friction formula and its limits, torque limits."""

from __future__ import annotations

import math

import numpy as np
import pytest

import aaria_pin as ap
from aaria_pin.core.actuator import (
    ActuatorModel,
    actuator_torques,
    armature,
    friction,
    model_effort_limits,
    torque_limits,
)
from aaria_pin.errors import ParameterError


def test_armature_is_the_rotor_inertia_reflected_through_the_gear() -> None:
    model = ActuatorModel(rotor_inertia=[1e-4, 2e-5, 3e-6], gear_ratio=[100.0, 50.0, 1.0])
    np.testing.assert_allclose(armature(model, 3), [1.0, 0.05, 3e-6], rtol=1e-15)
    assert armature(ActuatorModel(rotor_inertia=2e-4, gear_ratio=10.0), 4).tolist() == [0.02] * 4
    assert not np.any(armature(ActuatorModel(), 2))  # off by default


def test_viscous_and_smooth_coulomb_friction_by_hand() -> None:
    model = ActuatorModel(viscous=[0.5, 2.0], coulomb=[3.0, 1.0], coulomb_velocity=[0.01, 0.2])
    qd = np.array([[0.01, -0.2], [0.0, 0.0], [-0.03, 1.0]])
    expected = np.array(
        [
            [0.5 * 0.01 + 3.0 * math.tanh(1.0), 2.0 * -0.2 + 1.0 * math.tanh(-1.0)],
            [0.0, 0.0],
            [0.5 * -0.03 + 3.0 * math.tanh(-3.0), 2.0 + math.tanh(5.0)],
        ]
    )
    np.testing.assert_allclose(friction(model, qd), expected, rtol=1e-14)
    # the motor adds it: the sign of the velocity (friction opposes the motion), 0 at rest
    v = np.linspace(-2.0, 2.0, 401)[:, None] * np.ones(2)
    f = friction(model, v)
    assert np.all(f * v >= 0) and np.array_equal(friction(model, -v), -f)


def test_coulomb_tends_to_the_sign_as_the_smoothing_velocity_vanishes() -> None:
    qd = np.array([[-1.0, -1e-3, 0.0, 1e-3, 0.5]]).T * np.ones(1)
    errors = []
    for smooth in (1e-2, 1e-4, 1e-6):
        f = friction(ActuatorModel(coulomb=2.0, coulomb_velocity=smooth), qd)[:, 0]
        errors.append(np.abs(f - 2.0 * np.sign(qd[:, 0])).max())
    assert errors[0] > errors[1] > errors[2] and errors[2] < 1e-12
    # a tenth of a smoothing velocity away from rest: still near linear, slope coulomb/v_s
    f = friction(ActuatorModel(coulomb=2.0, coulomb_velocity=0.01), np.array([[1e-4]]))
    assert f[0, 0] == pytest.approx(2.0 * 1e-4 / 0.01, rel=1e-4)


def test_stribeck_adds_the_breakaway_torque_near_rest() -> None:
    model = ActuatorModel(
        viscous=0.0, coulomb=1.5, coulomb_velocity=1e-7, stribeck_torque=0.8, stribeck_velocity=0.1
    )
    qd = np.array([1e-5, 0.1, 0.2, 5.0, -1e-5])[:, None]
    f = friction(model, qd)[:, 0]
    e = math.exp
    expected = [1.5 + 0.8 * e(-1e-8), 1.5 + 0.8 * e(-1.0), 1.5 + 0.8 * e(-4.0), 1.5, -1.5 - 0.8]
    np.testing.assert_allclose(f, expected, rtol=1e-7)
    speeds = np.linspace(1e-5, 1.0, 1000)[:, None]
    curve = friction(model, speeds)[:, 0]
    assert curve[0] == curve.max() and np.all(np.diff(curve) <= 0)  # the peak at qd -> 0+


def test_actuator_torques_over_a_trajectory() -> None:
    model = ActuatorModel(rotor_inertia=1e-4, gear_ratio=[100.0, 20.0], viscous=1.0, coulomb=0.5)
    rng = np.random.default_rng(3)
    qd, qdd = rng.normal(size=(50, 2)), rng.normal(size=(50, 2))
    torques = actuator_torques(model, qd, qdd)
    np.testing.assert_allclose(torques.armature, qdd * [1.0, 0.04], rtol=1e-15)
    np.testing.assert_allclose(torques.friction, qd + 0.5 * np.tanh(qd / 0.01), rtol=1e-15)


def test_a_per_joint_value_of_another_count_names_the_field() -> None:
    with pytest.raises(ParameterError, match="viscous has 3 values") as info:
        friction(ActuatorModel(viscous=[1.0, 2.0, 3.0]), np.zeros((4, 2)))
    assert info.value.parameter == "viscous"
    with pytest.raises(ParameterError) as info:
        torque_limits(ActuatorModel(torque_limit=[1.0, 2.0]), [5.0, 5.0, 5.0])
    assert info.value.parameter == "torque_limit"


def test_torque_limits_default_to_the_models_effort_limit() -> None:
    import pinocchio as pin

    from aaria_pin.core.model import RobotModel

    entry = ap.find_robot("ur5")
    ur5 = pin.buildModelFromUrdf(str(entry.urdf))  # effort 150 N·m (shoulder, elbow), 28 (wrist)
    moving = pin.buildModelFromUrdf(str(entry.urdf), pin.JointModelFreeFlyer())
    for model, base in ((ur5, False), (moving, True)):
        robot = RobotModel(model, None, base, "base_link", "tool0", ())
        assert model_effort_limits(robot).tolist() == [150.0] * 3 + [28.0] * 3
    fixed = RobotModel(ur5, None, False, "base_link", "tool0", ())
    # a record with an empty column 1 (an Aaria arm's empty module): no limit there
    spread = model_effort_limits(fixed, [0, 2, 3, 4, 5, 6], 8)
    assert spread.tolist() == [150.0, np.inf, 150.0, 150.0, 28.0, 28.0, 28.0, np.inf]
    motor = ActuatorModel(torque_limit=[0.0, 0.0, 100.0, 0.0, 20.0, 0.0, 30.0, 0.0])
    assert torque_limits(motor, spread).tolist() == [
        150.0,
        np.inf,
        100.0,
        150.0,
        20.0,
        28.0,
        30.0,
        np.inf,
    ]
