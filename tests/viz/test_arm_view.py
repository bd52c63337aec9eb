"""Pick-place run files in the viewers: the arm's part meshes, the cylinder, the signals."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pinocchio as pin
import pytest

from aaria_pin.apps.arm.preset import arm_parts
from aaria_pin.apps.arm.run import pick_place_record, simulate_pick_place, write_pick_place_run
from aaria_pin.apps.arm.task import Cylinder
from aaria_pin.viz._arm_source import (
    CYLINDER_FRAME,
    PICK_PLACE_KIND,
    is_pick_place_run,
    load_pick_place_view,
)

CYLINDER = Cylinder(0.45, 0.25, radius=0.04, height=0.1, mass=0.8)
PLACE = (-0.3, 0.35)


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    run = simulate_pick_place(CYLINDER, PLACE, rate=50.0)
    return run, write_pick_place_run(tmp_path_factory.mktemp("view") / "pp.h5", run)


def test_probe_recognises_only_pick_place_runs(run_file, tmp_path) -> None:
    from aaria_pin.files.runfile import write_run

    run, path = run_file
    assert is_pick_place_run(path)
    record = pick_place_record(run)
    other = replace(record, attributes={**record.attributes, "task": "something else"})
    assert not is_pick_place_run(write_run(tmp_path / "other.h5", other))
    (tmp_path / "text.h5").write_text("not HDF5")
    assert not is_pick_place_run(tmp_path / "text.h5")
    assert not is_pick_place_run(tmp_path / "missing.h5")


def test_scene_is_the_arm_meshes_and_the_cylinder(run_file) -> None:
    from aaria_pin.viz.scene import posed_geometry

    run, path = run_file
    view = load_pick_place_view(path)
    assert view.kind == PICK_PLACE_KIND
    parts = arm_parts(run.dims)
    assert {s.frame for s in view.scene.solids} == {*parts, CYLINDER_FRAME}
    np.testing.assert_array_equal(view.signals.base_wrench, run.base_wrench)
    np.testing.assert_array_equal(view.signals.tau, run.tau)
    assert view.signals.q_labels[0] == "lift [m]" and view.signals.tau_labels[1] == "shoulder [N·m]"

    time = run.path.time
    held = run.path.held
    samples = np.array([0, np.flatnonzero(held)[len(np.flatnonzero(held)) // 2], time.size - 1])
    poses = view.frame_poses(samples)
    assert poses.shape == (3, len(view.scene.frames), 4, 4)
    # links: Pinocchio's poses from the URDF text, computed here independently
    model = pin.buildModelFromXML(pick_place_record(run).urdf)
    data = model.createData()
    index = {name: k for k, name in enumerate(view.scene.frames)}
    for row, k in enumerate(samples):
        pin.framesForwardKinematics(model, data, run.path.q[k])
        for name in (*parts, "grasp"):
            expected = data.oMf[model.getFrameId(name)].homogeneous
            np.testing.assert_allclose(poses[row, index[name]], expected, atol=1e-12)
    # the cylinder: on its pick spot, in the hand while held, on its place spot at the end
    centre = poses[:, index[CYLINDER_FRAME], :3, 3]
    h = CYLINDER.height
    np.testing.assert_allclose(centre[0], [CYLINDER.x, CYLINDER.y, h / 2], atol=1e-12)
    np.testing.assert_allclose(centre[1], run.tool_pose[samples[1], :3, 3], atol=1e-12)
    assert centre[1, 2] > h / 2 + 0.05  # carried off the floor
    np.testing.assert_allclose(centre[2], [*PLACE, h / 2], atol=1e-12)
    # the hand's solid is the hand mesh placed at the hand's pose
    geometry = posed_geometry(view.scene, poses[1])
    assert geometry.faces.shape[0] == sum(len(s.faces) for s in view.scene.solids)
    hand = next(s for s in view.scene.solids if s.frame == "hand")
    np.testing.assert_allclose(hand.vertices, parts["hand"].mesh.vertices)
    cylinder = next(s for s in view.scene.solids if s.frame == CYLINDER_FRAME)
    span = np.ptp(cylinder.vertices, axis=0)
    np.testing.assert_allclose(span[2], h, atol=1e-12)


def test_render_draws_the_arm(run_file, tmp_path) -> None:
    from aaria_pin.viz.render import render_geometry
    from aaria_pin.viz.scene import posed_geometry

    _, path = run_file
    view = load_pick_place_view(path)
    geometry = posed_geometry(view.scene, view.frame_poses(np.array([0]))[0])
    high = geometry.bounds()[1]
    assert high[2] == pytest.approx(0.85)  # the pillar's top
    png = render_geometry(geometry, tmp_path / "pp.png", "pp", width=300, height=240)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_viewers_load_pick_place_runs_through_the_plugin(run_file) -> None:
    from aaria_pin.viz.sources import load_run_view, run_kind

    _, path = run_file
    assert run_kind(path) == PICK_PLACE_KIND
    assert load_run_view(path).kind == PICK_PLACE_KIND


def test_preset_scene_is_the_arm_at_home() -> None:
    from aaria_pin.apps.arm.dims import ArmDimensions
    from aaria_pin.apps.arm.preset import build_arm_model
    from aaria_pin.apps.arm.task import home_pose
    from aaria_pin.viz._arm_source import PRESETS

    scene, poses = PRESETS["pick-place-arm"]()
    assert poses.shape == (len(scene.frames), 4, 4) and scene.frames[0] == "world"
    assert CYLINDER_FRAME not in scene.frames
    dims = ArmDimensions()
    model = build_arm_model(dims).model
    data = model.createData()
    pin.framesForwardKinematics(model, data, home_pose(dims))
    for k, name in enumerate(scene.frames[1:], start=1):
        expected = data.oMf[model.getFrameId(name)].homogeneous
        np.testing.assert_allclose(poses[k], expected, atol=1e-12)
