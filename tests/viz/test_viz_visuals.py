"""A URDF's visual geometry as solids: placed by their origins, sized, coloured, decimated."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from aaria_pin.errors import MeshWarning
from aaria_pin.viz.visuals import urdf_visual_solids


def rotation_z(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


@pytest.fixture()
def urdf(tmp_path: Path) -> str:
    import trimesh

    trimesh.creation.box(extents=(1.0, 1.0, 1.0)).export(tmp_path / "cube.stl")
    return f"""<?xml version="1.0"?>
<robot name="shapes">
  <material name="orange"><color rgba="1 0.5 0 1"/></material>
  <link name="base">
    <visual>
      <origin xyz="0.1 0 0" rpy="0 0 {np.pi / 2}"/>
      <geometry><box size="0.2 0.1 0.05"/></geometry>
      <material name="inline"><color rgba="0.2 0.4 0.6 1"/></material>
    </visual>
    <visual>
      <origin xyz="0 0 0.5"/>
      <geometry><sphere radius="0.03"/></geometry>
    </visual>
  </link>
  <link name="arm">
    <visual>
      <origin xyz="0 0 0.2"/>
      <geometry><cylinder radius="0.04" length="0.3"/></geometry>
      <material name="orange"/>
    </visual>
    <visual>
      <geometry><mesh filename="file://{tmp_path / "cube.stl"}" scale="0.5 0.5 2"/></geometry>
    </visual>
    <visual>
      <geometry><mesh filename="file://{tmp_path / "nowhere.stl"}"/></geometry>
    </visual>
  </link>
  <link name="other">
    <visual><geometry><box size="1 1 1"/></geometry></visual>
  </link>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
  <joint name="j2" type="fixed"><parent link="arm"/><child link="other"/></joint>
</robot>
"""


def test_each_visual_is_placed_sized_and_coloured(urdf: str) -> None:
    visuals = urdf_visual_solids(urdf, ["base", "arm"])
    assert [s.frame for s in visuals.solids] == ["base", "base", "arm", "arm"]  # "other" left out
    assert len(visuals.missing) == 1 and visuals.missing[0].endswith("nowhere.stl")
    box, sphere, cylinder, cube = visuals.solids
    # the box: its corners turned a quarter about z, then moved 0.1 m along x
    corners = np.array(
        [[x, y, z] for x in (-0.1, 0.1) for y in (-0.05, 0.05) for z in (-0.025, 0.025)]
    )
    expected = corners @ rotation_z(np.pi / 2).T + [0.1, 0.0, 0.0]
    assert sorted(map(tuple, np.round(box.vertices, 9))) == sorted(
        map(tuple, np.round(expected, 9))
    )
    assert box.colour == pytest.approx((0.2, 0.4, 0.6))
    # the sphere: every vertex 0.03 m from its centre; no material: the role's colour
    distance = np.linalg.norm(sphere.vertices - [0.0, 0.0, 0.5], axis=1)
    np.testing.assert_allclose(distance, 0.03, rtol=1e-9)
    assert sphere.colour is None and sphere.rgb == pytest.approx((0.15, 0.35, 0.90))
    # the cylinder: within its radius, 0.3 m long about z = 0.2, the named material's colour
    radial = np.linalg.norm(cylinder.vertices[:, :2], axis=1)
    assert radial.max() == pytest.approx(0.04) and np.ptp(cylinder.vertices[:, 2]) == pytest.approx(
        0.3
    )
    assert cylinder.vertices[:, 2].mean() == pytest.approx(0.2)
    assert cylinder.colour == pytest.approx((1.0, 0.5, 0.0))
    # the mesh: the unit cube scaled by 0.5, 0.5, 2; its triangles cover its six faces
    np.testing.assert_allclose(np.ptp(cube.vertices, axis=0), [0.5, 0.5, 2.0])
    assert cube.triangles().shape == (12, 3)


def test_meshes_are_decimated_to_the_budget() -> None:
    from aaria_pin.core.catalogue import find_robot

    robot = find_robot("ur5")
    text = robot.urdf.read_text(encoding="utf-8")
    links = ["base_link", "shoulder_link", "upper_arm_link", "forearm_link"]
    full = urdf_visual_solids(text, links, max_triangles=10**9)
    small = urdf_visual_solids(text, links, max_triangles=8000)
    count = [sum(len(s.triangles()) for s in v.solids) for v in (full, small)]
    # the budget is approximate: quadric decimation keeps some parts' sharp features
    assert count[0] > 60_000 and count[1] < 0.3 * count[0]
    # decimation keeps the shape: each link's bounding box within 5 mm
    for link in links:
        boxes = [
            np.ptp(np.concatenate([s.vertices for s in v.solids if s.frame == link]), axis=0)
            for v in (full, small)
        ]
        np.testing.assert_allclose(boxes[1], boxes[0], atol=0.005)


_RELATIVE_MESH_URDF = """<robot name="stick">
  <link name="base"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01"
    ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="arm"><inertial><origin xyz="0 0 0.1"/><mass value="1"/><inertia ixx="0.01"
    iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><geometry><mesh filename="meshes/block.stl"/></geometry></visual></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="10" velocity="3"/></joint>
</robot>"""


def test_a_run_s_relative_meshes_are_found_in_its_urdf_folder(tmp_path: Path) -> None:
    import warnings

    import trimesh

    from aaria_pin.core.urdf_run import simulate_urdf_run
    from aaria_pin.files.runfile import write_run
    from aaria_pin.viz._model_source import load_model_run

    (tmp_path / "meshes").mkdir()
    trimesh.creation.box(extents=(0.1, 0.2, 0.3)).export(tmp_path / "meshes" / "block.stl")
    record = simulate_urdf_run(_RELATIVE_MESH_URDF, urdf_dir=tmp_path, duration=0.1, rate=50)
    run = write_run(tmp_path / "run.h5", record)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # found: no warning
        view = load_model_run(run)
    meshes = [s for s in view.scene.solids if s.frame == "arm"]
    assert meshes and meshes[0].triangles().shape[0] == 12  # the box's 12 triangles
    record.attributes["urdf_dir"] = str(tmp_path / "elsewhere")
    with pytest.warns(MeshWarning, match="meshes/block.stl"):
        load_model_run(write_run(tmp_path / "moved.h5", record))
