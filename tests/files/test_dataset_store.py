"""The data set file's own checks and its attribute encoding (the run file's encoding)."""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import numpy as np
import pytest

from aaria_pin.errors import OutputFileError
from aaria_pin.files.dataset.layout import DatasetLayout
from aaria_pin.files.dataset.store import DatasetFile, check_dataset_path

LAYOUT = DatasetLayout(("j1",), ("imu_a",), ("link1",), {"joint_table": (1, 5)})


def test_an_existing_output_names_the_resume_parameter(tmp_path: Path) -> None:
    path = tmp_path / "set.h5"
    path.write_bytes(b"x")
    with pytest.raises(OutputFileError) as caught:
        check_dataset_path(path, resume=False, overwrite=False)
    error = caught.value
    assert (error.parameter, error.value) == ("resume", False)
    assert str(error).startswith("resume is False; allowed: True to continue")
    assert "--" not in str(error) and "\n" not in str(error)
    assert error.for_flag({"resume": "--resume"}).startswith("--resume is False; allowed:")


def test_resume_with_overwrite_names_the_overwrite_parameter(tmp_path: Path) -> None:
    with pytest.raises(OutputFileError) as caught:
        check_dataset_path(tmp_path / "set.h5", resume=True, overwrite=True)
    assert (caught.value.parameter, caught.value.value) == ("overwrite", True)
    assert str(caught.value).startswith("overwrite is True; allowed: False when resuming")


def test_attributes_are_stored_as_a_run_file_stores_them(tmp_path: Path) -> None:
    path = tmp_path / "set.h5"
    given = {
        "rate": 200.0,
        "seed": np.int64(7),  # a numpy integer: a plain attribute
        "gravity": [0.0, 0.0, -9.81],  # two or more numbers: a numeric attribute
        "vary": ["joints"],  # a one-item list: JSON
        "noise_parameters": {"gyro": 1e-3},  # a dict: JSON
    }
    with DatasetFile.create(path, 2, 5, "float32", given, LAYOUT) as store:
        read = store.attributes
    with h5py.File(path, "r") as handle:
        raw = dict(handle.attrs)
    assert raw["seed"] == 7 and isinstance(raw["seed"], np.integer)
    np.testing.assert_array_equal(raw["gravity"], [0.0, 0.0, -9.81])
    assert json.loads(raw["vary_json"]) == ["joints"]
    assert json.loads(raw["noise_parameters_json"]) == {"gyro": 1e-3}
    assert read["seed"] == 7 and read["gravity"] == [0.0, 0.0, -9.81]
    assert read["vary"] == ["joints"] and read["noise_parameters"] == {"gyro": 1e-3}
    assert (read["N"], read["samples"], read["dtype"]) == (2, 5, "float32")


def test_an_attribute_the_file_sets_itself_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "set.h5"
    with pytest.raises(OutputFileError, match="attribute name 'N' is reserved"):
        DatasetFile.create(path, 2, 5, "float32", {"N": 3}, LAYOUT)
    assert not path.exists()


def test_tables_and_series_carry_units(tmp_path: Path) -> None:
    path = tmp_path / "set.h5"
    DatasetFile.create(path, 1, 4, "float64", {}, LAYOUT).close()
    with h5py.File(path, "r") as handle:
        assert handle["time"].attrs["units"] == "s"
        assert handle["joint_table"].attrs["units"].startswith("columns: amplitude rad")
        assert handle["signals"].is_virtual
        assert list(handle["signals"].attrs["columns"]) == [
            "time",
            "q:j1",
            *(f"imu_a_{s}" for s in ("wx", "wy", "wz", "fx", "fy", "fz")),
        ]
