"""Meshes of the pick-place arm: mass properties against closed forms, STL files, the URDF."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
import trimesh

from aaria_pin.apps.arm.parts import (
    box_mesh,
    combine,
    cylinder_mesh,
    export_stl,
    mesh_inertia,
    prism_inertia,
    ring_mesh,
    stadium_mesh,
)
from aaria_pin.apps.arm.preset import ARM_JOINTS, ArmDimensions, arm_parts, arm_urdf, write_arm_urdf
from aaria_pin.core.inertia import box_inertia, cylinder_inertia, parallel_axis
from aaria_pin.errors import ParameterError


@pytest.mark.parametrize("size", [(0.1, 0.2, 0.3), (0.4, 0.05, 0.02), (1.0, 1.0, 1.0)])
def test_box_mesh_inertia_is_the_closed_form(size: tuple[float, float, float]) -> None:
    center = (0.3, -0.1, 0.7)
    props = mesh_inertia(box_mesh(size, center), 2700.0)
    mass = 2700.0 * float(np.prod(size))
    assert props.mass == pytest.approx(mass, rel=1e-12)
    np.testing.assert_allclose(props.com, center, atol=1e-12)
    np.testing.assert_allclose(props.inertia_com, box_inertia(mass, size), rtol=1e-10, atol=1e-12)


def test_rotated_box_mesh_inertia_is_r_i_rt() -> None:
    from aaria_pin.core.rotations import matrix_from_angles

    size, center = (0.1, 0.25, 0.4), np.array([0.2, -0.3, 0.1])
    R = np.asarray(matrix_from_angles([0.4, -0.7, 1.1], "ZYX"))
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, center
    mesh = box_mesh(size)
    mesh.apply_transform(T)
    props = mesh_inertia(mesh, 1000.0)
    mass = 1000.0 * float(np.prod(size))
    expected = R @ box_inertia(mass, size) @ R.T
    assert np.abs(expected - np.diag(np.diag(expected))).max() > 0.1 * np.abs(expected).max()
    assert props.mass == pytest.approx(mass, rel=1e-12)
    np.testing.assert_allclose(props.com, center, atol=1e-12)
    np.testing.assert_allclose(props.inertia_com, expected, rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("sections", [6, 12, 48, 256])
def test_cylinder_mesh_inertia_is_the_prism_closed_form(sections: int) -> None:
    radius, length, density = 0.05, 0.3, 7850.0
    props = mesh_inertia(cylinder_mesh(radius, length, sections=sections), density)
    area = sections / 2 * radius**2 * np.sin(2 * np.pi / sections)
    assert props.mass == pytest.approx(density * area * length, rel=1e-12)
    np.testing.assert_allclose(
        props.inertia_com,
        prism_inertia(props.mass, radius, length, sections),
        rtol=1e-10,
        atol=1e-12,
    )
    # and it tends to the circular cylinder's as the polygon gets finer (error O(1/n²))
    exact = cylinder_inertia(density * np.pi * radius**2 * length, radius, length)
    error = np.abs(props.inertia_com - exact).max() / np.abs(exact).max()
    assert error < 15.0 / sections**2  # mass (2π)²/6n², polar factor as much again


def test_ring_and_combined_parts_add_up() -> None:
    ring = mesh_inertia(ring_mesh(0.05, 0.08, 0.04, sections=512), 1000.0)
    m_out, m_in = (1000.0 * np.pi * r**2 * 0.04 for r in (0.08, 0.05))
    expected = cylinder_inertia(m_out, 0.08, 0.04) - cylinder_inertia(m_in, 0.05, 0.04)
    np.testing.assert_allclose(ring.inertia_com, expected, rtol=1e-4, atol=1e-12)
    a, b = box_mesh((0.1, 0.1, 0.1), (0.0, 0.0, 0.0)), box_mesh((0.2, 0.1, 0.1), (0.5, 0.0, 0.0))
    both = mesh_inertia(combine(a, b), 1000.0)
    ma, mb = 1.0, 2.0
    com = (ma * np.zeros(3) + mb * np.array([0.5, 0, 0])) / (ma + mb)
    expected = parallel_axis(box_inertia(ma, (0.1, 0.1, 0.1)), ma, -com) + parallel_axis(
        box_inertia(mb, (0.2, 0.1, 0.1)), mb, np.array([0.5, 0, 0]) - com
    )
    assert both.mass == pytest.approx(3.0)
    np.testing.assert_allclose(both.com, com, atol=1e-12)
    np.testing.assert_allclose(both.inertia_com, expected, rtol=1e-10, atol=1e-12)


def test_stadium_volume() -> None:
    mesh = stadium_mesh(0.4, 0.06, 0.04, sections=2000)
    assert mesh.is_watertight
    assert mesh.volume == pytest.approx((0.4 * 0.06 + np.pi * 0.03**2) * 0.04, rel=1e-5)


def test_bad_meshes_and_densities_are_refused() -> None:
    with pytest.raises(ParameterError, match="density") as error:
        mesh_inertia(box_mesh((1, 1, 1)), 0.0)
    assert (error.value.parameter, error.value.value) == ("density", 0.0)
    inverted = box_mesh((1, 1, 1))
    inverted.invert()
    with pytest.raises(ParameterError, match="outward normals") as error:
        mesh_inertia(inverted, 1000.0)
    assert error.value.parameter == "mesh"
    with pytest.raises(ParameterError, match="ring outer radius") as error:
        ring_mesh(0.05, 0.04, 0.1)
    assert (error.value.parameter, error.value.value) == ("outer", 0.04)
    with pytest.raises(ParameterError, match="box size along y") as error:
        box_mesh((1, -1, 1))
    assert (error.value.parameter, error.value.value) == ("size", -1)


def test_urdf_carries_the_mesh_mass_properties() -> None:
    dims = ArmDimensions()
    model = pin.buildModelFromXML(arm_urdf(dims))
    assert tuple(model.names[1:]) == ARM_JOINTS
    parts = arm_parts(dims)
    child = {
        "lift": "carriage",
        "shoulder": "upper_arm",
        "elbow": "forearm",
        "hand_yaw": "hand_yaw_link",
        "hand_pitch": "hand_pitch_link",
        "hand_roll": "hand",
        "finger": "sliding_finger",
    }
    for joint, link in child.items():
        props = parts[link].inertia()
        inertia = model.inertias[model.getJointId(joint)]
        assert inertia.mass == pytest.approx(props.mass, rel=1e-12)
        np.testing.assert_allclose(inertia.lever, props.com, atol=1e-12)
        np.testing.assert_allclose(inertia.inertia, props.inertia_com, rtol=1e-9, atol=1e-12)
    # the upper arm is aluminium: ring plus bar
    assert parts["upper_arm"].density == 2700.0


def test_write_arm_urdf_writes_loadable_stl_files(tmp_path) -> None:
    urdf = write_arm_urdf(tmp_path / "arm", ArmDimensions())
    text = urdf.read_text()
    for name, part in arm_parts(ArmDimensions()).items():
        stl = tmp_path / "arm" / "meshes" / f"{name}.stl"
        assert f'filename="meshes/{name}.stl"' in text
        loaded = trimesh.load(stl, force="mesh")
        assert loaded.volume == pytest.approx(part.mesh.volume, rel=1e-6)
    import yourdfpy

    robot = yourdfpy.URDF.load(str(urdf))
    assert set(robot.actuated_joint_names) == set(ARM_JOINTS)


def test_export_stl_round_trip(tmp_path) -> None:
    mesh = cylinder_mesh(0.1, 0.2)
    path = export_stl(mesh, tmp_path / "c.stl")
    assert trimesh.load(path).volume == pytest.approx(mesh.volume, rel=1e-6)


def test_dimensions_that_fold_the_hand_into_the_pillar_are_refused() -> None:
    with pytest.raises(ParameterError, match="A - B > pillar radius"):
        ArmDimensions(upper_arm=0.3, forearm=0.3)


def test_a_full_disk_half_way_leaves_no_partial_arm_folder(
    tmp_path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import errno

    import aaria_pin.apps.arm.preset as preset

    calls: list[str] = []
    real_export = preset.export_stl

    def export_until_full(mesh: object, path: object) -> None:
        calls.append(str(path))
        if len(calls) == 3:  # the third mesh finds the disk full
            raise OSError(errno.ENOSPC, "No space left on device")
        real_export(mesh, path)

    monkeypatch.setattr(preset, "export_stl", export_until_full)
    folder = tmp_path / "arm"
    with pytest.raises(OSError, match="No space left"):
        write_arm_urdf(folder, ArmDimensions())
    assert len(calls) == 3
    assert not folder.exists()  # the two meshes written and the folders made are gone
