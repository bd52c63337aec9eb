"""``aaria identify --rigid/--joint``: two IMUs of one link of a simulated arm, from a recording.

The oracle is the run's own IMU mounts (``imu_mount``, each IMU's pose on its link): the two
IMUs of link 3 are one rigid body, so B's pose relative to A is ``inv(T_link_A) @ T_link_B``;
joint 3 (revolute, a DH joint) turns about the link frame's z axis, which is each of link 3's
IMU frames' z (their mounts do not turn).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from conftest import run_cli

from aaria_pin.files.source import open_record


@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    folder = tmp_path_factory.mktemp("bodies")
    run, bag = folder / "run.h5", folder / "run.mcap"
    code, _, err = run_cli(
        "simulate", "--preset", "aaria-fig2", "--duration", "8", "--rate", "200", "--motion",
        "fourier", "--seed", "7", "-o", str(run),
    )  # fmt: skip
    assert code == 0, err
    code, _, err = run_cli("export", str(run), "-o", str(bag))
    assert code == 0, err
    return run, bag


def test_rigid_pair_from_a_bag_matches_the_mounts(
    recording: tuple[Path, Path], tmp_path: Path
) -> None:
    run, bag = recording
    report = tmp_path / "pair.json"
    code, out, err = run_cli(
        "identify", "--rigid", "imu_link3_a", "imu_link3_b", str(bag), "-o", str(report)
    )
    assert code == 0, err
    assert "position of imu_link3_b in imu_link3_a [mm]" in out
    record = open_record(run, None)
    names = list(record.imu_names)
    T_a = record.imu_mount[names.index("imu_link3_a")]
    T_b = record.imu_mount[names.index("imu_link3_b")]
    T_a_b = np.linalg.inv(T_a) @ T_b
    pair = json.loads(report.read_text())["pairs"][0]
    assert np.linalg.norm(np.array(pair["position_m"]) - T_a_b[:3, 3]) < 1e-3
    R = np.array(pair["rotation"])
    angle = np.arccos(np.clip((np.trace(T_a_b[:3, :3].T @ R) - 1.0) / 2.0, -1.0, 1.0))
    assert np.degrees(angle) < 0.05
    assert abs(pair["time_offset_s"]) < 1e-4  # one clock in a simulated run


def test_joint_between_two_links_is_the_dh_axis(recording: tuple[Path, Path]) -> None:
    run, _ = recording
    code, out, err = run_cli(
        "identify", "--joint", "imu_link2_a", "imu_link3_a", str(run), "--json"
    )
    assert code == 0, err
    joint = json.loads(out)["joints"][0]
    assert joint["kind"] == "revolute"
    assert abs(abs(joint["axis_b"][2]) - 1.0) < 1e-3  # link 3's z axis in its IMU's frame


@pytest.mark.parametrize(
    ("extra", "needle"),
    [
        (["--dynamics"], "--dynamics is given with --rigid"),
        (["--urdf", "x.urdf"], "--urdf is given with --rigid"),
    ],
)
def test_other_modes_options_refused(
    recording: tuple[Path, Path], tmp_path: Path, extra: list[str], needle: str
) -> None:
    _, bag = recording
    code, _, err = run_cli("identify", "--rigid", "imu_link3_a", "imu_link3_b", str(bag), *extra)
    assert code == 2
    assert needle in err and len(err.strip().splitlines()) == 1


def test_unknown_imu_one_line(recording: tuple[Path, Path], tmp_path: Path) -> None:
    _, bag = recording
    report = tmp_path / "pair.json"
    code, _, err = run_cli(
        "identify", "--rigid", "imu_link3_a", "nope", str(bag), "-o", str(report)
    )
    assert code == 2 and len(err.strip().splitlines()) == 1 and "nope" in err
    assert not report.exists()


def test_noise_free_pair_is_a_result_different_links_fail(tmp_path: Path) -> None:
    """Without noise A's residual is ~1e-16 (A's samples set the splines): no floor to compare
    B's with; the fit is a result, and a pair on two links still fails (exit 1)."""
    run = tmp_path / "clean.h5"
    code, _, err = run_cli(
        "simulate", "--preset", "aaria-fig2", "--duration", "6", "--rate", "100", "--motion",
        "fourier", "--no-noise", "-o", str(run),
    )  # fmt: skip
    assert code == 0, err
    code, out, err = run_cli("identify", "--rigid", "imu_link3_a", "imu_link3_b", str(run))
    assert code == 0, err + out
    assert "fit failed" not in out
    code, out, _ = run_cli("identify", "--rigid", "imu_link3_a", "imu_link2_a", str(run))
    assert code == 1 and "fit failed" in out


def test_a_link_that_only_slides_is_no_result(recording: tuple[Path, Path]) -> None:
    """Link 1 of aaria-fig2 is on a prismatic joint: it hardly turns, so its two IMUs' lever arm
    is not in their signals; the fit must say it failed (exit 1), not print a pose."""
    run, _ = recording
    code, out, _ = run_cli("identify", "--rigid", "imu_link1_a", "imu_link1_b", str(run))
    assert code == 1 and "fit failed" in out
