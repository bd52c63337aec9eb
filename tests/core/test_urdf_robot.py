"""URDF robots as simulation models: tool choice, joint tables within the URDF's limits."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from aaria_pin.core.catalogue import find_robot, robot_catalogue
from aaria_pin.core.trajectory import sample_times
from aaria_pin.core.urdf_robot import (
    default_urdf_joint_table,
    load_urdf_robot,
    read_urdf_file,
    urdf_joint_trajectory,
)
from aaria_pin.errors import AariaError, TableError


def _load(name: str, **kwargs: object):  # type: ignore[no-untyped-def]
    entry = find_robot(name)
    return load_urdf_robot(read_urdf_file(entry.urdf), urdf_dir=entry.urdf.parent, **kwargs)


@pytest.mark.parametrize(
    ("name", "tool"), [("ur5", "tool0"), ("panda", "panda_hand_tcp"), ("so100", None)]
)
def test_default_tool_frame(name: str, tool: str | None) -> None:
    loaded = _load(name)
    if tool is not None:
        assert loaded.robot.tool_frame == tool
    else:  # no conventional name: the deepest leaf link
        assert loaded.robot.tool_frame in loaded.summary.links
        assert loaded.robot.tool_frame not in {j.parent for j in loaded.summary.joints}


def test_tool_frame_can_be_chosen_and_must_exist() -> None:
    assert _load("ur5", tool_frame="wrist_2_link").robot.tool_frame == "wrist_2_link"
    with pytest.raises(AariaError, match="frame 'no_such_tool'"):
        _load("ur5", tool_frame="no_such_tool")


@pytest.mark.slow
def test_default_tables_stay_within_limits_for_every_loadable_robot() -> None:
    """Every example-robot-data robot that passes the URDF check moves within its limits."""
    time = sample_times(2.0, 200.0)
    loaded_any = 0
    for entry in robot_catalogue().values():
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                loaded = load_urdf_robot(read_urdf_file(entry.urdf), urdf_dir=entry.urdf.parent)
        except AariaError:
            continue
        loaded_any += 1
        trajectory = urdf_joint_trajectory(default_urdf_joint_table(loaded), loaded, time)
        for column, joint in enumerate(loaded.joints):
            if joint.mimic is not None:  # follows its leader (PR2's grippers break their limits)
                continue
            assert trajectory.q[:, column].min() >= joint.lower - 1e-12, (entry.name, joint.name)
            assert trajectory.q[:, column].max() <= joint.upper + 1e-12, (entry.name, joint.name)
            assert np.abs(trajectory.qd[:, column]).max() <= joint.velocity * (1 + 1e-9)
    assert loaded_any >= 40


def test_tables_leaving_the_urdf_limits_are_refused() -> None:
    loaded = _load("panda")
    table = default_urdf_joint_table(loaded)
    time = sample_times(1.0, 10.0)
    too_far = table.copy()
    too_far[3, 0] = 2.0  # panda_joint4 spans [-3.07, -0.07] rad
    with pytest.raises(TableError, match=r"row 4 \(revolute joint 'panda_joint4'\) moves over"):
        urdf_joint_trajectory(too_far, loaded, time)
    too_fast = table.copy()
    too_fast[0, 3] = 100.0
    with pytest.raises(TableError, match=r"velocity limit 2\.175 rad/s"):
        urdf_joint_trajectory(too_fast, loaded, time)
    with pytest.raises(TableError, match=r"shape \(8, 5\) is not allowed; expected 9 × 5"):
        urdf_joint_trajectory(table[:8], loaded, time)


def test_prismatic_finger_uses_the_prismatic_column() -> None:
    loaded = _load("panda")
    table = default_urdf_joint_table(loaded)
    finger = [j.name for j in loaded.joints].index("panda_finger_joint1")
    assert table[finger, 0] == 0 and table[finger, 1] == pytest.approx(0.4 * 0.04)
    assert table[finger, 2] == pytest.approx(0.02)  # the middle of [0, 0.04] m


def test_huge_prismatic_limits_give_a_bounded_motion() -> None:
    """URDFs write ±1e9 m for an unbounded rail: motions use its middle half metre."""
    from aaria_pin.aaria.randomize import RandomConfig, random_urdf_joint_table

    text = """<robot name="rail"><link name="a"/><link name="b"><inertial><mass value="1"/>
      <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <joint name="slide" type="prismatic"><parent link="a"/><child link="b"/>
      <axis xyz="1 0 0"/><limit lower="-1e9" upper="1e9" effort="1" velocity="1"/>
      </joint></robot>"""
    loaded = load_urdf_robot(text)
    assert default_urdf_joint_table(loaded)[0, 1] == pytest.approx(0.2)
    for seed in range(20):
        table = random_urdf_joint_table(RandomConfig(), loaded.joints, np.random.default_rng(seed))
        assert abs(table[0, 1]) + abs(table[0, 2]) <= 0.25 + 1e-12
