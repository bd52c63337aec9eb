"""Files written by aaria_pin 0.1.0, of every kind, in ``info``, ``torques``, ``plot`` and ``view``.

The fixtures (``tests/fixtures/v0_1_0``, README there: the commands that wrote them) are read
by the one run record; the numbers printed are checked against the raw files, read here with
h5py and scipy, not through the package.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest
from conftest import run_cli
from scipy.io import loadmat

FIXTURES = Path(__file__).parents[1] / "fixtures" / "v0_1_0"

RUNS = (
    "dh_run.h5",
    "dh_run.mat",
    "ur5_run.h5",
    "wrist_run.h5",
    "wrist_run.mat",
    "pick_place_run.h5",
)
DATASETS = ("dh_dataset.h5", "ur5_dataset.h5")

UR5_JOINTS = (
    "shoulder_pan_joint",
    "shoulder_lift_joint",
    "elbow_joint",
    "wrist_1_joint",
    "wrist_2_joint",
    "wrist_3_joint",
)
ARM_JOINTS = ("lift", "shoulder", "elbow", "hand_yaw", "hand_pitch", "hand_roll", "finger")


def raw(name: str) -> dict[str, Any]:
    """The stored arrays of a 0.1.0 run file, read without the package."""
    path = FIXTURES / name
    if path.suffix == ".mat":
        contents = loadmat(path)
        return {k: np.asarray(v) for k, v in contents.items() if not k.startswith("__")}
    with h5py.File(path, "r") as handle:
        return {k: handle[k][()] for k in handle if isinstance(handle[k], h5py.Dataset)}


def raw_dataset(name: str) -> dict[str, Any]:
    with h5py.File(FIXTURES / name, "r") as handle:
        return {k: handle[k][()] for k in handle if isinstance(handle[k], h5py.Dataset)}


def stored_columns(name: str, arrays: dict[str, Any]) -> list[int]:
    """The columns of ``tau`` a joint of the run's model owns (an empty DH module: none)."""
    if "senSenDH" in arrays:
        return [row for row in range(6) if arrays["senSenDH"][row, 4] != 0]
    return list(range(arrays["tau"].reshape(arrays["tau"].shape[0], -1).shape[1]))


def embedded_frames(page: str) -> list[str]:
    match = re.search(r'<script type="application/json" id="data">(.*?)</script>', page, re.S)
    assert match
    return list(json.loads(match.group(1))["frames"])


@pytest.mark.parametrize("name", RUNS + DATASETS)
def test_info_reads_every_old_file(name: str) -> None:
    code, out, err = run_cli("info", str(FIXTURES / name))
    assert code == 0, err
    assert out.startswith(f"{FIXTURES / name}:") and len(out.splitlines()) >= 4


@pytest.mark.parametrize("name", RUNS)
def test_torques_of_an_old_run_file_are_its_stored_peaks(name: str) -> None:
    """Peak |tau| per joint equals the stored tau's; the split adds up to the stored tau."""
    code, out, err = run_cli("torques", str(FIXTURES / name), "--json")
    assert code == 0, err
    report = json.loads(out)
    arrays = raw(name)
    tau = np.asarray(arrays["tau"], dtype=float)
    columns = stored_columns(name, arrays)
    assert [joint["module"] for joint in report["joints"]] == [c + 1 for c in columns]
    np.testing.assert_allclose(
        [joint["peak_abs"] for joint in report["joints"]],
        np.abs(tau[:, columns]).max(axis=0),
        rtol=0,
        atol=1e-12,
    )
    assert report["samples"] == tau.shape[0]
    # the model rebuilt from the old file (DH table, URDF, wrist, arm with its payload) gives
    # back the stored torques: gravity + Coriolis + inertial = tau at every sample
    assert report["split_residual"] < 1e-8 * max(1.0, float(np.abs(tau).max()))
    if "base_wrench" in arrays:
        peaks = np.abs(np.asarray(arrays["base_wrench"], dtype=float)).max(axis=0)
        np.testing.assert_allclose(list(report["base_wrench_peak"].values()), peaks, atol=1e-12)
    code, text, err = run_cli("torques", str(FIXTURES / name))
    assert code == 0, err
    assert "base wrench peaks" in text and f"{report['joints'][0]['peak_abs']:.4g}" in text


def test_torques_names_the_joints_of_each_robot() -> None:
    for name, joints in (
        ("dh_run.h5", ("joint1", "joint3", "joint4", "joint5", "joint6")),  # fig3: module 2 empty
        ("ur5_run.h5", UR5_JOINTS),
        ("wrist_run.mat", ("joint1", "joint2", "joint3")),
        ("pick_place_run.h5", ARM_JOINTS),
    ):
        code, out, err = run_cli("torques", str(FIXTURES / name), "--json")
        assert code == 0, err
        assert tuple(j["joint"] for j in json.loads(out)["joints"]) == joints


