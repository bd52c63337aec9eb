"""Tables as people have them: header rows, run files, and the bad ones named by row and column."""

from __future__ import annotations

import os
from pathlib import Path

import h5py
import numpy as np
import pytest
from scipy.io import loadmat

from aaria_pin.aaria.dh import AARIA_COLUMNS
from aaria_pin.aaria.presets import get_preset
from aaria_pin.errors import InputFileError
from aaria_pin.files.io import read_table

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures" / "v0_1_0"
TABLE = get_preset("aaria-fig2").table
JOINTS = np.arange(40, dtype=float).reshape(8, 5) / 10.0


def _csv(path: Path, header: str, table: np.ndarray, comment: str = "") -> Path:
    rows = "\n".join(",".join(repr(float(v)) for v in row) for row in table)
    path.write_text(f"{comment}{header}\n{rows}\n", encoding="utf-8")
    return path


def test_the_stored_dh_columns_are_the_aaria_columns() -> None:
    from aaria_pin.files.io import STORED_DH_COLUMNS

    assert STORED_DH_COLUMNS == AARIA_COLUMNS


def test_a_header_row_of_any_names_is_skipped(tmp_path: Path) -> None:
    path = _csv(
        tmp_path / "dh.csv",
        "alpha [rad],a [m],theta [rad],d [m],link type",
        TABLE,
        comment="# my arm\n\n",
    )
    np.testing.assert_array_equal(read_table(path), TABLE)
    path = _csv(tmp_path / "other.csv", "c1, c2, c3, c4, c5", TABLE)
    np.testing.assert_array_equal(read_table(path), TABLE)


def test_an_excel_csv_with_a_byte_order_mark(tmp_path: Path) -> None:
    path = _csv(tmp_path / "dh.csv", "\ufeffalpha,a,theta,d,link type", TABLE)
    np.testing.assert_array_equal(read_table(path, columns=AARIA_COLUMNS), TABLE)


def test_known_names_in_another_order_are_put_in_order(tmp_path: Path) -> None:
    order = [4, 0, 3, 1, 2]  # link type, alpha, d, a, theta
    header = ",".join(["Link_Type", "ALPHA (rad)", "d", "a [m]", "theta"])
    path = _csv(tmp_path / "dh.csv", header, TABLE[:, order])
    np.testing.assert_array_equal(read_table(path), TABLE)  # senSenDH's names are known
    # and so are the joint table's
    names = ["phase", "bias", "amplitude", "frequency", "prismatic amplitude"]
    path = _csv(tmp_path / "j.csv", ",".join(names), JOINTS[:, [4, 2, 0, 3, 1]])
    np.testing.assert_array_equal(read_table(path, "senSenJ"), JOINTS)


def test_a_known_name_in_the_wrong_column_is_refused(tmp_path: Path) -> None:
    path = _csv(tmp_path / "dh.csv", "a,alpha,theta,d,type", TABLE)  # swapped, one unknown
    with pytest.raises(InputFileError, match="header, column 1 is 'a', which is column 2"):
        read_table(path, columns=AARIA_COLUMNS)


def test_a_header_and_nothing_else_is_empty(tmp_path: Path) -> None:
    (tmp_path / "h.csv").write_text("alpha,a,theta,d,link type\n# no rows\n")
    with pytest.raises(InputFileError, match=r"is empty.*header row"):
        read_table(tmp_path / "h.csv")


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("1,2,3\n4,x,6\n", "row 2, column 2 is 'x'; allowed: a number"),
        ("1,2,3\n4,5\n", "row 2 has 2 columns; allowed: 3"),
        ("a,b,c\n1,2,3\nd,e,f\n", "row 2, column 1 is 'd'"),  # a header only as the first row
    ],
)
def test_bad_cells_are_named(tmp_path: Path, text: str, message: str) -> None:
    (tmp_path / "t.csv").write_text(text)
    with pytest.raises(InputFileError, match=message):
        read_table(tmp_path / "t.csv")


def test_dh_and_joint_tables_from_a_run_file() -> None:
    """The 0.1.0 run's tables, against the file's arrays read with h5py, and its .mat run."""
    with h5py.File(FIXTURES / "dh_run.h5", "r") as handle:
        stored = {name: handle[name][()] for name in ("senSenDH", "senSenJ", "senSenB")}
    for name, table in stored.items():
        np.testing.assert_array_equal(read_table(FIXTURES / "dh_run.h5", name), table)
    mat = loadmat(FIXTURES / "dh_run.mat")
    np.testing.assert_array_equal(read_table(FIXTURES / "dh_run.mat", "senSenJ"), mat["senSenJ"])


