"""Run files written by aaria_pin 0.1.0 read as today's RunRecord, checked against their raw
contents read by h5py and scipy directly."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest
from conftest import Rx, Rz, run_cli
from scipy.io import loadmat

from aaria_pin.core.record import RunRecord
from aaria_pin.files.runfile import is_run_file, read_run, run_file_summary, write_run

FIXTURES = Path(__file__).resolve().parents[1] / "fixtures" / "v0_1_0"
SLOTS = ["imu_base", "imu_tool", *(f"imu_link{i}_{s}" for i in range(1, 7) for s in "ab")]
PARENTS = ["base", "tool_tip", *(f"link{i}" for i in range(1, 7) for _ in "ab")]


def Ry(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1.0]])


def hand_base_pose(senB: np.ndarray, t: float) -> np.ndarray:
    """T(x, y, z)·Rx(ax)·Ry(ay)·Rz(az) from the paper's sines (row 1: x y z, row 2: angles)."""
    rows = np.repeat(senB, 3, axis=0) if senB.shape[0] == 2 else senB
    x, y, z, ax, ay, az = (A * np.sin(w * t + phase) + bias for A, bias, w, phase in rows)
    T = np.eye(4)
    T[:3, 3] = (x, y, z)
    return T @ Rx(ax) @ Ry(ay) @ Rz(az)


def raw_dh(name: str) -> dict[str, Any]:
    """The arrays and senSen column names of a 0.1.0 DH run file, as stored."""
    path = FIXTURES / name
    if path.suffix == ".mat":
        contents = loadmat(path)
        raw = {k: v for k, v in contents.items() if not k.startswith(("__", "attr_"))}
        raw["columns"] = [str(cell.item()) for cell in contents["senSen_columns"].ravel()]
        return raw
    with h5py.File(path, "r") as handle:
        raw = {name: handle[name][()] for name in handle}
        raw["columns"] = [str(c) for c in handle["senSen"].attrs["columns"]]
    return raw


@pytest.mark.parametrize("name", ["dh_run.h5", "dh_run.mat"])
def test_dh_run(name: str) -> None:
    raw = raw_dh(name)
    record = read_run(FIXTURES / name)
    sensen = raw["senSen"]
    samples = sensen.shape[0]
    assert samples == 11
    assert record.attributes["kind"] == "dh"
    assert record.attributes["robot"] == "aaria-arm"  # as the runs of a 0.1 data set
    assert record.attributes["version"] == "0.1.0"
    assert record.joint_names == tuple(f"joint{i}" for i in range(1, 7))
    assert list(record.imu_names) == SLOTS
    assert raw["columns"][7::6] == [f"{slot}_wx" for slot in SLOTS]
    np.testing.assert_array_equal(record.time, sensen[:, 0])
    np.testing.assert_array_equal(record.q, sensen[:, 1:7])
    for s, slot in enumerate(SLOTS):
        for k, signal in enumerate(("wx", "wy", "wz", "fx", "fy", "fz")):
            column = raw["columns"].index(f"{slot}_{signal}")
            np.testing.assert_array_equal(record.imu[:, s, k], sensen[:, column])
            np.testing.assert_array_equal(record.imu_signals(slot)[:, k], sensen[:, column])
    for array in ("q", "qd", "qdd", "tau", "base_wrench", "tool_pose", "imu_mount"):
        np.testing.assert_array_equal(getattr(record, array), raw[array], err_msg=array)
    for table in ("senSenDH", "senSenJ", "senSenB"):
        np.testing.assert_array_equal(record.tables[table], raw[table])
    assert record.view("senSen").tobytes() == np.ascontiguousarray(sensen).tobytes()
    assert record.views["senSen"].columns == tuple(raw["columns"])
    # an empty module's slots (link type 0) have a zero mount and parent ""
    empty = {i + 1 for i, row in enumerate(raw["senSenDH"][:6]) if row[4] == 0}
    assert bool(empty) == (name == "dh_run.h5")  # aaria-fig3 has an empty module, fig2 none
    for slot, parent, mount, expected in zip(
        SLOTS, PARENTS, record.imu_mounts, raw["imu_mount"], strict=True
    ):
        module = int(slot[8]) if slot.startswith("imu_link") else None
        assert mount.name == slot
        assert mount.parent == ("" if module in empty else parent), slot
        assert (not np.any(expected)) == (module in empty), slot
    for k, t in enumerate(sensen[:, 0]):
        np.testing.assert_allclose(
            record.base_pose[k], hand_base_pose(raw["senSenB"], t), rtol=0, atol=1e-14
        )
    assert np.ptp(record.base_pose[:, 0, 3]) > 0  # the base moves in these runs


