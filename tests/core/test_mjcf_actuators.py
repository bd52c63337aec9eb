"""Actuators in MJCF: MuJoCo's inverse dynamics of an exported run give the motor torque."""

from __future__ import annotations

import re
from dataclasses import replace

import numpy as np
import pytest

import aaria_pin as ap
from aaria_pin.apps.record_model import record_base_motion, record_mjcf
from aaria_pin.core.actuator import ActuatorModel, actuator_torques
from aaria_pin.core.export.mjcf_emit import emit_mjcf, load_mjcf
from aaria_pin.core.export.mjcf_replay import replay_motion
from aaria_pin.core.joint_sensors import model_attributes
from aaria_pin.errors import ParameterError

mujoco = pytest.importorskip("mujoco")

RTOL = 1e-9

ROTOR = np.array([1e-4, 2e-4, 1e-4, 3e-5, 3e-5, 2e-5])
RATIO = np.array([100.0, 120.0, 100.0, 80.0, 80.0, 50.0])
VISCOUS = np.array([2.0, 2.5, 1.5, 0.5, 0.4, 0.3])
COULOMB = np.array([3.0, 3.5, 2.0, 1.0, 0.8, 0.6])
ACTUATOR = ActuatorModel(
    rotor_inertia=tuple(ROTOR),
    gear_ratio=tuple(RATIO),
    viscous=tuple(VISCOUS),
    coulomb=tuple(COULOMB),
    stribeck_torque=0.4,
    torque_limit=(0.0, 0.0, 0.0, 20.0, 20.0, 20.0),
)


def with_actuator(record: ap.RunRecord, model: ActuatorModel) -> ap.RunRecord:
    """The run with its actuator's tables and attribute, as the engine records them."""
    torques = actuator_torques(model, record.qd, record.qdd)
    motor = record.tau + torques.armature + torques.friction
    tables = {"tau_armature": torques.armature, "tau_friction": torques.friction}
    attributes = {**record.attributes, "actuator": model_attributes(model)}
    return replace(record, tables={**record.tables, **tables, "tau_motor": motor},
                   attributes=attributes)  # fmt: skip


def assert_same_torques(actual: np.ndarray, expected: np.ndarray) -> None:
    scale = float(np.abs(expected).max())
    np.testing.assert_allclose(actual, expected, rtol=RTOL, atol=RTOL * scale)


@pytest.fixture(scope="module")
def ur5_run() -> ap.RunRecord:
    entry = ap.find_robot("ur5")
    run = ap.simulate_urdf_run(
        entry.urdf.read_text(), urdf_dir=entry.urdf.parent, duration=0.5, noise=False,
        moving_base=False,
    )  # fmt: skip
    return with_actuator(run, ACTUATOR)


@pytest.fixture(scope="module")
def fig2_run() -> ap.RunRecord:
    table = ap.get_preset("aaria-fig2").table  # a prismatic joint 1 and 5: N, kg, N·s/m
    run = ap.simulate_run(table, duration=0.5, noise=False, base_table=np.zeros((2, 4)))
    return with_actuator(run, ACTUATOR)


@pytest.mark.parametrize("name", ["ur5_run", "fig2_run"])
def test_mujoco_inverse_dynamics_give_the_motor_torque(
    name: str, request: pytest.FixtureRequest
) -> None:
    run: ap.RunRecord = request.getfixturevalue(name)
    xml, _ = record_mjcf(run, moving_base=False)
    imu, tau = replay_motion(run, xml)  # constraints (the friction loss) off
    expected = run.tau + ROTOR * RATIO**2 * run.qdd + VISCOUS * run.qd
    assert np.abs(ROTOR * RATIO**2 * run.qdd).max() > 0.1 and np.abs(run.qd).min() < 0.1
    assert_same_torques(tau, expected)
    np.testing.assert_allclose(imu, run.imu, atol=1e-9 * np.abs(run.imu).max())  # unchanged
    # the record's own tables say the same: tau_motor less the Coulomb part
    coulomb = run.tables["tau_friction"] - VISCOUS * run.qd
    assert_same_torques(tau, run.tables["tau_motor"] - coulomb)


def test_saturated_friction_loss_is_coulomb_against_the_motion(ur5_run: ap.RunRecord) -> None:
    xml, _ = record_mjcf(ur5_run, moving_base=False)
    _, without = replay_motion(ur5_run, xml)
    _, with_friction = replay_motion(ur5_run, xml, frictionloss=True)
    loss = with_friction - without  # +frictionloss·sign(qd) once MuJoCo's constraint saturates
    qd = ur5_run.qd
    fast = np.abs(qd) > 0.05  # MuJoCo's soft constraint saturates away from rest
    assert fast.mean() > 0.9 and np.any(qd[fast] < 0) and np.any(qd[fast] > 0)
    np.testing.assert_allclose(loss[fast], (COULOMB * np.sign(qd))[fast], atol=1e-9)
    # our smooth Coulomb term there is within coulomb·(1 - tanh(|qd|/v_s)) of MuJoCo's
    smooth = actuator_torques(replace(ACTUATOR, viscous=0.0, stribeck_torque=0.0), qd, qd)
    bound = COULOMB * (1 - np.tanh(np.abs(qd) / ACTUATOR.coulomb_velocity)) + 1e-12
    assert np.all(np.abs(smooth.friction - loss)[fast] <= bound[fast])