@pytest.mark.parametrize("name", DATASETS)
def test_torques_of_an_old_dataset_are_its_stored_peaks(name: str) -> None:
    arrays = raw_dataset(name)
    tau = np.asarray(arrays["tau"], dtype=float)  # runs × T × 6
    code, out, err = run_cli("torques", str(FIXTURES / name), "--json")
    assert code == 0, err
    summary = json.loads(out)
    expected: dict[tuple[str, str], list[float]] = {}
    for run in range(tau.shape[0]):
        for column in range(6):
            if "senSenDH" in arrays:
                kind = {1: "revolute", 2: "prismatic"}.get(int(arrays["senSenDH"][run, column, 4]))
                if kind is None:
                    continue
            else:
                kind = "revolute"  # every joint of the UR5
            peak = float(np.abs(tau[run, :, column]).max())
            expected.setdefault((str(column + 1), kind), []).append(peak)
    found = {
        (module, kind): stats for module, kinds in summary["by_module"].items()
        for kind, stats in kinds.items()
    }  # fmt: skip
    assert set(found) == set(expected)
    for key, peaks in expected.items():
        assert found[key]["runs"] == len(peaks)
        assert found[key]["max"] == pytest.approx(max(peaks), rel=1e-12)
    assert summary["largest"][0]["peak_abs"] == pytest.approx(
        max(max(p) for p in expected.values()), rel=1e-12
    )
    code, out, err = run_cli("torques", str(FIXTURES / name), "--run", "1", "--json")
    assert code == 0, err
    one = json.loads(out)
    columns = [int(module) - 1 for module in (j["module"] for j in one["joints"])]
    np.testing.assert_allclose(
        [j["peak_abs"] for j in one["joints"]], np.abs(tau[1][:, columns]).max(axis=0), atol=1e-12
    )


def png_size(path: Path) -> tuple[int, int]:
    from PIL import Image

    with Image.open(path) as image:
        return image.size


@pytest.mark.parametrize("name", RUNS + DATASETS)
def test_plot_and_view_of_every_old_file(tmp_path: Path, name: str) -> None:
    path = FIXTURES / name
    extra = ["--run", "1"] if name in DATASETS else []
    if name in DATASETS:
        samples = int(raw_dataset(name)["q"].shape[1])
    else:
        samples = int(np.asarray(raw(name)["q"]).shape[0])
    png, page = tmp_path / "run.png", tmp_path / "run.html"
    code, out, err = run_cli("plot", str(path), *extra, "--width", "800", "-o", str(png))
    assert code == 0, err
    assert f", {samples} samples" in out
    assert png_size(png)[0] == 800 and png.stat().st_size > 10_000
    code, out, err = run_cli("view", str(path), *extra, "--max-samples", "5", "-o", str(page))
    assert code == 0, err
    assert f" {min(5, samples)} of {samples} samples" in out
    frames = embedded_frames(page.read_text(encoding="utf-8"))
    if name.startswith("ur5"):
        expected: tuple[str, ...] = UR5_JOINTS  # the stick figure's joints
    elif name.startswith("pick_place"):
        expected = ("pillar", "hand", "grasp", "cylinder")  # the arm's meshes, the cylinder
    elif name.startswith("wrist"):
        expected = ("link1", "link2", "link3", "tool_tip")
    else:  # a DH arm: a link and two IMUs per non-empty module
        arrays = raw(name) if name in RUNS else {"senSenDH": raw_dataset(name)["senSenDH"][1]}
        modules = [row + 1 for row in range(6) if arrays["senSenDH"][row, 4] != 0]
        expected = ("tool_tip", *(f"link{m}" for m in modules))
        expected += tuple(f"imu_link{m}_{s}" for m in modules for s in "ab")
    assert set(expected) <= set(frames), frames
    code, out, err = run_cli("render", "--from", str(path), *extra, "--width", "300",
                             "--height", "200", "-o", str(tmp_path / "pose.png"))  # fmt: skip
    assert code == 0, err
    assert png_size(tmp_path / "pose.png") == (300, 200)


def test_plot_of_an_old_dh_run_shows_its_stored_imus(tmp_path: Path) -> None:
    """fig3 (module 2 empty): 12 IMUs, both joint kinds, the base wrench: 2 × (2 + 1 + 12)."""
    code, out, err = run_cli("plot", str(FIXTURES / "dh_run.h5"), "-o", str(tmp_path / "p.png"))
    assert code == 0, err
    assert "30 panels" in out


def test_run_option_is_for_data_sets_only(tmp_path: Path) -> None:
    code, _, err = run_cli(
        "view", str(FIXTURES / "dh_run.h5"), "--run", "1", "-o", str(tmp_path / "x.html")
    )
    assert code == 2 and re.search("--run is .*run file", err)
    assert list(tmp_path.iterdir()) == []
