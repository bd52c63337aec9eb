from __future__ import annotations

import io
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest
import yourdfpy
from conftest import paper_tool_pose, wrist_equation_9
from hypothesis import given, settings
from hypothesis import strategies as st

from aaria_pin.aaria.dh_robot import build_dh_robot
from aaria_pin.aaria.presets import get_preset
from aaria_pin.core.inertia import Part
from aaria_pin.core.se3 import rpy_from_matrix
from aaria_pin.core.urdf import JointDescription, LinkDescription, RobotDescription
from aaria_pin.core.urdf_emitter import emit_urdf
from aaria_pin.errors import ModelError

ROOT = Path(__file__).resolve().parents[2]


def _rpy_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    cr, sr, cp, sp, cy, sy = (
        np.cos(roll),
        np.sin(roll),
        np.cos(pitch),
        np.sin(pitch),
        np.cos(yaw),
        np.sin(yaw),
    )
    Rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    Ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    Rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    return Rz @ Ry @ Rx


@settings(max_examples=200, deadline=None)
@given(
    roll=st.floats(-np.pi, np.pi),
    yaw=st.floats(-np.pi, np.pi),
    pitch=st.sampled_from([np.pi / 2, -np.pi / 2, np.pi / 2 - 1e-9])
    | st.floats(-np.pi / 2, np.pi / 2),
)
def test_rpy_round_trip_including_gimbal_lock(roll: float, pitch: float, yaw: float) -> None:
    R = _rpy_matrix(roll, pitch, yaw)
    np.testing.assert_allclose(_rpy_matrix(*rpy_from_matrix(R)), R, atol=1e-9)


@pytest.mark.parametrize("name", ["aaria-fig2", "aaria-fig3", "spherical-wrist"])
def test_urdf_round_trips_through_yourdfpy(name: str, rng) -> None:
    preset = get_preset(name)
    robot = build_dh_robot(preset.table, preset.convention)
    urdf = yourdfpy.URDF.load(io.StringIO(robot.urdf), build_scene_graph=True, load_meshes=False)
    assert urdf.validate()
    assert urdf.actuated_joint_names == [f"joint{m}" for m in robot.chain.modules]
    assert {"base", "tool_tip", "imu_base", "imu_tool"} <= set(urdf.link_map)
    for slot in robot.imu_slots:
        assert (slot.name in urdf.link_map) == (slot.parent is not None)
    rewritten = yourdfpy.URDF.load(io.BytesIO(urdf.write_xml_string()), load_meshes=False)
    assert rewritten.validate()
    for _ in range(5):
        q = np.array(
            [
                rng.uniform(j.lower, j.upper) if j.kind == "prismatic" else rng.uniform(-3, 3)
                for j in robot.chain.joints
            ]
        )
        urdf.update_cfg(q)
        T = urdf.get_transform("tool_tip", "base")
        expected = (
            paper_tool_pose(preset.table, q)
            if preset.convention == "aaria"
            else wrist_equation_9(*q, d=0.132)
        )
        np.testing.assert_allclose(T, expected, atol=1e-9)


def test_visual_and_collision_are_the_same_geometry() -> None:
    robot = build_dh_robot(get_preset("aaria-fig2").table)
    urdf = yourdfpy.URDF.load(io.StringIO(robot.urdf), load_meshes=False)
    for link in urdf.robot.links:
        assert len(link.visuals) == len(link.collisions)
        for visual, collision in zip(link.visuals, link.collisions, strict=True):
            np.testing.assert_array_equal(visual.origin, collision.origin)
            assert repr(visual.geometry) == repr(collision.geometry)


def test_emitter_refuses_a_joint_to_an_unknown_link() -> None:
    description = RobotDescription(
        "bad",
        (LinkDescription("base"), LinkDescription("arm", (Part("box", (1, 1, 1), np.eye(4)),))),
        (JointDescription("j", "revolute", "base", "hand", np.eye(4)),),
    )
    with pytest.raises(ModelError, match="link 'hand' is not in the robot"):
        emit_urdf(description)


@pytest.mark.slow
def test_templates_ship_inside_the_wheel(tmp_path: Path) -> None:
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "wheel",
            "--no-deps",
            "--no-build-isolation",
            "-q",
            "-w",
            str(tmp_path),
            str(ROOT),
        ],
        check=True,
    )
    wheel = next(tmp_path.glob("aaria_pin-*.whl"))
    names = zipfile.ZipFile(wheel).namelist()
    for template in (ROOT / "urdf_templates").iterdir():
        assert f"aaria_pin/urdf_templates/{template.name}" in names