def test_the_model_names_each_term_as_mujoco_does(ur5_run: ap.RunRecord) -> None:
    xml, _ = record_mjcf(ur5_run, moving_base=False)
    model = load_mjcf(xml)
    np.testing.assert_allclose(model.dof_armature, ROTOR * RATIO**2, rtol=1e-15)
    assert model.dof_damping.tolist() == VISCOUS.tolist()
    assert model.dof_frictionloss.tolist() == COULOMB.tolist()
    # the limit: the motor's, or the URDF's effort (150 and 28 N·m) where the motor's is 0
    assert model.jnt_actfrclimited.tolist() == [1] * 6
    assert model.jnt_actfrcrange[:, 1].tolist() == [150.0, 150.0, 150.0, 20.0, 20.0, 20.0]
    assert np.array_equal(model.jnt_actfrcrange[:, 0], -model.jnt_actfrcrange[:, 1])
    comment = next(line for line in xml.splitlines() if "not MuJoCo terms" in line)
    assert "coulomb_velocity = 0.01, stribeck_torque = 0.4, stribeck_velocity = 0.1" in comment
    assert "tanh" in comment and "Stribeck" in comment and xml.isascii()


def test_a_moving_base_and_an_empty_module_keep_the_record_order() -> None:
    table = ap.get_preset("aaria-fig3").table  # module 2 empty: a zero column, no joint
    run = ap.simulate_run(table, duration=0.3, noise=False)
    values = np.arange(1.0, 7.0)  # one per record column, the empty one's (2.0) unused
    model = ActuatorModel(rotor_inertia=1e-4, gear_ratio=100.0, viscous=tuple(values))
    run = with_actuator(run, model)
    xml, _ = record_mjcf(run)
    compiled = load_mjcf(xml)
    assert compiled.dof_damping[6:].tolist() == [1.0, 3.0, 4.0, 5.0, 6.0]
    assert not np.any(compiled.dof_armature[:6]) and not np.any(compiled.dof_damping[:6])
    _, tau = replay_motion(run, xml, record_base_motion(run))
    expected = run.tau + 1.0 * run.qdd + values * run.qd
    expected[:, 1] = 0.0
    assert_same_torques(tau, expected)


URDF = """<robot name="one">
  <link name="base"/>
  <link name="arm"><inertial><mass value="1"/><origin xyz="0.1 0 0"/>
    <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.002"/></inertial></link>
  <link name="hand"><inertial><mass value="0.5"/>
    <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
  <joint name="spin" type="continuous"><parent link="base"/><child link="arm"/>
    <axis xyz="0 0 1"/></joint>
  <joint name="push" type="prismatic"><parent link="arm"/><child link="hand"/>
    <axis xyz="1 0 0"/><limit lower="0" upper="0.2" effort="40" velocity="1"/></joint>
</robot>"""


def test_without_an_actuator_the_model_is_as_before() -> None:
    plain, _ = emit_mjcf(URDF, (), moving_base=False)
    assert emit_mjcf(URDF, (), moving_base=False, actuator=None)[0] == plain
    model = ActuatorModel(viscous=[0.5, 2.0], coulomb=1.0)
    actuated, _ = emit_mjcf(URDF, (), moving_base=False, actuator=model)
    # the actuator adds its attributes to each joint and one comment line, nothing else
    stripped = re.sub(
        r' armature="[^"]*" damping="[^"]*" frictionloss="[^"]*"'
        r'( actuatorfrclimited="true" actuatorfrcrange="[^"]*")?(?=/>)',
        "",
        actuated,
    )
    assert [line for line in stripped.splitlines() if "not MuJoCo terms" not in line] == (
        plain.splitlines()
    )
    # the default joint order is the URDF's; the continuous joint has no effort limit
    compiled = load_mjcf(actuated)
    assert compiled.dof_damping.tolist() == [0.5, 2.0]
    assert compiled.jnt_actfrclimited.tolist() == [0, 1]
    assert compiled.jnt_actfrcrange[1].tolist() == [-40.0, 40.0]


def test_per_joint_values_must_match_the_joints() -> None:
    with pytest.raises(ParameterError, match="coulomb has 3 values") as info:
        emit_mjcf(URDF, (), actuator=ActuatorModel(coulomb=[1.0, 2.0, 3.0]))
    assert info.value.parameter == "coulomb"
    names = ("push", "spin", "empty")  # another order, and a name the URDF has not
    model = ActuatorModel(viscous=[1.0, 2.0, 3.0])
    text, _ = emit_mjcf(URDF, (), moving_base=False, actuator=model, joint_names=names)
    assert load_mjcf(text).dof_damping.tolist() == [2.0, 1.0]
