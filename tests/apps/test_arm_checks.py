"""The pick-place arm's grasp geometry, input checks, stored URDF and mount wrench."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from click.testing import CliRunner

from aaria_pin.apps.arm.dims import ArmDimensions, grasp_offset, height_limits
from aaria_pin.apps.arm.parts import mesh_inertia
from aaria_pin.apps.arm.payload import payload_inertia, with_payload
from aaria_pin.apps.arm.preset import arm_parts, build_arm_model
from aaria_pin.apps.arm.run import simulate_pick_place, write_pick_place_run
from aaria_pin.apps.arm.task import Cylinder, plan_pick_place
from aaria_pin.cli import main
from aaria_pin.errors import ParameterError

DIMS = ArmDimensions()
G = 9.81


def link_poses(robot, q: np.ndarray, frames: list[str]) -> np.ndarray:
    """World poses (T, F, 4, 4) of frames at joint values (T, 7), one Pinocchio call each."""
    model, data = robot.model, robot.model.createData()
    out = np.empty((len(q), len(frames), 4, 4))
    for k, qk in enumerate(q):
        pin.framesForwardKinematics(model, data, qk)
        for j, name in enumerate(frames):
            out[k, j] = data.oMf[model.getFrameId(name, pin.FrameType.BODY)].homogeneous
    return out


def rnea_at_rest(robot, trajectory, payload=None):
    """Joint torques and mount wrench by Pinocchio's RNEA, the base at rest, loaded if asked."""
    from dataclasses import replace

    from aaria_pin.core.dynamics import inverse_dynamics
    from aaria_pin.core.trajectory import BaseMotion

    if payload is not None:
        robot = replace(robot, model=with_payload(robot.model, payload))
    return inverse_dynamics(robot, BaseMotion.resting(trajectory.q.shape[0]), trajectory)


def still(q: np.ndarray):
    """A trajectory that rests at joint values (T, 7)."""
    from aaria_pin.core.trajectory import JointTrajectory

    zero = np.zeros_like(q)
    return JointTrajectory(np.zeros(len(q)), q, zero, zero.copy())


def _palm_and_fingertips(dims: ArmDimensions) -> tuple[float, float]:
    """Depth of the palm's lower face and of the fingertips in the hand frame, from the mesh."""
    hand = arm_parts(dims)["hand"].mesh
    bodies = hand.split(only_watertight=False)
    palm = max(bodies, key=lambda body: np.ptp(body.vertices[:, 0]))  # the widest along x
    return float(palm.vertices[:, 2].max()), float(hand.vertices[:, 2].max())


@pytest.mark.parametrize("share", [0.0, 0.25, 0.5, 0.75, 1.0])
def test_held_cylinder_stays_below_the_palm_over_the_accepted_heights(share: float) -> None:
    low, high = height_limits(DIMS)
    assert low < 0.12 < high  # the default cylinder is accepted
    h = low + share * (high - low)
    cylinder = Cylinder(0.45, -0.2, radius=0.035, height=h)
    path = plan_pick_place(DIMS, cylinder, (-0.2, 0.5))
    model = build_arm_model(DIMS, (cylinder.radius, h))
    k = int(np.argmax(path.held))  # the first held sample: the cylinder still on the floor
    hand = link_poses(model, path.q[k : k + 1], ["hand"])[0, 0]
    palm, tips = _palm_and_fingertips(DIMS)
    # the cylinder's top and middle on its axis, in the hand frame (z points down)
    world = np.array([[cylinder.x, cylinder.y, h, 1.0], [cylinder.x, cylinder.y, h / 2, 1.0]])
    top, middle = (np.linalg.inv(hand) @ world.T).T[:, 2]
    assert top > palm + 1e-6  # below the palm's face: not into the palm
    assert middle <= tips + 1e-9  # the fingers reach its half height
    fingertip_height = hand[2, 3] - tips  # hand pointing straight down
    assert fingertip_height > 0.0


@pytest.mark.parametrize("height", [0.07, 0.16])
def test_cylinders_the_hand_cannot_hold_are_refused(height: float) -> None:
    with pytest.raises(ParameterError, match=f"cylinder height {height} m; allowed"):
        plan_pick_place(DIMS, Cylinder(0.45, -0.2, height=height), (-0.2, 0.5))


