"""Data sets written by aaria_pin 0.1.0 (format version 1) still read, and re-make from inputs.

The fixtures are ``tests/fixtures/v0_1_0/dh_dataset.h5`` (Aaria arms: ``senSen`` N × T × 91 …)
and ``ur5_dataset.h5`` (a URDF robot: ``layout_json``, ``signals``); their README lists the
commands that wrote them. Every number a record gives is checked against the raw h5py contents.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest
from click.testing import CliRunner
from scipy.spatial.transform import Rotation

from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.apps.dataset.generate import generate_dataset
from aaria_pin.apps.dataset.urdf_spec import UrdfDatasetSpec, UrdfSource
from aaria_pin.cli import main
from aaria_pin.core.catalogue import find_robot
from aaria_pin.core.seeds import stored_seed
from aaria_pin.core.urdf_robot import read_urdf_file
from aaria_pin.errors import InputFileError
from aaria_pin.files.dataset.reader import DatasetReader
from aaria_pin.files.dataset.summary import dataset_summary
from aaria_pin.files.detection import is_dataset_file

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures" / "v0_1_0"
DH_SET = FIXTURES / "dh_dataset.h5"
UR5_SET = FIXTURES / "ur5_dataset.h5"
F32 = {"rtol": 2.0**-23, "atol": 0.0}  # one float32 rounding step


def _raw(path: Path, run: int) -> dict[str, np.ndarray]:
    with h5py.File(path, "r") as handle:
        return {
            name: handle[name][run]
            for name in handle
            if handle[name].ndim > 1 and handle[name].shape[0] == handle.attrs["N"]
        }


def _base_pose(table: np.ndarray, time: np.ndarray) -> np.ndarray:
    """T_world_base from a 6 × 4 base table, computed here: sines, then Rx·Ry·Rz."""
    amplitude, bias, frequency, phase = table.T
    x = bias + amplitude * np.sin(np.outer(time, frequency) + phase)
    pose = np.zeros((time.size, 4, 4))
    pose[:, :3, :3] = Rotation.from_euler("XYZ", x[:, 3:]).as_matrix()
    pose[:, :3, 3] = x[:, :3]
    pose[:, 3, 3] = 1.0
    return pose


@pytest.mark.parametrize("run", [0, 1, 2])
def test_dh_dataset_records_equal_the_raw_contents(run: int) -> None:
    raw = _raw(DH_SET, run)
    samples = raw["senSen"].shape[0]
    with DatasetReader(DH_SET) as reader:
        assert reader.version == 1 and len(reader) == 3
        record = reader.record(run)
    sensen = raw["senSen"]
    np.testing.assert_array_equal(record.time, sensen[:, 0])
    np.testing.assert_array_equal(record.q, sensen[:, 1:7])
    np.testing.assert_array_equal(record.imu, sensen[:, 7:].reshape(samples, 14, 6))
    np.testing.assert_array_equal(record.view("senSen"), sensen)
    np.testing.assert_array_equal(record.imu_signals("imu_link1_b")[:, 5], sensen[:, 7 + 3 * 6 + 5])
    for name in ("qd", "qdd", "tau", "base_wrench", "tool_pose"):
        np.testing.assert_array_equal(getattr(record, name), raw[name], err_msg=name)
    np.testing.assert_array_equal(record.imu_mount, raw["imu_mount"])
    for name in ("senSenDH", "senSenJ", "senSenB"):
        np.testing.assert_array_equal(record.tables[name], raw[name], err_msg=name)
    np.testing.assert_allclose(
        record.base_pose, _base_pose(raw["senSenB"], record.time), atol=1e-12
    )
    assert record.joint_names == tuple(f"joint{m}" for m in range(1, 7))
    empty = raw["senSenDH"][:6, 4] == 0
    parents = [mount.parent for mount in record.imu_mounts]
    assert parents[:2] == ["base", "tool_tip"]
    for module in range(6):
        expected = "" if empty[module] else f"link{module + 1}"
        assert parents[2 + 2 * module : 4 + 2 * module] == [expected, expected]
    assert record.attributes["kind"] == "dh" and record.attributes["run"] == run
    assert record.attributes["robot"] == "aaria-arm"
    seed = stored_seed(record.attributes)
    assert isinstance(seed, np.random.SeedSequence)
    assert (seed.entropy, seed.spawn_key) == (5, (run, 3))


@pytest.mark.parametrize("run", [0, 1])
def test_ur5_dataset_records_equal_the_raw_contents(run: int) -> None:
    raw = _raw(UR5_SET, run)
    signals = raw["signals"]
    samples = signals.shape[0]
    with DatasetReader(UR5_SET) as reader:
        record = reader.record(run)
        robot = reader.attributes["robot"]
    with h5py.File(UR5_SET, "r") as handle:
        urdf = handle["urdf"].asstr()[()]
    assert record.joint_names == tuple(robot["joint_names"])
    assert record.imu_names == tuple(robot["imu_names"])
    assert [m.parent for m in record.imu_mounts] == robot["imu_parents"]
    np.testing.assert_array_equal(record.time, signals[:, 0])
    np.testing.assert_array_equal(record.q, signals[:, 1:7])
    np.testing.assert_array_equal(record.imu, signals[:, 7:].reshape(samples, 14, 6))
    np.testing.assert_array_equal(record.signals(), signals)
    np.testing.assert_array_equal(record.view("signals"), signals)
    for name in ("qd", "qdd", "tau", "base_wrench", "tool_pose", "imu_mount"):
        np.testing.assert_array_equal(getattr(record, name), raw[name], err_msg=name)
    for name in ("joint_table", "base_table"):
        np.testing.assert_array_equal(record.tables[name], raw[name], err_msg=name)
    np.testing.assert_allclose(
        record.base_pose, _base_pose(raw["base_table"], record.time), atol=1e-12
    )
    assert record.urdf == urdf and record.attributes["kind"] == "urdf"
    assert record.attributes["robot"] == "ur5" and record.attributes["tool_frame"] == "tool0"


def test_summary_and_detection_of_both_versions(tmp_path: Path) -> None:
    dh = dataset_summary(DH_SET)
    assert (dh["format_version"], dh["kind"], dh["runs"], dh["complete"]) == (1, "dh", 3, 3)
    assert dh["samples"] == 11 and dh["seed"] == 5 and dh["arrays"]["senSen"] == [3, 11, 91]
    ur5 = dataset_summary(UR5_SET)
    assert (ur5["kind"], ur5["runs"], ur5["robot"]["name"]) == ("urdf", 2, "ur5")
    assert ur5["arrays"]["signals"] == [2, 11, 91]
    assert is_dataset_file(DH_SET) and is_dataset_file(UR5_SET)
    assert not is_dataset_file(FIXTURES / "dh_run.h5")
    made = tmp_path / "v2.h5"
    generate_dataset(made, DhDatasetSpec(n_runs=2, seed=5, duration=0.1), workers=1)
    assert is_dataset_file(made)
    summary = dataset_summary(made)
    assert (summary["format_version"], summary["kind"], summary["complete"]) == (2, "dh", 2)
    assert summary["views"]["senSen"] == [2, 11, 91]


def test_resuming_a_version_1_data_set_is_refused(tmp_path: Path) -> None:
    copy = tmp_path / "old.h5"
    shutil.copyfile(DH_SET, copy)
    before = copy.read_bytes()
    spec = DhDatasetSpec(n_runs=3, seed=5, duration=0.1, rate=100.0)
    with pytest.raises(InputFileError, match="format version 1") as caught:
        generate_dataset(copy, spec, workers=1, resume=True)
    assert "new output" in str(caught.value) and "\n" not in str(caught.value)
    result = CliRunner().invoke(
        main,
        ["dataset", "-n", "3", "--seed", "5", "--duration", "0.1", "--resume", "-o", str(copy)],
    )
    assert result.exit_code == 2 and result.stderr.count("\n") == 1
    assert "format version 1" in result.stderr
    assert copy.read_bytes() == before


@pytest.mark.parametrize("run", [0, 1, 2])
def test_a_0_1_dh_run_is_made_again_from_its_seed_and_index(run: int) -> None:
    """The physics is unchanged: run k of the 0.1.0 data set, made again by today's engine."""
    with DatasetReader(DH_SET) as reader:
        attributes = reader.attributes
    spec = DhDatasetSpec(
        n_runs=int(attributes["N"]),
        seed=int(attributes["seed"]),
        duration=float(attributes["duration"]),
        rate=float(attributes["rate"]),
        noise=bool(attributes["noise"]),
    )
    made = spec.make_run(run)
    raw = _raw(DH_SET, run)
    np.testing.assert_allclose(made.view("senSen").astype(np.float32), raw["senSen"], **F32)
    for name in ("q", "qd", "qdd", "tau", "base_wrench", "tool_pose"):
        np.testing.assert_allclose(
            getattr(made, name).astype(np.float32), raw[name], err_msg=name, **F32
        )
    for name in ("senSenDH", "senSenJ", "senSenB"):
        np.testing.assert_array_equal(made.tables[name], raw[name], err_msg=name)
    np.testing.assert_array_equal(made.imu_mount, raw["imu_mount"])


@pytest.mark.parametrize("run", [0, 1])
def test_a_0_1_ur5_run_is_made_again_from_its_seed_and_index(run: int) -> None:
    entry = find_robot("ur5")
    spec = UrdfDatasetSpec(
        n_runs=2,
        seed=6,
        duration=0.1,
        rate=100.0,
        vary=("joints", "base"),
        robot=UrdfSource(read_urdf_file(entry.urdf), "ur5", str(entry.urdf.parent)),
    )
    made = spec.make_run(run)
    raw = _raw(UR5_SET, run)
    np.testing.assert_allclose(made.signals().astype(np.float32), raw["signals"], **F32)
    np.testing.assert_allclose(made.tau.astype(np.float32), raw["tau"], **F32)
    np.testing.assert_array_equal(made.tables["joint_table"], raw["joint_table"])
