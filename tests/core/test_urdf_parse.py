"""The one URDF parser: every number of every catalogue robot as yourdfpy reads it; cached."""

from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.core.catalogue import robot_catalogue
from aaria_pin.core.urdf_parse import parse_urdf
from aaria_pin.errors import UrdfError

yourdfpy = pytest.importorskip("yourdfpy")


def _readable() -> list[str]:
    """Catalogue robots whose URDF passes the check (a few are refused on purpose)."""
    names = []
    for name, entry in sorted(robot_catalogue().items()):
        try:
            parse_urdf(entry.urdf.read_text())
        except UrdfError:
            continue
        names.append(name)
    return names


def _pose(matrix: object) -> np.ndarray:
    return np.eye(4) if matrix is None else np.asarray(matrix, dtype=float)


@pytest.mark.parametrize("name", _readable())
def test_every_catalogue_robot_reads_as_yourdfpy_reads_it(name: str) -> None:
    text = robot_catalogue()[name].urdf.read_text()
    document = parse_urdf(text)
    oracle = yourdfpy.URDF.load(
        str(robot_catalogue()[name].urdf), build_scene_graph=False, load_meshes=False
    ).robot
    assert document.name == oracle.name
    assert document.link_names == tuple(link.name for link in oracle.links)
    for link, expected in zip(document.links, oracle.links, strict=True):
        if expected.inertial is None:
            assert link.inertial is None
        else:
            assert link.inertial is not None
            assert link.inertial.mass == pytest.approx(float(expected.inertial.mass or 0.0))
            np.testing.assert_allclose(
                link.inertial.origin.transform(), _pose(expected.inertial.origin), atol=1e-12
            )
            np.testing.assert_array_equal(link.inertial.matrix(), expected.inertial.inertia)
        assert len(link.visuals) == len(expected.visuals)
        for visual, other in zip(link.visuals, expected.visuals, strict=True):
            np.testing.assert_allclose(visual.origin.transform(), _pose(other.origin), atol=1e-12)
            if other.geometry is not None and other.geometry.mesh is not None:
                assert visual.geometry is not None
                assert visual.geometry.filename == other.geometry.mesh.filename
            if other.geometry is not None and other.geometry.box is not None:
                assert visual.geometry is not None
                np.testing.assert_array_equal(visual.geometry.size, other.geometry.box.size)
    assert [j.name for j in document.joints] == [j.name for j in oracle.joints]
    for joint, expected in zip(document.joints, oracle.joints, strict=True):
        assert (joint.kind, joint.parent, joint.child) == (
            expected.type,
            expected.parent,
            expected.child,
        )
        np.testing.assert_allclose(joint.origin.transform(), _pose(expected.origin), atol=1e-12)
        if joint.kind in ("revolute", "prismatic"):
            limit = expected.limit  # a missing bound is 0, as urdfdom reads it
            assert (joint.lower, joint.upper) == (limit.lower or 0.0, limit.upper or 0.0)
        if joint.kind != "fixed" and expected.axis is not None:
            np.testing.assert_array_equal(joint.axis, expected.axis)
        if joint.kind == "fixed":  # a fixed joint's <mimic> means nothing: not kept
            assert joint.mimic is None
            continue
        assert (joint.mimic is None) == (expected.mimic is None)
        if joint.mimic is not None:
            assert joint.mimic[0] == expected.mimic.joint
            assert joint.mimic[1] == (expected.mimic.multiplier or 1.0)


TOY = """<robot name="toy">
  <material name="red"><color rgba="1 0 0 1"/></material>
  <link name="root"><visual><geometry><mesh filename="a.stl" scale="1 2 3"/></geometry>
    <material name="red"/></visual>
    <collision><geometry><sphere radius="0.5"/></geometry></collision></link>
  <link name="arm"><visual><origin xyz="1 2 3" rpy="0 0 1.5"/>
    <geometry><cylinder radius="0.1" length="0.4"/></geometry>
    <material name="green"><color rgba="0 1 0 0.5"/></material></visual>
    <visual><geometry><box size="1 2 3"/></geometry><material name="green"/></visual></link>
  <joint name="j" type="continuous"><parent link="root"/><child link="arm"/>
    <axis xyz="0 0 2"/></joint>
</robot>"""


def test_shapes_colours_and_meshes_are_read_and_the_parse_is_cached() -> None:
    document = parse_urdf(TOY)
    assert parse_urdf(TOY) is document  # one parse per text
    root, arm = document.links
    assert root.visuals[0].geometry is not None
    assert root.visuals[0].geometry.scale == (1.0, 2.0, 3.0)
    assert document.colour(root.visuals[0]) == (1.0, 0.0, 0.0, 1.0)
    assert root.collisions[0].geometry is not None
    assert root.collisions[0].geometry.radius == 0.5
    cylinder, box = arm.visuals
    assert cylinder.geometry is not None and box.geometry is not None
    assert (cylinder.geometry.radius, cylinder.geometry.length) == (0.1, 0.4)
    assert cylinder.origin.xyz == (1.0, 2.0, 3.0)
    c, s = np.cos(1.5), np.sin(1.5)
    np.testing.assert_allclose(
        cylinder.origin.rotation(), [[c, -s, 0], [s, c, 0], [0, 0, 1]], atol=1e-15
    )
    # a material defined inside one visual and reused by name in another
    assert document.colour(box) == document.colour(cylinder) == (0.0, 1.0, 0.0, 0.5)
    assert box.geometry.size == (1.0, 2.0, 3.0)
    assert document.meshes == ("a.stl",)
    (joint,) = document.joints
    assert joint.axis == (0.0, 0.0, 2.0) and joint.lower == -np.inf


def test_a_bad_document_names_the_urdf_parameter() -> None:
    with pytest.raises(UrdfError, match="link 'root' <visual> <mesh scale> is '1 2'") as info:
        parse_urdf(TOY.replace('scale="1 2 3"', 'scale="1 2"'))
    assert info.value.parameter == "urdf"
