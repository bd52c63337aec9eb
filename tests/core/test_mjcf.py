"""MJCF export: MuJoCo's sensors and inverse dynamics along our runs equal our IMUs, torques."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import aaria_pin as ap
from aaria_pin.apps.record_model import record_base_motion, record_mjcf, replay_in_mujoco
from aaria_pin.core.export.mjcf_emit import BASE_JOINTS, emit_mjcf, load_mjcf
from aaria_pin.core.export.mjcf_replay import gimbal_xyz_coordinates
from aaria_pin.core.record import ImuMount
from aaria_pin.errors import ModelError, ParameterError

mujoco = pytest.importorskip("mujoco")

RTOL = 1e-9


def assert_same_signals(actual: np.ndarray, expected: np.ndarray) -> None:
    """Equal to RTOL of the largest value of each kind (angular velocity, specific force)."""
    for part in (slice(0, 3), slice(3, 6)):
        scale = float(np.abs(expected[..., part]).max())
        np.testing.assert_allclose(
            actual[..., part], expected[..., part], rtol=RTOL, atol=RTOL * scale
        )


def assert_same_torques(actual: np.ndarray, expected: np.ndarray) -> None:
    scale = float(np.abs(expected).max())
    np.testing.assert_allclose(actual, expected, rtol=RTOL, atol=RTOL * scale)


@pytest.fixture(scope="module")
def fig2_run() -> ap.RunRecord:
    return ap.simulate_run(ap.get_preset("aaria-fig2").table, duration=1.0, noise=False)


@pytest.fixture(scope="module")
def ur5_run() -> ap.RunRecord:
    entry = ap.find_robot("ur5")
    return ap.simulate_urdf_run(
        entry.urdf.read_text(), urdf_dir=entry.urdf.parent, duration=1.0, noise=False
    )


def test_fig2_on_a_moving_base_replays_in_mujoco(fig2_run: ap.RunRecord) -> None:
    xml, skipped = record_mjcf(fig2_run)
    assert skipped == ()
    model = load_mjcf(xml)
    assert model.nsensor == 2 * 14 and model.nq == 6 + 6  # base chain + six modules
    assert model.opt.timestep == 0.01
    imu, tau = replay_in_mujoco(fig2_run, xml)
    assert np.abs(fig2_run.base_pose[:, :3, 3]).max() > 0.01  # the base really moves
    assert_same_signals(imu, fig2_run.imu)
    assert_same_torques(tau, fig2_run.tau)


def test_ur5_on_a_moving_base_replays_in_mujoco(ur5_run: ap.RunRecord) -> None:
    xml, skipped = record_mjcf(ur5_run)
    assert len(skipped) == 7  # the COLLADA visuals; the links show their STL collision meshes
    model = load_mjcf(xml)
    assert model.nmesh == 7 and model.nsensor == 2 * 14
    imu, tau = replay_in_mujoco(ur5_run, xml)
    assert_same_signals(imu, ur5_run.imu)
    assert_same_torques(tau, ur5_run.tau)


def test_the_model_has_pinocchios_mass_and_the_urdf_structure(ur5_run: ap.RunRecord) -> None:
    import pinocchio as pin

    xml, _ = record_mjcf(ur5_run)
    model = load_mjcf(xml)
    pinocchio_model = pin.buildModelFromXML(ur5_run.urdf, pin.JointModelFreeFlyer())
    assert model.body_subtreemass[0] == pytest.approx(pin.computeTotalMass(pinocchio_model))
    # a body per URDF link (fixed ones too) beside MuJoCo's world body
    assert model.nbody == 1 + ur5_run.urdf.count("<link ")
    names = [model.joint(k).name for k in range(model.njnt)]
    assert names == [*BASE_JOINTS, *ur5_run.joint_names]
    kinds = [int(model.jnt_type[k]) for k in range(model.njnt)]
    slide, hinge = int(mujoco.mjtJoint.mjJNT_SLIDE), int(mujoco.mjtJoint.mjJNT_HINGE)
    assert kinds == [slide] * 3 + [hinge] * 9
    assert model.nsite == 14 + 1  # the IMUs and the tool
    assert model.site("tool0").bodyid == model.body("tool0").id
    assert not np.any(model.geom_contype) and not np.any(model.geom_conaffinity)
    assert not np.any(model.dof_armature) and not np.any(model.dof_damping)


def test_an_arm_with_an_empty_module_on_a_fixed_base() -> None:
    table = ap.get_preset("aaria-fig3").table  # module 2 empty: a zero column, no joint
    run = ap.simulate_run(table, duration=0.5, noise=False, base_table=np.zeros((2, 4)))
    xml, _ = record_mjcf(run, moving_base=False)
    assert load_mjcf(xml).nq == 5
    imu, tau = replay_in_mujoco(run, xml)
    assert not np.any(tau[:, 1]) and not np.any(imu[:, 4:6])  # the empty module's slots
    assert_same_signals(imu, run.imu)
    assert_same_torques(tau, run.tau)


def test_gimbal_coordinates_invert_the_gimbal_motion() -> None:
    from gimbal_oracle import gimbal_xyz_motion

    rng = np.random.default_rng(7)
    angles = rng.uniform(-3.0, 3.0, (500, 3))
    angles[:, 1] = rng.uniform(-1.4, 1.4, 500)  # away from the singularity cos b = 0
    rates, accelerations = rng.normal(0, 2, (500, 3)), rng.normal(0, 5, (500, 3))
    R, omega, omega_dot = gimbal_xyz_motion(angles, rates, accelerations)
    got = gimbal_xyz_coordinates(R, omega, omega_dot)
    for value, expected in zip(got, (angles, rates, accelerations), strict=True):
        np.testing.assert_allclose(value, expected, rtol=0, atol=1e-11)


URDF = """<robot name="toy">
  <material name="red"><color rgba="1 0 0 1"/></material>
  <link name="root"/>
  <link name="arm">
    <inertial><origin xyz="0.1 0 0" rpy="0.3 0.2 0.1"/><mass value="2"/>
      <inertia ixx="0.02" ixy="0.001" ixz="0" iyy="0.03" iyz="0" izz="0.04"/></inertial>
    <visual><geometry><cylinder radius="0.02" length="0.2"/></geometry>
      <material name="red"/></visual>
  </link>
  <link name="slider">
    <inertial><mass value="0.5"/><inertia ixx="0.001" iyy="0.001" izz="0.001"/></inertial>
    <visual><origin xyz="0 0 0.05"/><geometry><sphere radius="0.03"/></geometry>
      <material name="blue"><color rgba="0 0 1 1"/></material></visual>
    <visual><geometry><mesh filename="part.dae"/></geometry></visual>
  </link>
  <link name="finger">
    <inertial><mass value="0.1"/><inertia ixx="1e-5" iyy="1e-5" izz="1e-5"/></inertial>
    <visual><geometry><box size="0.02 0.04 0.06"/></geometry></visual>
  </link>
  <joint name="spin" type="continuous"><parent link="root"/><child link="arm"/>
    <axis xyz="0 0.6 0.8"/></joint>
  <joint name="push" type="prismatic"><parent link="arm"/><child link="slider"/>
    <origin xyz="0.2 0 0"/><axis xyz="1 0 0"/>
    <limit lower="-0.1" upper="0.1" effort="10" velocity="1"/></joint>
  <joint name="grip" type="prismatic"><parent link="slider"/><child link="finger"/>
    <axis xyz="0 1 0"/><limit lower="0" upper="0.05" effort="10" velocity="1"/>
    <mimic joint="push" multiplier="0.5" offset="0.01"/></joint>
