"""Labels of a data set's runs: checked against the stored DH table decoded here with h5py."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from aaria_pin.errors import ParameterError
from aaria_pin.files.dataset.labels import LABELS, available_labels, label_sources
from aaria_pin.files.dataset.reader import DatasetReader


@pytest.fixture(scope="module")
def dataset(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Three random DH arms of 0.2 s at 100 Hz, made by ``aaria dataset``."""
    path = tmp_path_factory.mktemp("labels") / "ds.h5"
    command = [sys.executable, "-m", "aaria_pin.cli", "dataset", "-n", "3", "--seed", "5"]
    command += ["--duration", "0.2", "--rate", "100", "--workers", "1", "-o", str(path)]
    subprocess.run(command, check=True, capture_output=True)
    return path


def test_labels_of_a_run_decode_the_stored_dh_table(dataset: Path) -> None:
    with h5py.File(dataset, "r") as handle:
        tables = handle["senSenDH"][()]
        tau = handle["tau"][()]
    with DatasetReader(dataset) as reader:
        assert reader.label_names == ("link_types", "empty_mask")
        for k in range(3):
            labels = reader.labels(k)
            expected = [round(float(code)) for code in tables[k, :6, 4]]  # fifth column, rows 1-6
            assert labels["link_types"].dtype == np.int64 and labels["link_types"].shape == (6,)
            assert labels["link_types"].tolist() == expected
            assert set(expected) <= {0, 1, 2}
            assert labels["empty_mask"].dtype == np.bool_
            assert labels["empty_mask"].tolist() == [code == 0 for code in expected]
            assert not np.any(tau[k][:, labels["empty_mask"]])  # an empty module has no torque
            assert reader.labels(k, ("empty_mask",)).keys() == {"empty_mask"}
        with pytest.raises(ParameterError) as caught:
            reader.labels(0, ("inertial_parameters",))
        assert caught.value.parameter == "names"


def test_labels_come_whole_with_every_window(dataset: Path) -> None:
    names = ("imu", "tau", "link_types", "empty_mask", "senSenDH", "imu_mount")
    with DatasetReader(dataset) as reader:
        windows = reader.windows(5, 5, names=names)
        with pytest.raises(ParameterError) as caught:
            reader.statistics(("link_types",))  # a label has no statistics
        assert caught.value.parameter == "names"
    iterated = list(windows)
    with h5py.File(dataset, "r") as handle:
        for i in range(len(windows)):
            k, s = windows.locate(i)
            window = windows[i]
            assert window["link_types"].tolist() == np.rint(handle["senSenDH"][k, :6, 4]).tolist()
            np.testing.assert_array_equal(window["empty_mask"], handle["senSenDH"][k, :6, 4] == 0)
            np.testing.assert_array_equal(window["tau"], handle["tau"][k, s : s + 5])
            np.testing.assert_array_equal(window["imu_mount"], handle["imu_mount"][k])
            np.testing.assert_array_equal(iterated[i][2]["link_types"], window["link_types"])
            np.testing.assert_array_equal(iterated[i][2]["empty_mask"], window["empty_mask"])


def test_a_label_exists_only_with_its_source() -> None:
    assert available_labels(("q", "tau", "joint_table")) == ()
    assert set(available_labels(("senSenDH",))) == set(LABELS)
    assert label_sources(("imu", "link_types", "empty_mask", "senSenDH")) == ("imu", "senSenDH")


@pytest.mark.parametrize("version", ["v0_1_0", "v0_3_0"])
def test_labels_of_older_files_and_of_a_urdf_data_set(version: str) -> None:
    fixtures = Path(__file__).resolve().parent.parent / "fixtures" / version
    with h5py.File(fixtures / "dh_dataset.h5", "r") as handle:
        codes = handle["senSenDH"][0, :6, 4]
    with DatasetReader(fixtures / "dh_dataset.h5") as reader:
        assert reader.labels(0)["link_types"].tolist() == [round(float(c)) for c in codes]
    with DatasetReader(fixtures / "ur5_dataset.h5") as reader:  # a fixed structure: no labels
        assert reader.label_names == ()
        with pytest.raises(ParameterError) as caught:
            reader.windows(5, names=("q", "link_types"))
        assert caught.value.parameter == "names"
