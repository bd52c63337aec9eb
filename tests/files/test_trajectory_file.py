"""Trajectory files (CSV, NPY, HDF5, a run file) round-trip; bad files are refused in one line."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from aaria_pin.errors import InputFileError
from aaria_pin.files.trajectory_file import read_trajectory_file

TIME = np.arange(6) / 10.0
Q = np.column_stack([np.sin(TIME), 0.01 * TIME, np.cos(TIME)])
NAMES = ("shoulder", "slide", "elbow")


def _write_csv(path, header, rows):
    lines = ["# a comment before the header", ",".join(header)]
    lines += [",".join(repr(float(x)) for x in row) for row in rows]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_csv_round_trip_with_and_without_derivatives(tmp_path):
    plain = _write_csv(tmp_path / "q.csv", ["time", *NAMES], np.column_stack([TIME, Q]))
    time, q, qd, qdd, names = read_trajectory_file(plain)
    assert np.array_equal(time, TIME) and np.array_equal(q, Q)
    assert qd is None and qdd is None and names == NAMES
    # derivative columns in another order than the joints
    header = ["time", "qd_elbow", *NAMES, "qd_shoulder", "qd_slide"]
    QD = 2 * Q
    rows = np.column_stack([TIME, QD[:, 2], Q, QD[:, 0], QD[:, 1]])
    time, q, qd, qdd, names = read_trajectory_file(_write_csv(tmp_path / "qd.csv", header, rows))
    assert np.array_equal(q, Q) and np.array_equal(qd, QD) and qdd is None


def test_npy_round_trip(tmp_path):
    path = tmp_path / "q.npy"
    np.save(path, np.column_stack([TIME, Q]))
    time, q, qd, qdd, names = read_trajectory_file(path)
    assert np.array_equal(time, TIME) and np.array_equal(q, Q)
    assert qd is None and qdd is None and names is None


def test_hdf5_round_trip(tmp_path):
    path = tmp_path / "q.h5"
    with h5py.File(path, "w") as handle:
        handle["time"], handle["q"], handle["qd"], handle["qdd"] = TIME, Q, 2 * Q, 3 * Q
        handle["joint_names"] = np.array(NAMES, dtype=h5py.string_dtype())
    time, q, qd, qdd, names = read_trajectory_file(path)
    assert np.array_equal(time, TIME) and np.array_equal(q, Q)
    assert np.array_equal(qd, 2 * Q) and np.array_equal(qdd, 3 * Q) and names == NAMES


def test_a_run_file_is_a_trajectory_file(tmp_path):
    from aaria_pin.aaria.presets import get_preset
    from aaria_pin.aaria.simulate import simulate_run
    from aaria_pin.files.runfile import write_run

    preset = get_preset("aaria-fig3")
    record = simulate_run(preset.table, duration=0.2, rate=50, noise=False)
    time, q, qd, qdd, names = read_trajectory_file(write_run(tmp_path / "run.h5", record))
    assert np.array_equal(time, record.time) and np.array_equal(q, record.q)
    assert np.array_equal(qd, record.qd) and np.array_equal(qdd, record.qdd)
    assert names == record.joint_names


def _h5(path, **arrays):
    with h5py.File(path, "w") as handle:
        for name, value in arrays.items():
            handle[name] = value
    return path


BAD_CSV = {
    "no_header.csv": "# only a comment\n",
    "bad_header.csv": "t,a\n0,1\n0.1,2\n",
    "no_joint.csv": "time,qd_a\n0,1\n0.1,2\n",
    "ragged.csv": "time,a\n0,1\n0.1\n",
    "text.csv": "time,a\n0,1\n0.1,x\n",
    "nan.csv": "time,a\n0,1\n0.1,nan\n",
    "backwards.csv": "time,a\n0,1\n0.1,2\n0.1,3\n",
    "partial_qd.csv": "time,a,b,qd_a\n0,1,2,3\n0.1,1,2,3\n",
    "one_row.csv": "time,a\n0,1\n",
    "repeated.csv": "time,a,a\n0,1,2\n0.1,1,2\n",
}


@pytest.mark.parametrize("name", sorted(BAD_CSV))
def test_bad_csv_files_are_refused_in_one_line(tmp_path, name):
    path = tmp_path / name
    path.write_text(BAD_CSV[name])
    with pytest.raises(InputFileError) as error:
        read_trajectory_file(path)
    message = str(error.value)
    assert "\n" not in message and str(path) in message and "allowed" in message


def test_bad_npy_hdf5_and_paths_are_refused_in_one_line(tmp_path):
    one_d = tmp_path / "one_d.npy"
    np.save(one_d, TIME)
    text = tmp_path / "text.npy"
    np.save(text, np.array([["a", "b"], ["c", "d"]]))
    garbage = tmp_path / "garbage.h5"
    garbage.write_bytes(b"not an HDF5 file")
    cases = [
        one_d,
        text,
        garbage,
        _h5(tmp_path / "no_q.h5", time=TIME),
        _h5(tmp_path / "short_q.h5", time=TIME, q=Q[:4]),
        _h5(tmp_path / "qd_shape.h5", time=TIME, q=Q, qd=Q[:, :2]),
        _h5(tmp_path / "inf.h5", time=TIME, q=np.where(Q > 0.9, np.inf, Q)),
        tmp_path / "missing.csv",
        tmp_path / "table.xlsx",
    ]
    for path in cases:
        with pytest.raises(InputFileError) as error:
            read_trajectory_file(path)
        message = str(error.value)
        assert "\n" not in message and str(path) in message, message


@pytest.mark.parametrize(
    ("arrays", "message"),
    [
        (
            {"time": TIME, "q": Q > 0.5},
            "q holds bool values (dtype bool); allowed: a numeric table",
        ),
        ({"time": TIME.astype("S8"), "q": Q}, "time holds bytes values (dtype |S8)"),
        ({"time": TIME, "q": Q + 1j}, "q holds complex numbers; allowed: a real table"),
    ],
)
def test_hdf5_series_of_other_values_than_numbers_are_refused(tmp_path, arrays, message):
    path = _h5(tmp_path / "t.h5", **arrays)
    with pytest.raises(InputFileError) as error:
        read_trajectory_file(path)
    assert str(error.value).startswith(f"{path}: {message}")
    assert error.value.parameter == "file"
