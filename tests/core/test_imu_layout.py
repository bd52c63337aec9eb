"""IMU layouts of URDF robots: the default two-per-link layout, layout files, model frames."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from aaria_pin.core.catalogue import find_robot
from aaria_pin.core.imu_layout import (
    DEFAULT_MIN_OFFSET,
    _offset_from_axis,
    check_slot_mounts,
    default_imu_layout,
    moving_links,
    read_imu_layout,
)
from aaria_pin.core.record import ImuMount
from aaria_pin.core.urdf_robot import load_urdf_robot, read_urdf_file
from aaria_pin.core.urdf_run import simulate_urdf_run
from aaria_pin.errors import InputFileError, ModelError, ParameterError


def _ur5() -> str:
    return read_urdf_file(find_robot("ur5").urdf)


def test_default_layout_has_base_tool_and_two_per_moving_link() -> None:
    loaded = load_urdf_robot(_ur5())
    names = [mount.name for mount in loaded.imu_mounts]
    links = [link for _, _, link in moving_links(loaded.robot.model)]
    assert links == [
        "shoulder_link", "upper_arm_link", "forearm_link", "wrist_1_link", "wrist_2_link",
        "wrist_3_link",
    ]  # fmt: skip
    assert names[:2] == ["imu_base", "imu_tool"]
    assert names[2:] == [f"imu_{link}_{s}" for link in links for s in ("a", "b")]
    assert loaded.robot.sensor_frames == tuple(names)


def test_second_imu_sits_at_the_centre_of_mass_or_off_the_axis() -> None:
    loaded = load_urdf_robot(_ur5())
    model = loaded.robot.model
    for joint_id, _, link in moving_links(model):
        b = next(m for m in loaded.imu_mounts if m.name == f"imu_{link}_b")
        T_joint_link = model.frames[model.getFrameId(link)].placement.homogeneous
        position_joint = (T_joint_link @ b.T_parent_imu)[:3, 3]
        axis = np.eye(3)["XYZ".index(model.joints[joint_id].shortname()[-1])]  # UR5: RY, RZ
        radial = position_joint - axis * (axis @ position_joint)
        assert np.linalg.norm(radial) >= DEFAULT_MIN_OFFSET - 1e-12
        com = np.asarray(model.inertias[joint_id].lever)
        com_radial = np.linalg.norm(com - axis * (axis @ com))
        if com_radial >= DEFAULT_MIN_OFFSET:
            np.testing.assert_allclose(position_joint, com, atol=1e-12)


@settings(max_examples=200, deadline=None)
@given(
    st.lists(st.floats(-1, 1), min_size=3, max_size=3),
    st.lists(st.floats(-1, 1), min_size=3, max_size=3).filter(lambda v: np.linalg.norm(v) > 0.1),
)
def test_offset_moves_only_perpendicular_and_exactly_to_the_minimum(
    com: list[float], axis: list[float]
) -> None:
    c, a = np.array(com), np.array(axis) / np.linalg.norm(axis)
    moved = _offset_from_axis(c, np.array(axis), 0.05)
    distance = np.linalg.norm(moved - a * (a @ moved))
    assert distance >= 0.05 - 1e-12
    np.testing.assert_allclose(a @ moved, a @ c, atol=1e-12)  # no motion along the axis
    if np.linalg.norm(c - a * (a @ c)) >= 0.05:
        np.testing.assert_array_equal(moved, c)
    else:
        assert abs(distance - 0.05) < 1e-9


def test_com_on_the_axis_gets_a_perpendicular_offset() -> None:
    moved = _offset_from_axis(np.array([0, 0, 0.3]), np.array([0, 0, 1.0]), 0.05)
    assert moved[2] == pytest.approx(0.3) and np.hypot(moved[0], moved[1]) == pytest.approx(0.05)


def test_layout_file_replaces_the_default(tmp_path: Path) -> None:
    layout = tmp_path / "imus.toml"
    layout.write_text(
        '[[imu]]\nname = "imu_wrist"\nparent = "wrist_3_link"\nxyz = [0.0, 0.0, 0.05]\n'
        "rpy = [0.0, 0.0, 1.5707963267948966]\n\n"
        '[[imu]]\nname = "imu_elbow"\nparent = "elbow_joint"\n'
    )
    mounts = read_imu_layout(layout)
    assert [m.name for m in mounts] == ["imu_wrist", "imu_elbow"]
    np.testing.assert_allclose(mounts[0].T_parent_imu[:3, 3], [0, 0, 0.05])
    np.testing.assert_allclose(mounts[0].T_parent_imu[:3, :3], pin.rpy.rpyToMatrix(0, 0, np.pi / 2))
    record = simulate_urdf_run(_ur5(), imu_layout=mounts, duration=0.5, noise=False)
    assert record.columns[-12:-6] == tuple(
        f"imu_wrist_{s}" for s in ("wx", "wy", "wz", "fx", "fy", "fz")
    )
    assert record.imu.shape == (51, 2, 6)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "no \\[\\[imu\\]\\] tables"),
        ("[[imu]]\nparent = 'a'\n", "no name"),
        ("[[imu]]\nname = 'x'\nparent = 'a'\nxyz = [1, 2]\n", "xyz = \\[1, 2\\]"),
        ("[[imu]]\nname = 'x'\nparent = 'a'\ncolour = 'red'\n", "unknown key 'colour'"),
        ("[[imu]]\nname = 'x'\nparent = 'a'\n[[imu]]\nname = 'x'\nparent = 'b'\n", "used twice"),
        ("[[imu\n", "not a TOML file"),
    ],
)
def test_bad_layout_files_are_refused(tmp_path: Path, text: str, message: str) -> None:
    layout = tmp_path / "imus.toml"
    layout.write_text(text)
    with pytest.raises(InputFileError, match=message):
        read_imu_layout(layout)


def test_unknown_parent_frame_is_refused(tmp_path: Path) -> None:
    layout = tmp_path / "imus.toml"
    layout.write_text("[[imu]]\nname = 'x'\nparent = 'hand_of_god'\n")
    with pytest.raises(ModelError, match="parent frame 'hand_of_god' is not in model"):
        load_urdf_robot(_ur5(), imu_layout=read_imu_layout(layout))


def test_second_imu_sits_where_the_urdf_puts_the_centre_of_mass() -> None:
    """UR5's upper arm: its <inertial> origin, read from the XML, is 0.28 m off its joint's axis,
    so imu_upper_arm_link_b sits exactly there, axes along the link."""
    import xml.etree.ElementTree as ET

    text = _ur5()
    link = ET.fromstring(text).find("link[@name='upper_arm_link']")
    assert link is not None
    origin = link.find("inertial/origin")
    assert origin is not None
    com = np.array([float(v) for v in origin.get("xyz", "").split()])
    model = pin.buildModelFromXML(text)
    mounts = {m.name: m for m in default_imu_layout(model, "world", "tool0")}
    b = mounts["imu_upper_arm_link_b"]
    assert b.parent == "upper_arm_link"
    np.testing.assert_allclose(b.T_parent_imu[:3, 3], com, atol=1e-12)
    np.testing.assert_array_equal(b.T_parent_imu[:3, :3], np.eye(3))
    np.testing.assert_array_equal(mounts["imu_upper_arm_link_a"].T_parent_imu, np.eye(4))


def test_a_layout_entry_that_is_not_a_table_is_refused(tmp_path: Path) -> None:
    layout = tmp_path / "imus.toml"
    layout.write_text("imu = [1, 2]\n")
    with pytest.raises(InputFileError, match="1 is not a table"):
        read_imu_layout(layout)


def test_a_centre_of_mass_a_hair_off_the_axis_still_ends_at_the_minimum() -> None:
    """Found by hypothesis: 1e-10 m off the axis, the offset must not cancel that hair."""
    moved = _offset_from_axis(np.array([0.0, 1e-10, 0.0]), np.array([0.0, 0.0, -1.0]), 0.05)
    assert np.hypot(moved[0], moved[1]) == pytest.approx(0.05, abs=1e-15)


_CARRIED = """<robot name="carrier">
  <link name="base"/>
  <link name="arm"><inertial><mass value="1"/>
    <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  <link name="imu_base"/>
  <link name="imu_arm_a"/>
  <link name="marker"><visual><geometry><sphere radius="0.01"/></geometry></visual></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="2"/></joint>
  <joint name="imu_base_joint" type="fixed"><parent link="base"/><child link="imu_base"/>
    <origin xyz="0.1 0 0"/></joint>
  <joint name="imu_arm_a_joint" type="fixed"><parent link="arm"/><child link="imu_arm_a"/>
    <origin xyz="0 0.2 0" rpy="0 0 0.5"/></joint>
  <joint name="marker_joint" type="fixed"><parent link="arm"/><child link="marker"/></joint>