</robot>
"""


def test_joint_kinds_shapes_colours_and_mimic_joints() -> None:
    mounts = (
        ImuMount("imu_push", "push", np.eye(4)),  # a joint's frame: its child link
        ImuMount("imu_none", "", np.zeros((4, 4))),  # an empty slot: no site
    )
    xml, skipped = emit_mjcf(URDF, mounts, moving_base=False, gravity=(0, 0, -1.62), rate=250)
    assert skipped == ("part.dae",)
    model = load_mjcf(xml)
    assert model.opt.timestep == 0.004 and tuple(model.opt.gravity) == (0, 0, -1.62)
    assert model.nsensor == 2 and model.site("imu_push").bodyid == model.body("slider").id
    spin, push = model.joint("spin"), model.joint("push")
    assert spin.type[0] == mujoco.mjtJoint.mjJNT_HINGE and not spin.limited[0]
    np.testing.assert_allclose(spin.axis, [0, 0.6, 0.8])
    assert push.type[0] == mujoco.mjtJoint.mjJNT_SLIDE
    np.testing.assert_array_equal(push.range, [-0.1, 0.1])
    assert model.neq == 1 and list(model.eq_data[0][:2]) == [0.01, 0.5]
    types = sorted(int(t) for t in model.geom_type)
    assert types == sorted(
        int(getattr(mujoco.mjtGeom, f"mjGEOM_{kind}")) for kind in ("CYLINDER", "SPHERE", "BOX")
    )
    colours = {
        model.body(int(body)).name: tuple(rgba)
        for body, rgba in zip(model.geom_bodyid, model.geom_rgba, strict=True)
    }
    assert colours == {"arm": (1, 0, 0, 1), "slider": (0, 0, 1, 1), "finger": (0.7, 0.7, 0.7, 1)}
    # the inertia written in the link frame: MuJoCo's principal moments are the URDF's
    arm = model.body("arm")
    moments = np.linalg.eigvalsh([[0.02, 0.001, 0], [0.001, 0.03, 0], [0, 0, 0.04]])
    np.testing.assert_allclose(np.sort(arm.inertia), moments, rtol=1e-12)
    np.testing.assert_allclose(arm.ipos, [0.1, 0, 0])


SPHERICAL = """<robot name="ball">
  <link name="root"><inertial><mass value="3"/>
    <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  <link name="virtual_1"/>
  <link name="virtual_2"/>
  <link name="bob">
    <inertial><origin xyz="0 0 -0.5"/><mass value="2"/>
      <inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>
  </link>
  <joint name="z" type="continuous"><parent link="root"/><child link="virtual_1"/>
    <axis xyz="0 0 1"/></joint>
  <joint name="x" type="continuous"><parent link="virtual_1"/><child link="virtual_2"/>
    <axis xyz="1 0 0"/></joint>
  <joint name="y" type="continuous"><parent link="virtual_2"/><child link="bob"/>
    <axis xyz="0 1 0"/></joint>
