"""The data set layout (format version 2): one set of names for every robot, views as HDF5
virtual datasets over the stored series, each number stored once."""

from __future__ import annotations

import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.apps.dataset.generate import generate_dataset
from aaria_pin.apps.dataset.urdf_spec import UrdfDatasetSpec, UrdfSource
from aaria_pin.core.catalogue import find_robot
from aaria_pin.core.record import SERIES
from aaria_pin.core.urdf_robot import read_urdf_file
from aaria_pin.files.dataset.reader import DatasetReader

SHARED = (*SERIES, "imu_mount", "joint_names", "imu_names", "imu_parents", "urdf", "signals")
"""What every data set holds, whatever the robot (besides its bookkeeping)."""
RUNS, SAMPLES = 3, 21


@pytest.fixture(scope="module")
def sets(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("layout")
    entry = find_robot("ur5")
    robot = UrdfSource(read_urdf_file(entry.urdf), "ur5", str(entry.urdf.parent))
    specs = {
        "dh": DhDatasetSpec(n_runs=RUNS, seed=2, duration=0.2),
        "ur5": UrdfDatasetSpec(
            n_runs=RUNS, seed=2, duration=0.2, vary=("joints", "base"), robot=robot
        ),
    }
    for name, spec in specs.items():
        generate_dataset(folder / f"{name}.h5", spec, workers=1)
    return {name: folder / f"{name}.h5" for name in specs}


def test_a_dh_and_a_ur5_data_set_share_their_dataset_names(sets: dict[str, Path]) -> None:
    with h5py.File(sets["dh"], "r") as dh, h5py.File(sets["ur5"], "r") as ur5:
        assert set(SHARED) <= set(dh) and set(SHARED) <= set(ur5)
        assert set(dh) - set(ur5) == {"senSenDH", "senSenJ", "senSenB", "senSen"}
        assert set(ur5) - set(dh) == {"joint_table", "base_table"}
        for name in (*SERIES, "imu_mount", "signals"):
            assert dh[name].shape == ur5[name].shape, name  # ur5: 6 joints and 14 IMUs too
            assert dh[name].dtype == ur5[name].dtype, name
        assert dh["time"].shape == (RUNS, SAMPLES) and dh["imu"].shape == (RUNS, SAMPLES, 14, 6)
        assert dh["base_pose"].shape == (RUNS, SAMPLES, 4, 4)
        assert dh["senSenDH"].shape == (RUNS, 8, 5) and dh["senSenB"].shape == (RUNS, 6, 4)
        assert dh["senSenDH"].dtype == np.float64 and dh["imu"].dtype == np.float32
        assert dh.attrs["format_version"] == 2 and dh.attrs["kind"] == "dh"
        assert ur5.attrs["kind"] == "urdf" and ur5.attrs["robot"] == "ur5"
        assert list(dh["joint_names"].asstr()[()]) == [f"joint{m}" for m in range(1, 7)]
        assert ur5["urdf"].asstr()[()] == read_urdf_file(find_robot("ur5").urdf)
        stored = [name for name in dh if not dh[name].is_virtual]
        assert all(name not in stored for name in ("senSen", "signals"))  # views, not copies


@pytest.mark.parametrize("run", [0, 2])
def test_sensen_read_by_h5py_is_the_record_view_and_its_imu_columns_are_imu(
    sets: dict[str, Path], run: int
) -> None:
    with h5py.File(sets["dh"], "r") as handle:
        sensen = handle["senSen"][run]
        imu = handle["imu"][run]
        time, q = handle["time"][run], handle["q"][run]
        columns = list(handle["senSen"].attrs["columns"])
        sources = {source.file_name for source in handle["senSen"].virtual_sources()}
    assert sensen.shape == (SAMPLES, 91) and sensen.dtype == np.float32 and sources == {"."}
    assert columns[0] == "time" and columns[7] == "imu_base_wx" and columns[-1] == "imu_link6_b_fz"
    with DatasetReader(sets["dh"]) as reader:
        record = reader.record(run)
    np.testing.assert_array_equal(sensen, record.view("senSen"))
    np.testing.assert_array_equal(sensen[:, 7:].reshape(SAMPLES, 14, 6), record.imu)
    np.testing.assert_array_equal(sensen[:, 7:].reshape(SAMPLES, 14, 6), imu)
    np.testing.assert_array_equal(sensen[:, 0], time)
    np.testing.assert_array_equal(sensen[:, 1:7], q)
    assert np.abs(imu).max() > 0.1  # real signals, not the fill value
    made = DhDatasetSpec(n_runs=RUNS, seed=2, duration=0.2).make_run(run)
    assert [m.parent for m in record.imu_mounts] == [m.parent for m in made.imu_mounts]
    np.testing.assert_array_equal(record.imu_mount, made.imu_mount)


def test_base_pose_is_stored_as_the_base_table_moves_it(sets: dict[str, Path]) -> None:
    """``base_pose`` (new in version 2) against sines and Rx·Ry·Rz computed here."""
    from scipy.spatial.transform import Rotation

    with DatasetReader(sets["dh"]) as reader:
        record = reader.record(1)
    amplitude, bias, frequency, phase = record.tables["senSenB"].T
    x = bias + amplitude * np.sin(np.outer(record.time, frequency) + phase)
    np.testing.assert_allclose(record.base_pose[:, :3, 3], x[:, :3], atol=1e-7)
    rotation = Rotation.from_euler("XYZ", x[:, 3:]).as_matrix()
    np.testing.assert_allclose(record.base_pose[:, :3, :3], rotation, atol=1e-7)
    np.testing.assert_array_equal(
        record.base_pose[:, 3], np.tile([0.0, 0.0, 0.0, 1.0], (SAMPLES, 1))
    )


def test_views_stay_valid_when_the_file_is_moved(sets: dict[str, Path], tmp_path: Path) -> None:
    moved = tmp_path / "elsewhere" / "renamed.h5"
    moved.parent.mkdir()
    shutil.copyfile(sets["ur5"], moved)
    with h5py.File(moved, "r") as handle:
        signals = handle["signals"][1]
        imu, q = handle["imu"][1], handle["q"][1]
    np.testing.assert_array_equal(signals[:, 7:], imu.reshape(SAMPLES, -1))
    np.testing.assert_array_equal(signals[:, 1:7], q)
    with DatasetReader(moved) as reader:
        record = reader.record(1)
    np.testing.assert_array_equal(record.signals(), signals)
    assert record.joint_names[0] == "shoulder_pan_joint" and record.imu_mounts[3].parent


def test_a_run_s_drawn_hardware_values_go_into_its_attributes() -> None:
    from aaria_pin.files.dataset.layout import record_attributes

    names = ["noise_parameters/gyro_noise_density_rad_s_sqrtHz", "encoder/noise/1",
             "noise_parameters/gyro_scale_error"]  # fmt: skip
    stored = {
        "noise_parameters": {"gyro_noise_density_rad_s_sqrtHz": 2.0, "gyro_scale_error": 0.5},
        "encoder": {"noise": [0.5, 0.5]},
        "hardware_names": names,
        "hardware": {"imu": {}},
    }
    run = record_attributes(stored, 3, 3, np.array([1.5, 0.25, np.nan]))
    assert run["noise_parameters"] == {"gyro_noise_density_rad_s_sqrtHz": 1.5}  # NaN: left out
    assert run["encoder"] == {"noise": [0.5, 0.25]}
    assert "hardware_names" not in run and "hardware" not in run  # the data set's, not the run's
    assert stored["encoder"] == {"noise": [0.5, 0.5]}  # the file's attributes untouched
    assert record_attributes(stored, 3, 3)["encoder"] == {"noise": [0.5, 0.5]}