</robot>"""


def test_imus_the_urdf_carries_as_links_are_its_mounts() -> None:
    """A bare frame link named as a default IMU is that IMU: where the URDF puts it."""
    loaded = load_urdf_robot(_CARRIED, moving_base=False)
    mounts = {mount.name: mount for mount in loaded.imu_mounts}
    assert list(mounts) == ["imu_base", "imu_tool", "imu_arm_a", "imu_arm_b"]
    assert (mounts["imu_base"].parent, mounts["imu_arm_a"].parent) == ("base", "arm")
    expected = np.eye(4)
    expected[:3, :3] = [[np.cos(0.5), -np.sin(0.5), 0], [np.sin(0.5), np.cos(0.5), 0], [0, 0, 1]]
    expected[:3, 3] = [0.0, 0.2, 0.0]
    assert np.allclose(mounts["imu_arm_a"].T_parent_imu, expected, atol=1e-15)
    assert np.array_equal(mounts["imu_base"].T_parent_imu[:3, 3], [0.1, 0.0, 0.0])
    # The IMU is the URDF's link frame itself: one frame of that name, none added.
    model = loaded.robot.model
    assert [frame.name for frame in model.frames].count("imu_arm_a") == 1
    data = model.createData()
    q = np.array([0.3])
    pin.framesForwardKinematics(model, data, q)
    arm = data.oMf[model.getFrameId("arm", pin.FrameType.BODY)].homogeneous
    imu = data.oMf[loaded.robot.frame_id("imu_arm_a")].homogeneous
    assert np.allclose(imu, arm @ expected, atol=1e-15)


def test_a_layout_that_moves_a_carried_imu_is_refused(tmp_path: Path) -> None:
    """A layout may name a carried IMU only as the URDF mounts it (a re-made run does)."""
    loaded = load_urdf_robot(_CARRIED)
    again = load_urdf_robot(_CARRIED, imu_layout=loaded.imu_mounts)
    assert again.robot.sensor_frames == loaded.robot.sensor_frames
    layout = tmp_path / "moved.toml"
    layout.write_text('[[imu]]\nname = "imu_base"\nparent = "base"\nxyz = [0.2, 0, 0]\n')
    with pytest.raises(ModelError, match="IMU name 'imu_base' is already a frame"):
        load_urdf_robot(_CARRIED, imu_layout=read_imu_layout(layout))


_SLOTS = (("imu_base", "base"), ("imu_tool", "tool_tip"), ("imu_link1_a", "link1"))


def _mounts(*pairs: tuple[str, str]) -> list[ImuMount]:
    return [ImuMount(name, parent, np.eye(4)) for name, parent in pairs]


def test_slot_mounts_of_the_robot_or_of_an_empty_slot_pass() -> None:
    check_slot_mounts(_mounts(*_SLOTS), _SLOTS, "run.h5")
    check_slot_mounts(_mounts(_SLOTS[0], _SLOTS[1], ("imu_link1_a", "")), _SLOTS, "run.h5")


@pytest.mark.parametrize(
    ("pairs", "message"),
    [
        (
            (("imu_base", "world"), _SLOTS[1]),
            "parent of imu_base in ur5.h5 is 'world'; allowed: base (the link of slot imu_base)",
        ),
        (
            (_SLOTS[0], ("imu_wrist", "tool_tip")),
            "IMU 2 of ur5.h5 is 'imu_wrist'; allowed: imu_tool (slot 2 of the robot)",
        ),
        (
            (_SLOTS[0], _SLOTS[1], ("imu_link1_a", "link2")),
            "parent of imu_link1_a in ur5.h5 is 'link2'; allowed: link1",
        ),
    ],
)
def test_mounts_of_another_robot_are_refused(
    pairs: tuple[tuple[str, str], ...], message: str
) -> None:
    with pytest.raises(ParameterError) as caught:
        check_slot_mounts(_mounts(*pairs), _SLOTS, "ur5.h5")
    assert str(caught.value).startswith(message)
    assert caught.value.parameter == "imu_mount"


def test_the_aaria_arm_refuses_a_urdf_robots_mounts(tmp_path: Path) -> None:
    """``--imu-mount ur5.h5`` on an Aaria arm: one line naming the flag, nothing written."""
    from click.testing import CliRunner

    from aaria_pin.cli import main

    short = ["--duration", "0.1", "--no-noise"]
    ur5 = tmp_path / "ur5.h5"
    assert (
        CliRunner().invoke(main, ["simulate", "--robot", "ur5", *short, "-o", str(ur5)]).exit_code
        == 0
    )
    out = tmp_path / "arm.h5"
    argv = ["simulate", "--preset", "aaria-fig2", "--imu-mount", str(ur5), *short, "-o", str(out)]
    result = CliRunner().invoke(main, argv)
    assert result.exit_code == 2
    assert result.output == (
        f"aaria: error: parent of imu_base in {ur5} of --imu-mount is 'world'; allowed: base "
        "(the link of slot imu_base)\n"
    )
    assert not out.exists()
