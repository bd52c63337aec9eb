"""The one URDF emitter: any axis, continuous joints, meshes and spheres, materials; the direct
model equals the parsed URDF's; the pick-place arm's URDF describes the 0.1.0 arm."""

from __future__ import annotations

import io
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin
import pytest
import yourdfpy
from conftest import Rx, Rz, Tx, Tz

from aaria_pin.aaria.dh_robot import build_dh_robot
from aaria_pin.aaria.presets import get_preset
from aaria_pin.apps.arm.preset import ArmDimensions, arm_description, arm_urdf
from aaria_pin.core.inertia import Inertia, Part
from aaria_pin.core.model import build_model, model_from_description
from aaria_pin.core.se3 import translation
from aaria_pin.core.urdf import (
    Box,
    Cylinder,
    JointDescription,
    LinkDescription,
    Material,
    Mesh,
    RobotDescription,
    Shape,
    Sphere,
)
from aaria_pin.core.urdf_emitter import emit_urdf
from aaria_pin.errors import ModelError

FIXTURE = (
    Path(__file__).resolve().parents[1] / "fixtures" / "arm_urdf_v0_1_0" / "pick_place_arm.urdf"
)

TILTED = np.array([0.0, 0.6, 0.8])
SLANT = np.array([1.0, -2.0, 2.0]) / 3.0
RED = Material("red", (1.0, 0.0, 0.0, 1.0))


