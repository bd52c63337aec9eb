from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.io import savemat

from aaria_pin.aaria.presets import get_preset
from aaria_pin.errors import InputFileError, OutputFileError
from aaria_pin.files.io import atomic_output, read_table, write_text_atomic

TABLE = get_preset("aaria-fig2").table


def test_read_csv_npy_and_mat(tmp_path: Path) -> None:
    np.savetxt(tmp_path / "t.csv", TABLE, delimiter=",", header="alpha,a,theta,d,type")
    np.save(tmp_path / "t.npy", TABLE)
    savemat(tmp_path / "t.mat", {"senSenDH": TABLE})
    for name in ("t.csv", "t.npy", "t.mat"):
        np.testing.assert_array_equal(read_table(tmp_path / name), TABLE)


@pytest.mark.parametrize(
    ("name", "content", "pattern"),
    [
        ("missing.csv", None, "no such file"),
        ("t.xlsx", b"x", "unknown table file type '.xlsx'"),
        ("t.csv", b"1,2,abc\n", "row 1, column 3 is 'abc'; allowed: a number"),
        ("t.npy", b"not numpy", "cannot be read"),
        ("t.mat", b"garbage", "cannot be read"),
    ],
)
def test_unreadable_tables(tmp_path: Path, name: str, content: bytes | None, pattern: str) -> None:
    path = tmp_path / name
    if content is not None:
        path.write_bytes(content)
    with pytest.raises(InputFileError, match=pattern):
        read_table(path)


def test_mat_without_the_named_array(tmp_path: Path) -> None:
    savemat(tmp_path / "t.mat", {"other": TABLE})
    with pytest.raises(InputFileError, match=r"no array 'senSenDH'.*other"):
        read_table(tmp_path / "t.mat")


def test_atomic_output_leaves_nothing_on_failure(tmp_path: Path) -> None:
    target = tmp_path / "out.txt"
    with pytest.raises(RuntimeError), atomic_output(target) as temporary:
        temporary.write_text("half")
        raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []


def test_atomic_output_replaces_only_when_complete(tmp_path: Path) -> None:
    target = tmp_path / "out.txt"
    target.write_text("old")
    write_text_atomic(target, "new")
    assert target.read_text() == "new"
    assert [p.name for p in tmp_path.iterdir()] == ["out.txt"]


def test_atomic_output_into_a_missing_folder(tmp_path: Path) -> None:
    with pytest.raises(OutputFileError, match="does not exist"):
        write_text_atomic(tmp_path / "nope" / "out.txt", "x")


def test_empty_and_complex_tables_are_refused(tmp_path: Path) -> None:
    (tmp_path / "empty.csv").write_text("# nothing here\n")
    with pytest.raises(InputFileError, match="is empty"):
        read_table(tmp_path / "empty.csv")
    np.save(tmp_path / "complex.npy", TABLE + 1j)
    with pytest.raises(InputFileError, match="complex"):
        read_table(tmp_path / "complex.npy")


def _mat73(path: Path, values: np.ndarray, matlab_class: str) -> Path:
    """A v7.3 MAT-file (HDF5 after a 512-byte header) holding ``senSenDH`` of a MATLAB class."""
    import h5py

    with h5py.File(path, "w", userblock_size=512) as handle:
        handle["senSenDH"] = values.T  # MATLAB stores column-major
        handle["senSenDH"].attrs["MATLAB_class"] = np.bytes_(matlab_class)
    with path.open("r+b") as stream:
        stream.write(b"MATLAB 7.3 MAT-file, made by a test")
    return path


@pytest.mark.parametrize(
    ("name", "values", "what"),
    [
        ("bool.npy", TABLE > 0, "bool values (dtype bool)"),
        ("text.npy", TABLE.astype(str), "text values (dtype <U"),
        ("bytes.npy", TABLE.astype(bytes), "bytes values (dtype |S"),
        ("date.npy", np.zeros((8, 5), "datetime64[s]"), "date values"),
        ("record.npy", np.zeros((8, 5), [("x", float)]), "structured values"),
        ("text.mat", np.array(["abcde"] * 8), "text values (dtype <U5)"),
    ],
)
def test_tables_of_other_values_than_numbers_are_refused(
    tmp_path: Path, name: str, values: np.ndarray, what: str
) -> None:
    path = tmp_path / name
    if name.endswith(".npy"):
        np.save(path, values)
    else:
        savemat(path, {"senSenDH": values})
    with pytest.raises(InputFileError) as error:
        read_table(path)
    assert str(error.value).startswith(f"{path}: holds {what}")
    assert str(error.value).endswith("; allowed: a numeric table")
    assert error.value.parameter == "file"


def test_mat73_logical_and_char_arrays_are_refused(tmp_path: Path) -> None:
    logical = _mat73(tmp_path / "l.mat", (TABLE > 0).astype(np.uint8), "logical")
    with pytest.raises(InputFileError, match=r"holds bool values \(MATLAB logical\); allowed"):
        read_table(logical)
    char = _mat73(tmp_path / "c.mat", np.full((8, 5), 49, np.uint16), "char")
    with pytest.raises(InputFileError, match=r"holds text values \(MATLAB char\)"):
        read_table(char)
    double = _mat73(tmp_path / "d.mat", TABLE, "double")
    np.testing.assert_array_equal(read_table(double), TABLE)


def test_integer_tables_are_numbers(tmp_path: Path) -> None:
    np.save(tmp_path / "ints.npy", np.arange(40, dtype=np.int16).reshape(8, 5))
    table = read_table(tmp_path / "ints.npy")
    assert table.dtype == np.float64
    np.testing.assert_array_equal(table, np.arange(40.0).reshape(8, 5))
