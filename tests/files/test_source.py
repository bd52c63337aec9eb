"""The one reader of "a run file, or run K of a data set"."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

from aaria_pin.errors import InputFileError, ParameterError
from aaria_pin.files.source import open_record

FIXTURES = Path(__file__).resolve().parents[1] / "fixtures" / "v0_3_0"


def test_a_run_file_and_a_data_set_run_read_as_stored() -> None:
    run = open_record(FIXTURES / "ur5_run.h5")
    with h5py.File(FIXTURES / "ur5_run.h5", "r") as handle:
        np.testing.assert_array_equal(run.q, handle["q"][()])
        np.testing.assert_array_equal(run.imu, handle["imu"][()])
    third = open_record(FIXTURES / "ur5_dataset.h5", run=1)
    with h5py.File(FIXTURES / "ur5_dataset.h5", "r") as handle:
        np.testing.assert_array_equal(third.q, handle["q"][1].astype(float))
        np.testing.assert_array_equal(third.tau, handle["tau"][1].astype(float))
    assert third.attributes["run"] == 1


def test_the_run_rule_and_the_file_errors_name_their_parameter(tmp_path: Path) -> None:
    with pytest.raises(ParameterError, match="run is None; allowed: a run index") as bad:
        open_record(FIXTURES / "ur5_dataset.h5")
    assert bad.value.parameter == "run"
    with pytest.raises(ParameterError, match=r"run is for a data set; .*ur5_run\.h5 is") as bad:
        open_record(FIXTURES / "ur5_run.h5", run=1)
    assert bad.value.parameter == "run"
    with pytest.raises(ParameterError, match="run 99; allowed: 0 to") as bad:
        open_record(FIXTURES / "ur5_dataset.h5", run=99)
    assert bad.value.parameter == "run" and bad.value.value == 99
    with pytest.raises(InputFileError, match="no such file") as missing:
        open_record(tmp_path / "missing.h5")
    assert missing.value.parameter == "file" and isinstance(missing.value, OSError)
    garbage = tmp_path / "garbage.h5"
    garbage.write_bytes(b"not HDF5")
    with pytest.raises(InputFileError, match="cannot be read as an HDF5 run file") as bad_file:
        open_record(garbage)
    assert bad_file.value.parameter == "file"
