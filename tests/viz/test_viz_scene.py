"""The scene of an arm (solids and frames on named frames) and the poses drawn from runs."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from aaria_pin.aaria.dh_robot import build_dh_robot
from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.apps.wrist.run import simulate_wrist, write_wrist_run
from aaria_pin.errors import InputFileError, ParameterError
from aaria_pin.files.runfile import write_run
from aaria_pin.viz._model_source import load_model_run
from aaria_pin.viz.scene import (
    WORLD,
    box_solid,
    cylinder_solid,
    one_axis_joint,
    posed_geometry,
    scene_from_dh_robot,
    scene_from_model,
)
from aaria_pin.viz.sources import load_run_view, run_kind, sample_at, table_view


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("runs")
    record = simulate_run(get_preset("aaria-fig3").table, duration=1.0, rate=50.0, noise=False)
    aaria, mat = write_run(folder / "fig3.h5", record), write_run(folder / "fig3.mat", record)
    wrist = simulate_wrist(np.radians([60.0, 45.0, -30.0]), start=0.2, rate=50.0)
    return {
        "aaria": aaria,
        "mat": mat,
        "wrist": write_wrist_run(folder / "wrist.h5", wrist),
        "wrist_mat": write_wrist_run(folder / "wrist.mat", wrist),
        "record": aaria,
    }


def test_box_and_cylinder_meshes_have_their_dimensions() -> None:
    T = np.eye(4)
    T[:3, 3] = (1.0, 2.0, 3.0)
    box = box_solid("f", T, (0.4, 0.2, 0.1), "link")
    assert np.allclose(box.vertices.max(0) - box.vertices.min(0), (0.4, 0.2, 0.1))
    assert np.allclose(box.vertices.mean(0), (1.0, 2.0, 3.0))
    assert box.faces.shape == (6, 4)
    cylinder = cylinder_solid("f", np.eye(4), 0.05, 0.3, "joint")
    radial = np.linalg.norm(cylinder.vertices[:-2, :2], axis=1)
    assert np.allclose(radial, 0.05)
    assert np.allclose(np.abs(cylinder.vertices[:, 2]), 0.15)


def test_dh_scene_has_the_paper_frames_and_colours_roles() -> None:
    preset = get_preset("aaria-fig3")
    robot = build_dh_robot(preset.table)
    scene = scene_from_dh_robot(robot, "fig3")
    roles = [item.role for item in scene.lines]
    # world, dh0 + one DH frame at each link's end, tool tip, one per mounted IMU
    mounted = sum(slot.parent is not None for slot in robot.imu_slots)
    assert roles.count("world_frame") == 1
    assert roles.count("dh_frame") == 1 + len(robot.chain.joints)
    assert roles.count("tool_frame") == 1
    assert roles.count("imu_frame") == mounted == 12  # module 2 empty: no link-2 IMUs
    solid_roles = {s.role for s in scene.solids}
    assert solid_roles == {"joint", "link"}
    # three prismatic modules: three green rails; two revolute: two housings
    joints = [s for s in scene.solids if s.role == "joint"]
    assert len(joints) == 3 + 3 + 2  # rails, sliders, housings
    assert scene.frames[0] == WORLD


def test_table_pose_puts_the_tool_where_the_chain_says() -> None:
    preset = get_preset("aaria-fig2")
    scene, poses = table_view(preset.table, "aaria", "fig2")
    robot = build_dh_robot(preset.table)
    tool = poses[scene.frames.index("tool_tip")]
    assert np.allclose(tool, robot.chain.T_base_tool(np.zeros(len(robot.chain.joints))))
    assert np.allclose(poses[0], np.eye(4))
    geometry = posed_geometry(scene, poses)
    # the yellow tool frame's segments start at the tool tip
    starts = geometry.segments[[r == "tool_frame" for r in geometry.segment_roles], 0]
    assert np.allclose(starts, tool[:3, 3])


@pytest.mark.parametrize("key", ["aaria", "mat"])
def test_run_poses_follow_the_stored_tool_pose_and_base(runs: dict[str, Path], key: str) -> None:
    from aaria_pin.files.runfile import read_run

    view = load_run_view(runs[key])
    assert view.kind == "aaria"
    record = read_run(runs["record"])
    samples = np.arange(view.time.size)
    poses = view.frame_poses(samples)
    tool = poses[:, view.scene.frames.index("tool_tip")]
    assert np.allclose(tool, record.tool_pose, atol=1e-9)
    # the arm moves with the base while the world frame stays put
    base_origin = poses[:, view.scene.frames.index("imu_base"), :3, 3]
    assert np.ptp(base_origin, axis=0).max() > 1e-3
    assert np.allclose(poses[:, 0], np.eye(4))
    # signals: empty module 2 left out, units in the labels, 12 IMUs
    types = record.tables["senSenDH"][:6, 4]
    expected_q = tuple(
        f"q{m + 1} [{'rad' if t == 1 else 'm'}]" for m, t in enumerate(types) if t != 0
    )
    expected_tau = tuple(
        f"tau{m + 1} [N·m]" if t == 1 else f"f{m + 1} [N]" for m, t in enumerate(types) if t != 0
    )
    assert view.signals.q_labels == expected_q and len(expected_q) == 5
    assert view.signals.tau_labels == expected_tau
    assert len(view.signals.imus) == 12 and "imu_link2_a" not in view.signals.imus
    assert np.allclose(view.signals.imus["imu_tool"], record.view("senSen")[:, 13:19])


@pytest.mark.parametrize("key", ["wrist", "wrist_mat"])
def test_wrist_runs_are_recognised_and_posed(runs: dict[str, Path], key: str) -> None:
    import h5py

    assert run_kind(runs[key]) == "wrist"
    view = load_run_view(runs[key])
    poses = view.frame_poses(np.arange(view.time.size))
    with h5py.File(runs["wrist"]) as handle:
        stored = handle["tool_pose"][:]
    assert np.allclose(poses[:, view.scene.frames.index("tool_tip")], stored, atol=1e-12)
    # the signals the record holds: the fixed mount's wrench, the wrist's IMUs
    from aaria_pin.files.runfile import read_run

    record = read_run(runs[key])
    assert np.any(record.base_wrench)
    np.testing.assert_array_equal(view.signals.base_wrench, record.base_wrench)
    assert list(view.signals.imus) == list(record.imu_names)
    for name, values in view.signals.imus.items():
        np.testing.assert_array_equal(values, record.imu_signals(name))


def test_a_wrist_run_of_0_1_0_has_no_wrench_and_no_imus() -> None:
    """0.1.0 wrist files stored neither: the viewers show none."""
    fixtures = Path(__file__).parents[1] / "fixtures" / "v0_1_0"
    for name in ("wrist_run.h5", "wrist_run.mat"):
        view = load_run_view(fixtures / name)
        assert view.kind == "wrist"
        assert view.signals.base_wrench is None and view.signals.imus == {}


def test_unknown_files_and_times_are_refused(tmp_path: Path, runs: dict[str, Path]) -> None:
    other = tmp_path / "other.h5"
    import h5py

    with h5py.File(other, "w") as handle:
        handle["x"] = np.zeros(3)
    with pytest.raises(InputFileError, match="not a run file"):
        load_run_view(other)
    with pytest.raises(InputFileError, match="no such file"):
        load_run_view(tmp_path / "missing.h5")
    time = np.linspace(0.0, 1.0, 51)
    assert sample_at(time, 0.5) == 25
    with pytest.raises(ParameterError, match="outside the run"):
        sample_at(time, 1.5)


def test_stick_figure_of_any_model_joins_joint_origins() -> None:
    robot = build_dh_robot(get_preset("aaria-fig2").table)
    model = robot.model()
    scene = scene_from_model(model)
    # base to joint 1, 5 between joints, 1 to the tool
    assert len(scene.bones) == len(robot.chain.joints) + 1
    assert sum(s.role == "joint" for s in scene.solids) == len(robot.chain.joints)
    poses = np.stack([np.eye(4)] * len(scene.frames))
    geometry = posed_geometry(scene, poses)
    assert geometry.segments.shape[0] == 3 * len(scene.lines) + len(scene.bones)


@pytest.mark.slow
def test_model_kind_runs_of_a_urdf_robot_and_the_pick_place_arm(tmp_path: Path) -> None:
    """Runs of a URDF robot and of the pick-and-place arm are posed from their URDF."""
    from click.testing import CliRunner

    from aaria_pin.cli import main
    from aaria_pin.files.runfile import read_run

    ur5, arm = tmp_path / "ur5.h5", tmp_path / "arm.h5"
    for args in (
        ["simulate", "--robot", "ur5", "--duration", "1", "--rate", "50", "-o", str(ur5)],
        ["arm", "pick-place", "--cylinder", "0.4", "0.1", "--place", "0.2", "-0.3", "-o", str(arm)],
    ):
        result = CliRunner().invoke(main, args)
        assert result.exit_code == 0, result.output
    assert run_kind(ur5) == "model"
    assert run_kind(arm) == "pick-place"  # the arm's plug-in kind
    for path in (ur5, arm):
        view = load_model_run(path)  # the model kind reads both
        record = read_run(path)
        samples = np.arange(0, view.time.size, 7)
        poses = view.frame_poses(samples)
        tool = poses[:, view.scene.frames.index(record.attributes["tool_frame"])]
        assert np.allclose(tool, record.tool_pose[samples], atol=1e-9)
        assert len(view.signals.imus) == len(record.imu_mounts)
    # the UR5 is drawn with its URDF's visual geometry on every link that has one (read here
    # with ElementTree), no stick figure; the arm's meshes (paths relative to its URDF's
    # folder, which a run file does not keep) are not found: its stick figure is drawn
    import xml.etree.ElementTree as ET

    links = ET.fromstring(read_run(ur5).urdf).iter("link")
    visual_links = {link.get("name") for link in links if link.find("visual") is not None}
    ur5_scene = load_model_run(ur5).scene
    assert {solid.frame for solid in ur5_scene.solids} == visual_links and not ur5_scene.bones
    assert len(load_model_run(arm).scene.bones) >= len(read_run(arm).joint_names)
    assert load_run_view(ur5).signals.base_wrench is not None  # moving base by default
    # joint kinds from the URDF joint types: the arm's lift and finger slide
    assert load_model_run(ur5).signals.kinds == ("revolute",) * 6
    arm_view = load_model_run(arm)
    prismatic = {
        name
        for name, kind in zip(read_run(arm).joint_names, arm_view.signals.kinds, strict=True)
        if kind == "prismatic"
    }
    assert prismatic == {"lift", "finger"}
    assert arm_view.signals.tau_labels[0] == "lift [N]"


def test_joint_kinds_are_told_by_exact_pinocchio_type_names() -> None:
    import pinocchio as pin

    cases = {
        pin.JointModelRX(): "revolute",
        pin.JointModelRUBZ(): "revolute",
        pin.JointModelRevoluteUnaligned(0.0, 1.0, 0.0): "revolute",
        pin.JointModelRevoluteUnboundedUnaligned(): "revolute",
        pin.JointModelPY(): "prismatic",
        pin.JointModelPrismaticUnaligned(1.0, 0.0, 0.0): "prismatic",
        pin.JointModelPlanar(): None,  # starts with "JointModelP" but slides in two axes
        pin.JointModelFreeFlyer(): None,
        pin.JointModelSpherical(): None,
    }
    for joint, kind in cases.items():
        told = one_axis_joint(joint)
        assert (None if told is None else told[0]) == kind, joint.shortname()


URDF = """<robot name="two">
  <link name="base"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01"
    ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="a"><inertial><origin xyz="0.1 0 0"/><mass value="1"/><inertia ixx="0.01"
    iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="b"><inertial><mass value="0.5"/><inertia ixx="0.01" iyy="0.01" izz="0.01"
    ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="spin" type="continuous"><parent link="base"/><child link="a"/>
    <axis xyz="0 0 1"/></joint>
  <joint name="slide" type="prismatic"><parent link="a"/><child link="b"/>
    <origin xyz="0.2 0 0"/><axis xyz="1 0 0"/><limit lower="-0.1" upper="0.1" effort="50"
    velocity="1"/></joint>
</robot>"""


def test_a_continuous_joint_is_revolute_and_a_prismatic_one_gets_forces(tmp_path: Path) -> None:
    """A URDF continuous joint (Pinocchio's RUBZ) is revolute: N·m; the prismatic one: N."""
    from aaria_pin.core.urdf_run import simulate_urdf_run
    from aaria_pin.files.runfile import write_run

    record = simulate_urdf_run(URDF, duration=0.5, rate=20.0, noise=False)
    view = load_run_view(write_run(tmp_path / "two.h5", record))
    assert view.kind == "model"
    assert view.signals.kinds == ("revolute", "prismatic")
    assert view.signals.q_labels == ("spin [rad]", "slide [m]")
    assert view.signals.tau_labels == ("spin [N·m]", "slide [N]")
    joints = [s for s in view.scene.solids if s.role == "joint"]
    assert len(joints) == 2  # a cylinder for the continuous joint too
