"""``check_file``: every complete run of a data set verified, a run file read whole.

Damage is made in copies of real files (``aaria dataset -n 3``, ``aaria simulate``): a flipped
chunk, numbers changed under their checksum, a NaN, an array deleted; each damaged run is
found, the others are not reported.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest
from dataset_damage import flip_chunk, small_dataset

from aaria_pin.apps.check import check_file
from aaria_pin.errors import InputFileError

FIXTURES = Path(__file__).parents[1] / "fixtures"


@pytest.fixture(scope="module")
def made(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return small_dataset(tmp_path_factory.mktemp("check") / "ds.h5")


def test_an_intact_data_set_is_ok(made: Path) -> None:
    result = check_file(made)
    assert result.ok and result.kind == "dataset" and (result.runs, result.checked) == (3, 3)
    assert result.to_json()["damaged"] == [] and result.notes == ()


def test_every_damaged_run_is_listed(made: Path, tmp_path: Path) -> None:
    path = tmp_path / "ds.h5"
    shutil.copy(made, path)
    flip_chunk(path, "imu", 0)
    with h5py.File(path, "r+") as handle:
        handle["qd"][2, 7, 3] = np.nan
    result = check_file(path)
    assert sorted(result.damaged) == [0, 2]  # run 1 intact
    assert "run 0 of" in result.damaged[0] and "is damaged (imu" in result.damaged[0]
    assert "qd has NaN at sample 7, joint 3" in result.damaged[2]
    assert result.to_json()["damaged"][0]["run"] == 0 and not result.to_json()["ok"]


def test_a_data_set_without_an_array_is_damaged_as_a_whole(made: Path, tmp_path: Path) -> None:
    path = tmp_path / "ds.h5"
    shutil.copy(made, path)
    with h5py.File(path, "r+") as handle:
        del handle["q"]
    result = check_file(path)
    assert list(result.damaged) == [None] and "no 'q' array" in result.damaged[None]


def test_run_files_and_old_data_sets() -> None:
    assert check_file(FIXTURES / "v0_3_0" / "dh_run.h5").ok
    old = check_file(FIXTURES / "v0_1_0" / "dh_dataset.h5")
    assert old.ok and old.checked == 3 and "no checksums" in old.notes[0]


def test_what_is_not_a_file_to_check_raises(tmp_path: Path) -> None:
    with pytest.raises(InputFileError, match="no such file"):
        check_file(tmp_path / "missing.h5")
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as handle:
        handle["x"] = 1
    with pytest.raises(InputFileError) as bad:
        check_file(other)
    assert bad.value.parameter == "file"


def test_a_data_set_attribute_a_command_refuses_is_found_by_check(tmp_path: Path) -> None:
    """``check`` and ``torques`` agree: a bogus kind or a rate of 0 is damage to both."""
    from aaria_pin.files.dataset.reader import DatasetReader

    made = small_dataset(tmp_path / "ds.h5")
    for name, value in (("kind", "bogus"), ("rate", 0.0)):
        path = tmp_path / f"{name}.h5"
        shutil.copy(made, path)
        with h5py.File(path, "r+") as handle:
            handle.attrs[name] = value
        result = check_file(path)
        assert not result.ok and None in result.damaged, name
        with DatasetReader(path) as reader, pytest.raises(InputFileError) as refused:
            reader.record(0)
        assert name in str(refused.value) and name in result.damaged[None]


def test_every_fixture_of_earlier_versions_checks_intact() -> None:
    """No false alarm: the 0.1, 0.2 and 0.3 files (run files and data sets) are intact."""
    fixtures = Path(__file__).parents[1] / "fixtures"
    files = sorted(p for p in fixtures.glob("v0_*/*") if p.suffix in (".h5", ".mat"))
    assert len(files) > 10
    for path in files:
        assert check_file(path).ok, path