def test_urdf_ur5_run() -> None:
    path = FIXTURES / "ur5_run.h5"
    record = read_run(path)
    with h5py.File(path, "r") as handle:
        signals = handle["signals"][()]
        columns = [str(c) for c in handle["signals"].attrs["columns"]]
        joints = [str(c) for c in handle["q"].attrs["joint_names"]]
        imus = [str(c) for c in handle["imu_mount"].attrs["imu_names"]]
        parents = [str(c) for c in handle["imu_mount"].attrs["imu_parents"]]
        raw = {name: handle[name][()] for name in handle if name not in ("signals", "urdf")}
        urdf = handle["urdf"].asstr()[()]
    assert record.attributes["kind"] == "urdf"
    assert record.attributes["robot"] == "ur5"
    assert list(record.joint_names) == joints and len(joints) == 6
    assert list(record.imu_names) == imus and len(imus) == 14
    assert [m.parent for m in record.imu_mounts] == parents
    assert record.urdf == urdf and "<robot" in urdf
    np.testing.assert_array_equal(record.time, signals[:, 0])
    for j, joint in enumerate(joints):
        np.testing.assert_array_equal(record.q[:, j], signals[:, columns.index(f"q:{joint}")])
    for s, imu in enumerate(imus):
        for k, signal in enumerate(("wx", "wy", "wz", "fx", "fy", "fz")):
            np.testing.assert_array_equal(
                record.imu[:, s, k], signals[:, columns.index(f"{imu}_{signal}")]
            )
    for name in ("q", "qd", "qdd", "tau", "base_pose", "base_wrench", "tool_pose", "imu_mount"):
        np.testing.assert_array_equal(getattr(record, name), raw[name], err_msg=name)
    assert set(record.tables) == {"joint_table", "base_table"}
    for name in record.tables:
        np.testing.assert_array_equal(record.tables[name], raw[name])
    np.testing.assert_array_equal(record.signals(), signals)


def test_pick_place_run() -> None:
    path = FIXTURES / "pick_place_run.h5"
    record = read_run(path)
    with h5py.File(path, "r") as handle:
        signals = handle["signals"][()]
        raw = {name: handle[name][()] for name in ("q", "tau", "base_pose", "base_wrench")}
        task = handle.attrs["task"]
    assert task == "pick-place"
    assert record.attributes["kind"] == "pick-place"
    assert record.attributes["robot"] == "pick-place-arm"
    assert record.joint_names[0] == "lift" and len(record.joint_names) == 7
    assert record.imu.shape == (57, 0, 6)
    assert record.imu_mounts == ()
    np.testing.assert_array_equal(record.time, signals[:, 0])
    for name, array in raw.items():
        np.testing.assert_array_equal(getattr(record, name), array, err_msg=name)


