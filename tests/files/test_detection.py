"""The one format detection of the files layer: run file (HDF5, MAT v5, MAT v7.3) or data set."""

from __future__ import annotations

from pathlib import Path

import pytest

from aaria_pin.errors import InputFileError
from aaria_pin.files.detection import file_format, is_dataset_file
from aaria_pin.files.runfile import read_run, write_run

FIXTURES = Path(__file__).resolve().parents[1] / "fixtures" / "v0_3_0"


def test_every_format_is_told_from_its_marks(tmp_path: Path) -> None:
    assert file_format(FIXTURES / "dh_run.h5") == "hdf5"
    assert file_format(FIXTURES / "dh_run.mat") == "mat5"
    assert file_format(FIXTURES / "ur5_dataset.h5") == "dataset"
    record = read_run(FIXTURES / "ur5_run.h5")
    long = tmp_path / "run.mat"
    write_run(long, record, mat_version="7.3")
    assert long.read_bytes().startswith(b"MATLAB 7.3 MAT-file")
    assert file_format(long) == "mat73"
    renamed = tmp_path / "RUN.HDF5"
    renamed.write_bytes((FIXTURES / "ur5_dataset.h5").read_bytes())
    assert file_format(renamed) == "dataset" and is_dataset_file(renamed)
    assert not is_dataset_file(FIXTURES / "dh_run.h5")
    assert not is_dataset_file(tmp_path / "missing.h5")


def test_a_file_of_another_kind_is_refused_naming_file(tmp_path: Path) -> None:
    with pytest.raises(InputFileError, match=r"unknown run file type '\.csv'") as bad:
        file_format(FIXTURES / "traj.csv")
    assert bad.value.parameter == "file"
    garbage = tmp_path / "garbage.h5"
    garbage.write_bytes(b"not HDF5")
    with pytest.raises(InputFileError, match="cannot be read as an HDF5 run file") as bad:
        file_format(garbage)
    assert bad.value.parameter == "file"


def test_a_truncated_hdf5_file_is_damaged_and_a_text_file_is_not_hdf5(tmp_path: Path) -> None:
    from aaria_pin.files._stored import DamagedFileError
    from aaria_pin.files.detection import has_hdf5_signature

    whole = (FIXTURES / "ur5_dataset.h5").read_bytes()
    truncated = tmp_path / "cut.h5"
    truncated.write_bytes(whole[: len(whole) // 3])
    with pytest.raises(DamagedFileError, match=r"cut\.h5 is damaged \(.*truncated file") as error:
        file_format(truncated)
    assert error.value.parameter == "file" and "\n" not in str(error.value)
    text = tmp_path / "text.h5"
    text.write_text("a text file\n")
    with pytest.raises(InputFileError, match="cannot be read as an HDF5") as error:
        file_format(text)
    assert not isinstance(error.value, DamagedFileError)
    user_block = tmp_path / "block.mat"  # a MAT-file v7.3: its superblock after 512 bytes
    user_block.write_bytes(b"MATLAB 7.3 MAT-file".ljust(512, b" ") + whole[:64])
    assert has_hdf5_signature(user_block) and has_hdf5_signature(truncated)
    assert not has_hdf5_signature(text)
