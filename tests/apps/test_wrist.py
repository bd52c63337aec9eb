from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from conftest import wrist_equation_9
from scipy.spatial.transform import Rotation

from aaria_pin.aaria.dh_robot import build_dh_robot
from aaria_pin.aaria.presets import get_preset
from aaria_pin.apps.wrist.kinematics import REPORT_LIMITS, wrist_fk, wrist_ik
from aaria_pin.core.rotations import matrix_from_angles
from aaria_pin.errors import ParameterError


def test_fk_is_equation_9_and_pinocchio_on_the_emitted_urdf() -> None:
    q = np.random.default_rng(0).uniform(-np.pi, np.pi, (50, 3))
    T = wrist_fk(q)
    model = build_dh_robot(get_preset("spherical-wrist").table, "standard").model()
    data = model.model.createData()
    for qk, Tk in zip(q, T, strict=True):
        np.testing.assert_allclose(Tk, wrist_equation_9(*qk, d=0.132), atol=1e-14)
        pin.framesForwardKinematics(model.model, data, qk)
        np.testing.assert_allclose(Tk, data.oMf[model.frame_id("tool_tip")].homogeneous, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(T[:, :3, 3], axis=1), 0.132)  # on the sphere


def test_ik_gives_both_branches_each_reproducing_the_rotation() -> None:
    for R in Rotation.random(300, random_state=1).as_matrix():
        result = wrist_ik(R)
        assert not result.singular and len(result.solutions) == 2
        signs = np.sign(result.solutions[:, 1])
        assert set(signs) == {-1.0, 1.0}
        for q in result.solutions:
            np.testing.assert_allclose(wrist_fk(q)[:3, :3], R, atol=1e-12)


@pytest.mark.parametrize("theta2", [0.0, np.pi, 1e-12, np.pi - 1e-12])
def test_singularity_is_reported_with_a_canonical_member(theta2: float) -> None:
    q = np.array([0.7, theta2, -1.1])
    R = wrist_fk(q)[:3, :3]
    result = wrist_ik(R)
    assert result.singular and len(result.solutions) == 1
    if np.sin(theta2) == np.sin(0.0) or theta2 in (0.0, np.pi):
        assert result.solutions[0, 2] == 0.0  # exactly singular: the canonical member
    np.testing.assert_allclose(wrist_fk(result.solutions[0])[:3, :3], R, atol=1e-9)


def test_near_but_not_at_the_singularity() -> None:
    R = wrist_fk([0.3, 1e-6, 0.5])[:3, :3]
    result = wrist_ik(R)
    assert not result.singular
    for q in result.solutions:
        np.testing.assert_allclose(wrist_fk(q)[:3, :3], R, atol=1e-9)


def test_report_formulas_agree_where_they_hold_and_fail_beyond() -> None:
    # equations (6)-(8): j2 = acos(r33), j1 = asin(r23/s2), j3 = asin(r32/s2)
    q = np.radians([30.0, 45.0, 20.0])
    R = wrist_fk(q)[:3, :3]
    j2 = np.arccos(R[2, 2])
    report = np.array([np.arcsin(R[1, 2] / np.sin(j2)), j2, np.arcsin(R[2, 1] / np.sin(j2))])
    np.testing.assert_allclose(report, q, atol=1e-12)
    np.testing.assert_allclose(wrist_ik(R).solutions[0], q, atol=1e-12)
    beyond = np.radians([150.0, 45.0, -120.0])  # asin cannot return these
    assert np.any(np.all(np.isclose(wrist_ik(wrist_fk(beyond)[:3, :3]).solutions, beyond), axis=1))


def test_ik_from_angles_in_any_order() -> None:
    R = matrix_from_angles(np.radians([10.0, -40.0, 75.0]), "zyx")
    for q in wrist_ik(R).solutions:
        np.testing.assert_allclose(wrist_fk(q)[:3, :3], R, atol=1e-12)


def test_joint_limits_filter_and_unreachable() -> None:
    R = wrist_fk(np.radians([200.0, 60.0, 10.0]))[:3, :3]
    limited = wrist_ik(R, REPORT_LIMITS)
    assert limited.reachable and len(limited.solutions) == 1
    assert 0 <= limited.solutions[0, 1] <= np.pi
    narrow = np.radians([[0.0, 90.0], [0.0, 30.0], [-180.0, 180.0]])
    assert not wrist_ik(R, narrow).reachable