@pytest.mark.parametrize("name", ["wrist_run.h5", "wrist_run.mat"])
def test_wrist_run(name: str) -> None:
    path = FIXTURES / name
    if path.suffix == ".mat":
        raw = loadmat(path)
        raw["time"] = raw["time"].ravel()
        targets = raw["targets_rad"].ravel().tolist()
        speed = raw["speed_rad_s"].item()
    else:
        with h5py.File(path, "r") as handle:
            raw = {k: handle[k][()] for k in handle}
            targets = handle.attrs["targets_rad"].tolist()
            speed = handle.attrs["speed_rad_s"]
    record = read_run(path)
    assert record.attributes["kind"] == "wrist"
    assert record.attributes["robot"] == "spherical-wrist"
    assert record.attributes["base_wrench_known"] is False
    assert record.attributes["targets_rad"] == targets
    np.testing.assert_allclose(targets, np.radians([10, 20, 30]), rtol=1e-15)
    assert record.attributes["speed_rad_s"] == speed
    assert record.attributes["profile"] == "trapezoid"
    assert record.joint_names == ("joint1", "joint2", "joint3")
    for array in ("time", "q", "qd", "qdd", "tau", "tool_pose"):
        np.testing.assert_array_equal(getattr(record, array), raw[array], err_msg=array)
    assert record.q.shape == (11, 3)
    np.testing.assert_array_equal(record.base_pose, np.tile(np.eye(4), (11, 1, 1)))
    np.testing.assert_array_equal(record.base_wrench, np.zeros((11, 6)))
    assert record.imu.shape == (11, 0, 6)


def test_wrist_h5_and_mat_read_the_same() -> None:
    h5, mat = read_run(FIXTURES / "wrist_run.h5"), read_run(FIXTURES / "wrist_run.mat")
    for name, array in h5.arrays().items():
        np.testing.assert_array_equal(mat.arrays()[name], array, err_msg=name)
    assert mat.attributes == h5.attributes


RUNS = [
    "dh_run.h5",
    "dh_run.mat",
    "ur5_run.h5",
    "pick_place_run.h5",
    "wrist_run.h5",
    "wrist_run.mat",
]
KINDS = {"dh": "dh", "ur5": "urdf", "pick": "pick-place", "wrist": "wrist"}


@pytest.mark.parametrize("name", RUNS)
def test_rewritten_as_version_2(tmp_path: Path, name: str) -> None:
    record = read_run(FIXTURES / name)
    for suffix in (".h5", ".mat"):
        read = read_run(write_run(tmp_path / f"run{suffix}", record))
        assert_same(read, record)


def assert_same(read: RunRecord, record: RunRecord) -> None:
    for array_name, array in record.arrays().items():
        np.testing.assert_array_equal(read.arrays()[array_name], array, err_msg=array_name)
    assert read.joint_names == record.joint_names
    assert read.imu_mounts.__len__() == len(record.imu_mounts)
    assert [(m.name, m.parent) for m in read.imu_mounts] == [
        (m.name, m.parent) for m in record.imu_mounts
    ]
    for view in record.views:
        np.testing.assert_array_equal(read.view(view), record.view(view))
    assert read.attributes == record.attributes


@pytest.mark.parametrize("name", RUNS)
def test_summary_and_info(name: str) -> None:
    path = FIXTURES / name
    kind = KINDS[name.split("_")[0]]
    assert is_run_file(path)
    summary = run_file_summary(path)
    assert summary["kind"] == kind
    assert summary["format_version"] == 1
    assert summary["samples"] == read_run(path).n_samples
    code, out, err = run_cli("info", str(path))
    assert code == 0, err
    assert f": {kind} run of " in out
    assert "format version 1" in out
    if kind == "dh":
        assert "senSen        11 × 91 (view)" in out
        assert "at 100 Hz" in out
    if kind == "wrist":
        assert "at 20 Hz" in out  # from the sample times: 0.1.0 stored no rate


@pytest.mark.parametrize("name", ["dh_dataset.h5", "ur5_dataset.h5"])
def test_info_on_datasets(name: str) -> None:
    path = FIXTURES / name
    assert not is_run_file(path)
    code, out, err = run_cli("info", str(path))
    assert code == 0, err
    assert "data set of" in out