def test_a_urdf_run_file_gives_its_base_table() -> None:
    with h5py.File(FIXTURES / "ur5_run.h5", "r") as handle:
        base = handle["base_table"][()]
        joints = handle["joint_table"][()]
    np.testing.assert_array_equal(read_table(FIXTURES / "ur5_run.h5", "senSenB"), base)
    np.testing.assert_array_equal(read_table(FIXTURES / "ur5_run.h5", "joint_table"), joints)
    with pytest.raises(InputFileError, match=r"without the table 'senSenDH'.*base_table"):
        read_table(FIXTURES / "ur5_run.h5", "senSenDH")


def test_a_new_run_file_gives_its_tables(tmp_path: Path) -> None:
    from aaria_pin.aaria.simulate import simulate_run
    from aaria_pin.files.runfile import write_run

    record = simulate_run(TABLE, duration=0.05, rate=100.0, noise=False)
    write_run(tmp_path / "run.h5", record)
    with h5py.File(tmp_path / "run.h5", "r") as handle:
        names = []
        handle.visit(names.append)
        stored = next(n for n in names if n.endswith("senSenDH"))
        expected = handle[stored][()]
    np.testing.assert_array_equal(expected, TABLE)
    np.testing.assert_array_equal(read_table(tmp_path / "run.h5"), TABLE)


@pytest.mark.parametrize("empty", [np.array([]), np.empty((0, 5)), np.empty((8, 0))])
def test_an_empty_npy_is_one_line(tmp_path: Path, empty: np.ndarray) -> None:
    np.save(tmp_path / "e.npy", empty)
    with pytest.raises(InputFileError, match=r"is an empty table \(shape"):
        read_table(tmp_path / "e.npy")


def test_nan_and_inf_are_named_by_row_and_column(tmp_path: Path) -> None:
    table = TABLE.copy()
    table[2, 3] = np.nan
    np.save(tmp_path / "nan.npy", table)
    with pytest.raises(InputFileError, match=r"row 3, column 4 \(d\) is nan; allowed: a finite"):
        read_table(tmp_path / "nan.npy")
    joints = JOINTS.copy()
    joints[1, 2] = np.inf
    np.savetxt(tmp_path / "j.csv", joints, delimiter=",")
    with pytest.raises(InputFileError, match=r"row 2, column 3 \(bias\) is inf") as caught:
        read_table(tmp_path / "j.csv", "senSenJ")
    assert caught.value.element == "row 2, column 3 (bias)"


def test_a_fifo_or_folder_is_refused_without_waiting(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "pipe.csv")
    with pytest.raises(InputFileError, match=r"is a FIFO \(named pipe\); allowed: a regular"):
        read_table(tmp_path / "pipe.csv")
    (tmp_path / "folder.csv").mkdir()
    with pytest.raises(InputFileError, match="is a folder"):
        read_table(tmp_path / "folder.csv")


def test_read_csv_table_gives_the_numbers_as_float_parses_them_and_the_header(
    tmp_path: Path,
) -> None:
    from aaria_pin.files.io import read_csv_table

    rows = [["0.1", "1e-3", "-2.5"], ["0.30000000000000004", "7", "0.1234567890123456789"]]
    path = tmp_path / "t.csv"
    path.write_text("# made by hand\ntime, a ,b\n" + "\n".join(",".join(r) for r in rows) + "\n")
    table, header = read_csv_table(path)
    assert header == ["time", "a", "b"]
    assert table.tolist() == [[float(x) for x in row] for row in rows]
    bare = tmp_path / "bare.csv"
    bare.write_text("1,2\n3,4  # a note\n")
    table, header = read_csv_table(bare)
    assert header is None and table.tolist() == [[1.0, 2.0], [3.0, 4.0]]


def test_a_table_of_a_mat_v73_run_file_reads_as_the_stored_table(tmp_path: Path) -> None:
    from aaria_pin.files.detection import file_format
    from aaria_pin.files.runfile import read_run, write_run

    record = read_run(Path(__file__).parents[1] / "fixtures" / "v0_3_0" / "dh_run.h5")
    path = write_run(tmp_path / "run.mat", record, mat_version="7.3")
    assert file_format(path) == "mat73"
    for name in ("senSenDH", "senSenJ", "senSenB"):
        np.testing.assert_array_equal(read_table(path, name), record.tables[name])
