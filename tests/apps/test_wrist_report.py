"""The wrist's report: solutions, pose and angles against equation (9) and scipy; projection."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import wrist_equation_9
from scipy.spatial.transform import Rotation

from aaria_pin.apps.wrist.report import (
    MATRIX_TOLERANCE,
    nearest_rotation,
    workspace_report,
    wrist_report,
)
from aaria_pin.apps.wrist.wrist_kinematics import Workspace
from aaria_pin.errors import ParameterError


@pytest.mark.parametrize("order", ["xyz", "ZYX", "ZYZ", "zyz"])
def test_report_solutions_pose_and_angles(order: str) -> None:
    rng = np.random.default_rng(3)
    for q in rng.uniform([-170, 5, -170], [170, 175, 170], (5, 3)):
        T = wrist_equation_9(*np.radians(q), d=0.132)
        report = wrist_report(T[:3, :3], order)
        assert report.degrees and not report.singular and report.reachable
        assert len(report.solutions) == 2
        assert [round(v, 8) for v in q] in [[round(v, 8) for v in s] for s in report.solutions]
        for s in report.solutions:  # every solution puts the tool where equation (9) does
            np.testing.assert_allclose(wrist_equation_9(*np.radians(s), d=0.132), T, atol=1e-12)
        np.testing.assert_allclose(report.T_base_tool, T, atol=1e-12)
        expected = Rotation.from_matrix(T[:3, :3]).as_euler(order, degrees=True)
        np.testing.assert_allclose(
            Rotation.from_euler(order, report.angles, degrees=True).as_matrix(),
            Rotation.from_euler(order, expected, degrees=True).as_matrix(),
            atol=1e-12,
        )


def test_report_in_radians_with_limits_and_its_text() -> None:
    T = wrist_equation_9(0.4, -0.7, 0.2, d=0.132)  # θ2 < 0: outside the report's 0–180°
    report = wrist_report(T[:3, :3], "xyz", limits=True, degrees=False)
    assert len(report.solutions) == 1 and 0 <= report.solutions[0][1] <= np.pi
    np.testing.assert_allclose(
        wrist_equation_9(*report.solutions[0], d=0.132)[:3, :3], T[:3, :3], atol=1e-12
    )
    data = report.to_dict()
    assert data["pose"] == report.T_base_tool.tolist() and data["order"] == "xyz"
    text = report.text().splitlines()
    assert text[0] == "rotation:" and text[4].startswith("tool point [m]: ")
    assert [float(v) for v in text[4].split(":")[1].split()] == pytest.approx(T[:3, 3], abs=1e-6)
    assert text[5].startswith("angles (xyz) [rad]: ")


def test_singular_rotation_is_reported() -> None:
    report = wrist_report(np.eye(3))
    assert report.singular and len(report.solutions) == 1
    assert "singular" in report.text()


def test_nearest_rotation_projects_printed_matrices_only() -> None:
    R = Rotation.from_euler("ZYZ", [0.3, 1.1, -2.0]).as_matrix()
    same, note = nearest_rotation(R)
    assert note is None and np.array_equal(same, R)
    rounded = np.round(R, 6)
    projected, note = nearest_rotation(rounded.ravel())
    assert note is not None and note.startswith("matrix is") and "nearest rotation" in note
    np.testing.assert_allclose(projected.T @ projected, np.eye(3), atol=1e-15)
    np.testing.assert_allclose(projected, R, atol=1e-6)
    for bad in (np.diag([1, 1, 1 + 10 * MATRIX_TOLERANCE]), np.diag([1.0, 1.0, -1.0])):
        with pytest.raises(ParameterError, match="matrix is not a rotation") as caught:
            nearest_rotation(bad)
        assert caught.value.parameter == "matrix"


def test_workspace_report_numbers_and_text() -> None:
    points = np.array([[0.0, 0.0, 0.132], [0.1, 0.0, 0.0]])
    space = Workspace(points, (0.1, 0.132), np.pi, 2 * np.pi)
    summary, text = workspace_report(space)
    assert summary == {
        "radius_m": [0.1, 0.132],
        "solid_angle_sr": np.pi,
        "solid_angle_exact_sr": 2 * np.pi,
        "sphere_fraction": 0.25,
        "samples": 2,
    }
    assert "radius 132.000 mm (sampled radii 100.000-132.000 mm)" in text
    assert "(25.0% of the sphere), exactly 6.2832 sr" in text


def test_the_reports_of_joint_angles_and_of_their_rotation_agree() -> None:
    from aaria_pin.apps.wrist.report import joints_report, rotation_report
    from aaria_pin.apps.wrist.wrist_kinematics import wrist_fk

    joints = np.array([30.0, 45.0, 10.0])
    forward = joints_report(joints, "ZYZ")
    np.testing.assert_allclose(forward.T_base_tool, wrist_fk(np.radians(joints)), atol=1e-12)
    by_matrix = rotation_report(None, forward.T_base_tool[:3, :3].ravel(), "ZYZ")
    by_angles = rotation_report(forward.angles, None, "ZYZ")
    for report in (by_matrix, by_angles):
        assert any(np.allclose(q, joints, atol=1e-9) for q in report.solutions)
    radians = joints_report(np.radians(joints), "ZYZ", degrees=False)
    np.testing.assert_allclose(radians.angles, np.radians(forward.angles), atol=1e-12)