</robot>
"""


def test_massless_virtual_links_and_a_point_mass_get_negligible_inertia() -> None:
    from aaria_pin.core.export.mjcf_bodies import NEGLIGIBLE_INERTIA, NEGLIGIBLE_MASS

    # MuJoCo refuses moving bodies without mass or moments: the two virtual links of a
    # spherical joint made of hinges, and a point mass (its moments are all zero)
    with pytest.raises(ValueError, match="mass and inertia of moving bodies"):
        mujoco.MjModel.from_xml_string(SPHERICAL)  # MuJoCo's own URDF import
    model = load_mjcf(emit_mjcf(SPHERICAL, (), moving_base=False)[0])
    for name in ("virtual_1", "virtual_2"):
        assert model.body(name).mass[0] == NEGLIGIBLE_MASS
    assert model.body("bob").mass[0] == 2.0
    np.testing.assert_allclose(model.body("bob").inertia, NEGLIGIBLE_INERTIA, rtol=1e-12)
    # the pendulum's gravity torque about y at 90°: m g l = 2 · 9.81 · 0.5, to 1e-9
    data = mujoco.MjData(model)
    data.qpos[:] = [0.0, 0.0, np.pi / 2]
    mujoco.mj_inverse(model, data)
    assert data.qfrc_inverse[2] == pytest.approx(2 * 9.81 * 0.5, rel=1e-9)


UNBALANCED = URDF.replace(
    '<inertia ixx="0.02" ixy="0.001" ixz="0" iyy="0.03" iyz="0" izz="0.04"/>',
    '<inertia ixx="0.001" iyy="0.001" izz="0.01"/>',
)


def test_inertias_mujoco_refuses_are_balanced_only_when_asked() -> None:
    with pytest.raises(ModelError, match="A \\+ B >= C"):
        load_mjcf(emit_mjcf(UNBALANCED, ())[0])
    model = load_mjcf(emit_mjcf(UNBALANCED, (), balance_inertia=True)[0])
    A, B, C = sorted(model.body("arm").inertia)  # raised: A + B >= C now, the trace kept
    assert A + B >= C and A + B + C == pytest.approx(0.012, rel=1e-12)


def test_bad_inputs_name_what_is_wrong(fig2_run: ap.RunRecord) -> None:
    with pytest.raises(ModelError, match="parent frame 'nowhere' is not in the URDF"):
        emit_mjcf(URDF, (ImuMount("imu", "nowhere", np.eye(4)),))
    with pytest.raises(ModelError, match="has the name of a base joint"):
        emit_mjcf(URDF.replace('"spin"', '"base_rx"'), ())
    with pytest.raises(ParameterError, match="rate is 0"):
        emit_mjcf(URDF, (), rate=0.0)
    from dataclasses import replace

    other = replace(fig2_run, tables={"senSenB": np.array([[0.1, 0, 1, 0], [0, 0, 1, 0]])})
    with pytest.raises(ParameterError, match="does not give its stored base_pose"):
        record_base_motion(other)
    with pytest.raises(ModelError, match="MuJoCo cannot compile"):
        load_mjcf("<mujoco><worldbody><body/></mujoco>")


def test_a_written_model_loads_from_its_file(tmp_path: Path, ur5_run: ap.RunRecord) -> None:
    path = tmp_path / "ur5.xml"
    path.write_text(record_mjcf(ur5_run)[0])
    model = mujoco.MjModel.from_xml_path(str(path))
    assert model.nsensor == 28 and model.sensor("imu_tool_accelerometer").dim[0] == 3


def test_auto_balance_balances_only_what_mujoco_refuses() -> None:
    with pytest.warns(UserWarning, match="break A \\+ B >= C \\('arm'"):
        text, _ = emit_mjcf(UNBALANCED, (), balance_inertia="auto")
    assert 'balanceinertia="true"' in text
    A, B, C = sorted(load_mjcf(text).body("arm").inertia)
    assert A + B >= C and A + B + C == pytest.approx(0.012, rel=1e-12)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a model MuJoCo accepts: written as asked, no warning
        assert emit_mjcf(URDF, (), balance_inertia="auto") == emit_mjcf(URDF, ())


def test_a_moving_base_replay_needs_the_base_motion(fig2_run: ap.RunRecord) -> None:
    from aaria_pin.core.export.mjcf_replay import replay_motion

    xml, _ = record_mjcf(fig2_run)
    with pytest.raises(ParameterError, match="no base motion is given") as info:
        replay_motion(fig2_run, xml)
    assert info.value.parameter == "base"