@pytest.mark.parametrize(
    ("matrix", "pattern"),
    [
        (np.eye(3) * 2, "not a rotation"),
        (np.diag([1.0, -1.0, 1.0]), "det = -1"),
        (np.full((3, 3), np.nan), "NaN"),
        (np.eye(2), "shape"),
    ],
)
def test_bad_matrices_are_refused(matrix, pattern: str) -> None:
    with pytest.raises(ParameterError, match=pattern):
        wrist_ik(matrix)


def test_cli_fk_and_ik(tmp_path) -> None:
    import json

    from click.testing import CliRunner

    from aaria_pin.cli import main

    result = CliRunner().invoke(main, ["wrist", "fk", "-30", "45", "10", "--json"])
    assert result.exit_code == 0, result.output
    out = json.loads(result.stdout)
    np.testing.assert_allclose(
        out["pose"], wrist_equation_9(*np.radians([-30, 45, 10]), d=0.132), atol=1e-12
    )
    assert [-30.0, 45.0, 10.0] in [[round(v, 9) for v in s] for s in out["solutions"]]
    result = CliRunner().invoke(
        main, ["wrist", "ik", "--angles", "10", "-40", "75", "--order", "ZYX", "--json"]
    )
    out = json.loads(result.stdout)
    np.testing.assert_allclose(out["angles"], [10, -40, 75], atol=1e-9)
    for q in out["solutions"]:
        np.testing.assert_allclose(wrist_fk(np.radians(q))[:3, :3], out["rotation"], atol=1e-12)
    plain = CliRunner().invoke(main, ["wrist", "ik", "--matrix", *"1 0 0 0 1 0 0 0 1".split()])
    assert "singular" in plain.stdout
    bad = CliRunner().invoke(main, ["wrist", "ik", "--matrix", *"2 0 0 0 1 0 0 0 1".split()])
    assert bad.exit_code == 2 and "not a rotation" in bad.stderr
    both = CliRunner().invoke(main, ["wrist", "ik"])
    assert both.exit_code == 2 and "exactly one of --angles" in both.stderr


def test_batch_ik_equals_the_single_ik() -> None:
    from aaria_pin.apps.wrist.kinematics import wrist_ik_batch

    R = Rotation.random(200, random_state=5).as_matrix()
    batch, singular = wrist_ik_batch(R)
    assert batch.shape == (200, 2, 3) and not singular.any()
    for k in range(200):
        np.testing.assert_allclose(batch[k], wrist_ik(R[k]).solutions, atol=1e-12)
        for q in batch[k]:
            np.testing.assert_allclose(wrist_fk(q)[:3, :3], R[k], atol=1e-12)


def test_workspace_is_a_sphere_and_its_solid_angle() -> None:
    from aaria_pin.apps.wrist.kinematics import wrist_workspace

    full = wrist_workspace(50_000)  # the report's limits: 0-360°, 0-180°
    np.testing.assert_allclose(full.radius, (0.132, 0.132))
    np.testing.assert_allclose(full.solid_angle_exact, 4 * np.pi)  # the whole sphere
    np.testing.assert_allclose(full.solid_angle, 4 * np.pi, rtol=0.02)
    upper = wrist_workspace(50_000, np.radians([[0, 360], [0, 90], [-180, 180]]))
    np.testing.assert_allclose(upper.solid_angle_exact, 2 * np.pi)  # a hemisphere
    np.testing.assert_allclose(upper.solid_angle, 2 * np.pi, rtol=0.03)
    assert np.all(upper.points[:, 2] >= -1e-12)


def test_workspace_cli_plot(tmp_path) -> None:
    import json

    from click.testing import CliRunner

    from aaria_pin.cli import main

    png = tmp_path / "ws.png"
    result = CliRunner().invoke(
        main,
        [
            "wrist",
            "workspace",
            "--samples",
            "20000",
            "--theta2",
            "0",
            "90",
            "--plot",
            str(png),
            "--json",
        ],
    )
    assert result.exit_code == 0, result.output
    out = json.loads(result.stdout.splitlines()[0])
    assert out["sphere_fraction"] == pytest.approx(0.5, abs=0.03)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10_000