def _rotation_about(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues' formula, written here."""
    k = np.asarray(axis, dtype=float)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    T = np.eye(4)
    T[:3, :3] = np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K
    return T


def _solid(mass: float, com: tuple[float, float, float]) -> Inertia:
    I = np.array([[0.3, 0.01, -0.02], [0.01, 0.2, 0.03], [-0.02, 0.03, 0.25]])
    return Inertia(mass, np.array(com), I)


def _every_feature() -> RobotDescription:
    """A robot using every joint kind, unaligned axes, every geometry and rotated fixed joints."""
    box = Part("box", (0.2, 0.05, 0.04), Tx(0.1) @ Rz(0.3))
    links = (
        LinkDescription("root", mass_properties=_solid(2.0, (0.0, 0.0, 0.1))),
        LinkDescription("a", (box,)),
        LinkDescription(
            "b",
            mass_properties=_solid(1.5, (0.05, 0.01, 0.0)),
            shapes=(
                Shape(Mesh("meshes/b.stl", (0.001, 0.001, 0.002)), Rx(0.4), RED, "b_mesh"),
                Shape(Sphere(0.03), Tz(0.2), visual=False),
            ),
        ),
        LinkDescription("c", shapes=(Shape(Cylinder(0.02, 0.3), material=RED, collision=False),)),
        LinkDescription("d", mass_properties=_solid(0.7, (0.0, 0.02, 0.01))),
        LinkDescription("e", (Part("cylinder", (0.03, 0.1), Rx(0.5), role="housing"),)),
        LinkDescription("f", mass_properties=_solid(0.4, (0.01, 0.0, 0.03))),
        LinkDescription("tip"),
        LinkDescription("side", (Part("box", (0.1, 0.1, 0.1), Tz(0.05)),)),
    )
    joints = (
        JointDescription(
            "j_tilted", "revolute", "root", "a", Tz(0.3) @ Rx(0.2), -2.0, 2.5, axis=tuple(TILTED)
        ),
        JointDescription(
            "j_slide", "prismatic", "a", "b", Tx(0.2) @ Rz(-0.7), -0.1, 0.3, 50.0, 0.5, (1, 0, 0)
        ),
        JointDescription(
            "j_turn", "continuous", "b", "c", Tx(0.1), effort=7.0, velocity=3.0, axis=(0, 1, 0)
        ),
        JointDescription("j_fixed", "fixed", "c", "d", Tz(0.15) @ Rx(1.1) @ Rz(0.4)),
        JointDescription(
            "j_slant", "continuous", "d", "e", Tx(0.05), effort=2.0, velocity=1.0, axis=tuple(SLANT)
        ),
        JointDescription(
            "j_push", "prismatic", "e", "f", Tz(0.1), 0.0, 0.2, 30.0, 0.2, tuple(-TILTED)
        ),
        JointDescription("j_tip", "fixed", "f", "tip", Tx(0.08) @ Rx(np.pi)),
        JointDescription("j_side", "fixed", "root", "side", Tx(-0.2) @ Rz(0.9)),
    )
    return RobotDescription("every_feature", links, joints, materials=())


def _joint_axes(model: pin.Model) -> list[np.ndarray]:
    """Each joint's motion (6-vector, its own frame) at the neutral configuration."""
    data = model.createData()
    q = pin.neutral(model)
    pin.computeJointJacobians(model, data, q)
    axes = []
    for j in range(1, model.njoints):
        J = pin.getJointJacobian(model, data, j, pin.ReferenceFrame.LOCAL)
        joint = model.joints[j]
        axes.append(J[:, joint.idx_v : joint.idx_v + joint.nv])
    return axes


def _assert_same_models(a: pin.Model, b: pin.Model, frames: bool = True) -> None:
    """Same joints (names, types, axes, placements, limits), inertias and frames, to 1e-12."""
    assert list(a.names) == list(b.names)
    assert [j.shortname() for j in a.joints] == [j.shortname() for j in b.joints]
    assert (a.nq, a.nv) == (b.nq, b.nv)
    for pa, pb in zip(a.jointPlacements, b.jointPlacements, strict=True):
        np.testing.assert_allclose(pa.homogeneous, pb.homogeneous, atol=1e-12)
    for Sa, Sb in zip(_joint_axes(a), _joint_axes(b), strict=True):
        np.testing.assert_allclose(Sa, Sb, atol=1e-12)
    for ia, ib in zip(a.inertias, b.inertias, strict=True):
        assert ia.mass == pytest.approx(ib.mass, rel=1e-12, abs=1e-12)
        np.testing.assert_allclose(ia.toDynamicParameters(), ib.toDynamicParameters(), atol=1e-12)
    for limit in ("lowerPositionLimit", "upperPositionLimit", "effortLimit", "velocityLimit"):
        np.testing.assert_allclose(getattr(a, limit), getattr(b, limit), atol=1e-12)
    if not frames:
        return
    assert [(f.name, f.type) for f in a.frames] == [(f.name, f.type) for f in b.frames]
    for fa, fb in zip(a.frames, b.frames, strict=True):
        assert (fa.parentJoint, fa.parentFrame) == (fb.parentJoint, fb.parentFrame), fa.name
        np.testing.assert_allclose(fa.placement.homogeneous, fb.placement.homogeneous, atol=1e-12)
        np.testing.assert_allclose(
            fa.inertia.toDynamicParameters(), fb.inertia.toDynamicParameters(), atol=1e-12
        )


def _assert_same_dynamics(a: pin.Model, b: pin.Model, seed: int) -> None:
    rng = np.random.default_rng(seed)
    for _ in range(3):
        q = pin.randomConfiguration(b)
        v, acc = rng.normal(size=b.nv), rng.normal(size=b.nv)
        np.testing.assert_allclose(
            pin.rnea(a, a.createData(), q, v, acc),
            pin.rnea(b, b.createData(), q, v, acc),
            atol=1e-9,
        )


def _description(which: str) -> tuple[RobotDescription, str]:
    """A robot description and its tool frame."""
    if which == "every_feature":
        return _every_feature(), "tip"
    if which == "arm":
        return arm_description(ArmDimensions()), "grasp"
    preset = get_preset(which)
    return build_dh_robot(preset.table, preset.convention).description, "tool_tip"


@pytest.mark.parametrize("moving_base", [False, True])
@pytest.mark.parametrize("which", ["every_feature", "arm", "aaria-fig2", "spherical-wrist"])
def test_direct_model_equals_the_parsed_urdf(which: str, moving_base: bool) -> None:
    """Joints, inertias and frames in the same order with the same values, as parsed."""
    description, tip = _description(which)
    root = description.links[0].name
    direct = model_from_description(
        description, moving_base=moving_base, base_frame=root, tool_frame=tip, sensor_frames=()
    ).model
    parsed = build_model(
        emit_urdf(description),
        moving_base=moving_base,
        base_frame=root,
        tool_frame=tip,
        sensor_frames=(),
    ).model
    _assert_same_models(direct, parsed)
    _assert_same_dynamics(direct, parsed, 4)


def test_joint_kinds_and_axes_become_the_expected_pinocchio_joints() -> None:
    model = model_from_description(
        _every_feature(), base_frame="root", tool_frame="tip", sensor_frames=()
    ).model
    kinds = {name: model.joints[model.getJointId(name)].shortname() for name in model.names[1:]}
    assert kinds == {
        "j_tilted": "JointModelRevoluteUnaligned",
        "j_slide": "JointModelPX",
        "j_turn": "JointModelRUBY",
        "j_slant": "JointModelRevoluteUnboundedUnaligned",
        "j_push": "JointModelPrismaticUnaligned",
    }
    axes = dict(zip(model.names[1:], _joint_axes(model), strict=True))
    np.testing.assert_allclose(axes["j_tilted"][:, 0], [0, 0, 0, *TILTED], atol=1e-15)
    np.testing.assert_allclose(axes["j_push"][:, 0], [*-TILTED, 0, 0, 0], atol=1e-15)
    np.testing.assert_allclose(axes["j_slant"][:, 0], [0, 0, 0, *SLANT], atol=1e-15)
    # limits: a continuous joint has none on its (cos, sin) pair; effort and velocity it keeps
    turn = model.joints[model.getJointId("j_turn")]
    np.testing.assert_array_equal(model.upperPositionLimit[turn.idx_q : turn.idx_q + 2], 1.01)
    assert model.effortLimit[turn.idx_v] == 7.0 and model.velocityLimit[turn.idx_v] == 3.0


def test_unaligned_joints_move_the_tip_as_rodrigues_says() -> None:
    description = _every_feature()
    urdf = yourdfpy.URDF.load(io.StringIO(emit_urdf(description)), load_meshes=False)
    assert urdf.validate()
    q = {"j_tilted": 0.7, "j_slide": 0.12, "j_turn": -1.3, "j_slant": 2.1, "j_push": 0.05}
    urdf.update_cfg(q)
    expected = (
        Tz(0.3) @ Rx(0.2) @ _rotation_about(TILTED, 0.7)
        @ Tx(0.2) @ Rz(-0.7) @ Tx(0.12)
        @ Tx(0.1) @ _rotation_about(np.array([0, 1, 0]), -1.3)
        @ Tz(0.15) @ Rx(1.1) @ Rz(0.4)
        @ Tx(0.05) @ _rotation_about(SLANT, 2.1)
        @ Tz(0.1) @ translation(*(-0.05 * TILTED))
        @ Tx(0.08) @ Rx(np.pi)
    )  # fmt: skip
    np.testing.assert_allclose(urdf.get_transform("tip", "root"), expected, atol=1e-12)


def test_shapes_and_materials_are_written_as_given() -> None:
    root = ET.fromstring(emit_urdf(_every_feature()))
    assert [(m.get("name"), m.find("color").get("rgba")) for m in root.findall("material")] == [
        ("link_blue", "0.20 0.35 0.85 1"),  # link a's box, declared on first use
        ("red", "1 0 0 1"),
        ("joint_green", "0.13 0.69 0.30 1"),  # link e's housing
    ]
    b = root.find("link[@name='b']")
    (visual,) = b.findall("visual")
    mesh = visual.find("geometry/mesh")
    assert (mesh.get("filename"), mesh.get("scale")) == ("meshes/b.stl", "0.001 0.001 0.002")
    assert visual.find("origin").get("rpy") == "0.4 0.0 0.0"
    assert visual.find("material").get("name") == "red"
    collisions = b.findall("collision")
    assert [c.find("geometry/*").tag for c in collisions] == ["mesh", "sphere"]
    assert collisions[1].find("geometry/sphere").get("radius") == "0.03"
    assert collisions[1].get("name") == "b_shape_1"
    c = root.find("link[@name='c']")
    assert c.find("collision") is None
    assert c.find("visual/geometry/cylinder").attrib == {"radius": "0.02", "length": "0.3"}
    assert root.find("link[@name='c']/inertial") is None
    turn = root.find("joint[@name='j_turn']")
    assert turn.find("axis").get("xyz") == "0 1 0"
    assert turn.find("limit").attrib == {"effort": "7.0", "velocity": "3.0"}
    slant = root.find("joint[@name='j_slant']/axis").get("xyz")
    np.testing.assert_array_equal(np.array(slant.split(), dtype=float), SLANT)


def _description_with(changes: dict[str, Any]) -> RobotDescription:
    """A two-link robot whose joint (or the arm link's shapes) takes the changes."""
    shapes = tuple(changes.pop("shapes", ()))
    fields: dict[str, Any] = {"name": "j", "kind": "revolute", "parent": "root", "child": "arm"}
    fields |= {"T_parent_child": np.eye(4), "lower": -1.0, "upper": 1.0} | changes
    arm = LinkDescription("arm", shapes=shapes)
    materials = (Material("red", (0.9, 0.0, 0.0, 1.0)),)
    return RobotDescription(
        "bad", (LinkDescription("root"), arm), (JointDescription(**fields),), materials=materials
    )


@pytest.mark.parametrize(
    ("changes", "pattern"),
    [
        ({"axis": (0.0, 0.0, 2.0)}, r"joint 'j' axis is \(0.0, 0.0, 2.0\); allowed: a unit vector"),
        ({"axis": (1.0, 0.0)}, "allowed: a unit vector of 3 numbers"),
        ({"kind": "spherical"}, "kind is 'spherical'; allowed: revolute, continuous"),
        ({"lower": 1.0, "upper": -1.0}, r"lower limit is 1.0; allowed: <= upper limit -1.0"),
        ({"upper": float("nan")}, "allowed: finite numbers"),
        ({"child": "hand"}, "link 'hand' is not in the robot"),
        ({"name": "j k"}, "name 'j k' is not allowed in a URDF"),
        (
            {"shapes": [Shape(Box((1, 1, 1)), material=RED)]},
            r"material 'red' has colours \(0.9, 0.0, 0.0, 1.0\) and \(1.0, 0.0, 0.0, 1.0\)",
        ),
        (
            {"shapes": [Shape(Box((1, 1, 1)), material=Material("pale", (1.2, 0.0, 0.0, 1.0)))]},
            r"material 'pale' rgba is \(1.2, 0.0, 0.0, 1.0\); allowed: 4 numbers in \[0, 1\]",
        ),
    ],
)
def test_bad_descriptions_are_refused(changes: dict[str, Any], pattern: str) -> None:
    description = _description_with(dict(changes))
    with pytest.raises(ModelError, match=pattern):
        emit_urdf(description)


def _arm_model(urdf: str, moving_base: bool) -> pin.Model:
    return build_model(
        urdf, moving_base=moving_base, base_frame="pillar", tool_frame="grasp", sensor_frames=()
    ).model


def _shapes(urdf: str) -> dict[tuple[str, str], tuple[str, np.ndarray, tuple[float, ...]]]:
    """(link, visual or collision) → mesh file, xyz and rpy, colour (from any URDF's layout)."""
    root = ET.fromstring(urdf)
    colours = {
        material.get("name"): colour.get("rgba")
        for material in root.iter("material")
        if (colour := material.find("color")) is not None
    }
    found = {}
    for link in root.findall("link"):
        for element in (*link.findall("visual"), *link.findall("collision")):
            origin = element.find("origin")
            pose = np.array([*origin.get("xyz").split(), *origin.get("rpy").split()], dtype=float)
            material = element.find("material")
            rgba = "" if material is None else colours[material.get("name")]
            colour = tuple(float(v) for v in rgba.split())
            mesh = element.find("geometry/mesh").get("filename")
            found[(link.get("name"), element.tag)] = (mesh, pose, colour)
    return found


def test_the_arm_urdf_describes_the_0_1_0_arm() -> None:
    old_text = FIXTURE.read_text(encoding="utf-8")
    new_text = arm_urdf(ArmDimensions())
    for moving_base in (False, True):
        old, new = _arm_model(old_text, moving_base), _arm_model(new_text, moving_base)
        _assert_same_models(old, new)
        _assert_same_dynamics(old, new, 7)
    old_shapes, new_shapes = _shapes(old_text), _shapes(new_text)
    assert sorted(new_shapes) == sorted(old_shapes)
    assert len(new_shapes) == 16  # a visual and a collision mesh on each of the 8 solid links
    for key, (mesh, pose, colour) in old_shapes.items():
        assert new_shapes[key][0] == mesh == f"meshes/{key[0]}.stl"
        np.testing.assert_array_equal(new_shapes[key][1], pose)
        assert new_shapes[key][2] == colour
