from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from conftest import wrist_equation_9
from scipy.spatial.transform import Rotation

from aaria_pin.aaria.dh_robot import build_dh_robot
from aaria_pin.aaria.presets import get_preset
from aaria_pin.apps.wrist.wrist_kinematics import (
    REPORT_LIMITS,
    wrist_fk,
    wrist_ik,
    wrist_ik_batch,
    wrist_workspace,
)
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
    from aaria_pin.apps.wrist.wrist_kinematics import wrist_ik_batch

    R = Rotation.random(200, random_state=5).as_matrix()
    batch, singular, residual = wrist_ik_batch(R)
    assert batch.shape == (200, 2, 3) and not singular.any()
    assert residual.shape == (200,) and residual.max() < 2e-15
    for k in range(200):
        np.testing.assert_allclose(batch[k], wrist_ik(R[k]).solutions, atol=1e-12)
        for q in batch[k]:
            np.testing.assert_allclose(wrist_fk(q)[:3, :3], R[k], atol=1e-12)


def test_workspace_is_a_sphere_and_its_solid_angle() -> None:
    from aaria_pin.apps.wrist.wrist_kinematics import wrist_workspace

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


def _fk_scipy(q: np.ndarray) -> np.ndarray:
    """The wrist's rotation Rz(θ1)·Ry(θ2)·Rz(θ3) by scipy (independent of wrist_fk)."""
    return Rotation.from_euler("ZYZ", np.reshape(q, (-1, 3))).as_matrix()


@pytest.mark.parametrize("delta", [9e-10, 1e-10, 1e-11, 1e-12, 3e-13])
def test_near_the_singularity_every_solution_is_exact(delta: float) -> None:
    # the issue: AssertionError on 5 to 282 of 300 such rotations, batch solutions off by 6e-6
    rng = np.random.default_rng(int(-np.log10(delta) * 10))
    q = rng.uniform(-np.pi, np.pi, (300, 3))
    q[:, 1] = np.where(rng.random(300) < 0.5, delta, np.pi - delta) * rng.choice([-1, 1], 300)
    R = _fk_scipy(q)
    batch = wrist_ik_batch(R)
    assert batch.singular.all() and batch.residual.max() < 2e-15
    for k in range(2):
        np.testing.assert_allclose(_fk_scipy(batch.solutions[:, k]), R, atol=2e-15)
    for Rk in R[:100]:
        for limits in (None, REPORT_LIMITS):
            result = wrist_ik(Rk, limits)
            assert result.singular and result.reachable and result.residual < 2e-15
            np.testing.assert_allclose(_fk_scipy(result.solutions), [Rk], atol=2e-15)


def test_solutions_are_in_the_half_open_range() -> None:
    R = Rotation.random(500, random_state=9).as_matrix()
    half_turns = _fk_scipy(np.array([[np.pi, 0.4, np.pi], [-np.pi, 2.0, 0.0], [0.0, 1.0, np.pi]]))
    R = np.concatenate([R, half_turns, np.where(np.abs(half_turns) < 1e-15, -0.0, half_turns)])
    solutions = wrist_ik_batch(R).solutions
    assert np.all((solutions > -np.pi) & (solutions <= np.pi))
    for Rk in R:
        q = wrist_ik(Rk).solutions
        assert np.all((q > -np.pi) & (q <= np.pi))


def test_singular_family_is_searched_within_the_limits() -> None:
    # the issue: (30°, 0, 20°) is inside θ3 ∈ [10°, 30°], but only θ3 = 0 was tried
    R = _fk_scipy(np.radians([30.0, 0.0, 20.0]))[0]
    limits = np.radians([[-180.0, 180.0], [-180.0, 180.0], [10.0, 30.0]])
    result = wrist_ik(R, limits)
    assert result.singular and result.reachable
    np.testing.assert_allclose(np.degrees(result.solutions), [[30.0, 0.0, 20.0]], atol=1e-12)
    flipped = _fk_scipy(np.radians([100.0, 180.0, -40.0]))[0]  # θ2 = π: θ1 − θ3 is fixed
    member = wrist_ik(flipped, np.radians([[0.0, 360.0], [0.0, 180.0], [-60.0, -50.0]]))
    assert member.reachable and -60.0 <= np.degrees(member.solutions[0, 2]) <= -50.0
    np.testing.assert_allclose(_fk_scipy(member.solutions), [flipped], atol=2e-15)


def test_singular_family_search_agrees_with_a_brute_force_scan() -> None:
    rng = np.random.default_rng(21)
    found = 0
    for _ in range(300):
        q = np.array([rng.uniform(-np.pi, np.pi), rng.choice([0.0, np.pi]), 0.0])
        R = _fk_scipy(q)[0]
        low = rng.uniform(-2 * np.pi, 2 * np.pi, 3)
        limits = np.column_stack([low, low + rng.uniform(0.05, 1.5, 3)])
        limits[1] = [-0.1, 0.1] if q[1] == 0.0 else [np.pi - 0.1, np.pi + 0.1]
        # brute force: θ3 on a fine grid, θ1 from the fixed sum or difference, wrapped
        theta3 = np.linspace(limits[2, 0], limits[2, 1], 20_001)
        theta1 = q[0] - theta3 if q[1] == 0.0 else q[0] + theta3
        theta1 = limits[0, 0] + np.mod(theta1 - limits[0, 0], 2 * np.pi)
        scan = bool(np.any(theta1 <= limits[0, 1]))
        result = wrist_ik(R, limits)
        assert result.reachable or not scan  # the scan may miss a sliver
        if result.reachable:
            found += 1
            s = result.solutions[0]
            assert np.all((s >= limits[:, 0] - 1e-12) & (s <= limits[:, 1] + 1e-12))
            np.testing.assert_allclose(_fk_scipy(s)[0], R, atol=2e-15)
    assert found > 50


@pytest.mark.parametrize(
    ("limits", "pattern"),
    [
        ([[0, 1], [0, np.inf], [0, 1]], r"limits of joint 2 are \[0, inf\] rad \(not finite\)"),
        ([[0, 1], [0, 1], [np.nan, 1]], r"joint 3 are \[nan, 1\] rad \(not finite\)"),
        ([[1, 0], [0, 1], [0, 1]], r"joint 1 are \[1, 0\] rad \(reversed\)"),
        ([[0, 1], [0, 1]], r"shape \(2, 2\)"),
    ],
)
def test_bad_limits_name_the_joint(limits, pattern: str) -> None:
    with pytest.raises(ParameterError, match=pattern) as caught:
        wrist_ik(np.eye(3), limits)
    assert "np.float64" not in str(caught.value)
    with pytest.raises(ParameterError, match=pattern):
        wrist_workspace(100, limits)


def test_nan_joint_angles_are_named() -> None:
    with pytest.raises(ParameterError, match=r"hold nan at θ2; allowed: finite numbers"):
        wrist_fk([0.1, np.nan, 0.3])
    with pytest.raises(ParameterError, match=r"shape \(2,\)"):
        wrist_fk([0.1, 0.2])