def test_stored_urdf_grasp_frame_is_the_stored_tool_pose(tmp_path) -> None:
    from aaria_pin.files.runfile import read_run

    run = simulate_pick_place(Cylinder(0.45, 0.25, radius=0.045, height=0.1), (-0.3, 0.35))
    record = read_run(write_pick_place_run(tmp_path / "run.h5", run))
    model = pin.buildModelFromXML(record.urdf)
    data = model.createData()
    frame = model.getFrameId(record.attributes["tool_frame"])
    for k in np.linspace(0, len(record.q) - 1, 7).astype(int):
        pin.framesForwardKinematics(model, data, record.q[k])
        np.testing.assert_allclose(data.oMf[frame].homogeneous, record.tool_pose[k], atol=1e-12)


@pytest.mark.parametrize(
    ("cylinder", "place", "what", "dims"),
    [
        ((0.11, 0.0), (0.4, 0.3), "cylinder", ArmDimensions(foot_size=0.08)),  # inner rim
        ((0.4, 0.3), (-0.1, -0.71), "place", DIMS),  # outer rim
        ((0.72, 0.0), (0.4, 0.3), "cylinder", DIMS),
    ],
)
def test_out_of_reach_names_what_was_typed(cylinder, place, what, dims) -> None:
    c = Cylinder(*cylinder, radius=0.045, height=0.1)
    with pytest.raises(ParameterError) as error:
        plan_pick_place(dims, c, place)
    message = str(error.value)
    x, y = cylinder if what == "cylinder" else place
    assert message.startswith(f"{what} ({x:g}, {y:g}) m")
    assert "0.015 m out from the wrist" in message  # -0.03 + 0.045: the grasp point's offset
    assert "reachable annulus 0.1 m <= r <= 0.7 m" in message
    assert "allowed: " + what + " at 0.115 to 0.715 m" in message
    assert error.value.parameter == what and error.value.value == (x, y)


def test_cli_out_of_reach_message_names_the_cylinder(tmp_path) -> None:
    out = tmp_path / "run.h5"
    result = CliRunner().invoke(
        main,
        [*"arm pick-place --cylinder 0.72 0 --place 0.3 0.3 --radius 0.045 -o".split(), str(out)],
    )
    assert result.exit_code == 2 and not out.exists()
    assert "cylinder (0.72, 0) m at 0.72 m from the pillar's axis is out of reach" in result.output


@pytest.mark.parametrize(
    ("cylinder", "place"),
    [((0.12, 0.0), (0.4, 0.3)), ((0.4, 0.3), (0.0, -0.17)), ((0.4, 0.3), (-0.16, 0.16))],
)
def test_cylinders_on_the_foot_plate_are_refused(cylinder, place) -> None:
    with pytest.raises(ParameterError, match="foot plate"):
        plan_pick_place(DIMS, Cylinder(*cylinder), place)
    plan_pick_place(DIMS, Cylinder(0.4, 0.3), (0.2, 0.2))  # 0.071 m from the plate's corner


def _mount_wrench_by_hand(
    q: np.ndarray, cylinder: Cylinder | None, lift_acceleration: float = 0.0
) -> np.ndarray:
    """The mount holds up every part's weight (and the cylinder's), and accelerates all but the
    pillar straight up when only the lift moves: m·(g + a) on each, as forces at the centres."""
    parts = arm_parts(DIMS)
    model = build_arm_model(DIMS)
    poses = link_poses(model, q[None], list(parts))[0]
    forces, centres = [], []
    for T, (name, part) in zip(poses, parts.items(), strict=True):
        props = mesh_inertia(part.mesh, part.density)
        up = G if name == "pillar" else G + lift_acceleration
        forces.append(np.array([0.0, 0.0, props.mass * up]))
        centres.append(T[:3, :3] @ props.com + T[:3, 3])
    if cylinder is not None:
        hand = poses[list(parts).index("hand")]
        forces.append(np.array([0.0, 0.0, cylinder.mass * (G + lift_acceleration)]))
        centres.append((hand @ grasp_offset(DIMS, cylinder.radius, cylinder.height))[:3, 3])
    force = sum(forces)
    moment = sum(np.cross(c, f) for f, c in zip(forces, centres, strict=True))
    return np.concatenate([force, moment])


def test_mount_wrench_is_the_weight_of_arm_and_payload() -> None:
    cylinder = Cylinder(0.0, 0.0, radius=0.04, height=0.1, mass=1.5)
    q = np.array([0.5, 0.7, -1.1, 0.4, 0.9, -0.3, 0.08])  # hand tilted
    rooted = build_arm_model(DIMS, (cylinder.radius, cylinder.height), free_flyer=True)
    payload = payload_inertia(DIMS, cylinder)
    tau, wrench = rnea_at_rest(rooted, still(q[None]), payload)
    _, wrench_free = rnea_at_rest(rooted, still(q[None]))
    np.testing.assert_allclose(wrench[0], _mount_wrench_by_hand(q, cylinder), atol=1e-9)
    np.testing.assert_allclose(wrench_free[0], _mount_wrench_by_hand(q, None), atol=1e-9)
    # the joint torques are the fixed arm's
    fixed = build_arm_model(DIMS, (cylinder.radius, cylinder.height))
    tau_fixed, _ = rnea_at_rest(fixed, still(q[None]), payload)
    np.testing.assert_allclose(tau[0], tau_fixed[0], atol=1e-9)


def test_run_stores_the_mount_wrench(tmp_path) -> None:
    from aaria_pin.files.runfile import read_run

    cylinder = Cylinder(0.5, 0.2, mass=1.2)
    run = simulate_pick_place(cylinder, (-0.3, 0.4))
    expected = _mount_wrench_by_hand(run.path.q[0], None)
    np.testing.assert_allclose(run.base_wrench[0], expected, rtol=1e-12, atol=1e-9)
    lifting = run.path.held & (run.path.phase == 3)  # held, only the lift moves
    assert lifting.sum() > 10
    for k in np.flatnonzero(lifting)[::10]:
        assert np.all(run.path.qd[k, 1:] == 0) and np.all(run.path.qdd[k, 1:] == 0)
        expected = _mount_wrench_by_hand(run.path.q[k], cylinder, run.path.qdd[k, 0])
        np.testing.assert_allclose(run.base_wrench[k], expected, rtol=1e-12, atol=1e-9)
    record = read_run(write_pick_place_run(tmp_path / "run.h5", run))
    np.testing.assert_array_equal(record.base_wrench, run.base_wrench)


def _pick_place(tmp_path, *extra: str):
    out = tmp_path / "run.h5"
    args = ["arm", "pick-place", "--cylinder", "0.5", "0.2", "--place", "-0.3", "0.4"]
    return out, CliRunner().invoke(main, [*args, "-o", str(out), *extra])


@pytest.mark.parametrize(
    ("extra", "expected"),
    [
        (("--sheet", "nodir/s.png"), "no folder"),
        (("--animation", "a.gif", "--fps", "0"), "--fps 0; allowed: 1 to 50"),
        (("--sheet", "s.gif"), "allowed: .png"),
        (("--animation", "nodir/a.gif"), "no folder"),
    ],
)
def test_cli_checks_every_option_before_writing(tmp_path, monkeypatch, extra, expected) -> None:
    monkeypatch.chdir(tmp_path)
    _, result = _pick_place(tmp_path, *extra)
    assert result.exit_code == 2, result.output
    assert expected in result.output
    assert result.output.strip().count("\n") == 0  # one line
    assert list(tmp_path.iterdir()) == []  # nothing written


def test_cli_refuses_a_run_file_in_a_missing_folder(tmp_path) -> None:
    result = CliRunner().invoke(
        main,
        [*"arm pick-place --cylinder 0.5 0.2 --place -0.3 0.4 -o".split(), f"{tmp_path}/x/r.h5"],
    )
    assert result.exit_code == 2 and "no folder" in result.output
    assert result.output.strip().count("\n") == 0


def test_cli_warns_of_torques_beyond_the_effort_limits(tmp_path) -> None:
    from aaria_pin.apps.arm.preset import arm_joints

    limit = {j.name: j.effort for j in arm_joints(DIMS)}["lift"]
    _, result = _pick_place(tmp_path, "--mass", "50")  # about (8.5 + 50) kg · g on the lift
    assert result.exit_code == 0, result.output
    assert "warning: lift peak |tau|" in result.output
    assert f"effort limit {limit:g}" in result.output
    _, result = _pick_place(tmp_path, "--mass", "0.5")
    assert "warning" not in result.output
