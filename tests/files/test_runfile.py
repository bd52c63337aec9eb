from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest
import scipy.io
from scipy.io import loadmat, savemat

from aaria_pin.aaria.sensen import SENSEN_COLUMNS, RunRecord
from aaria_pin.errors import InputFileError, OutputFileError
from aaria_pin.files.runfile import read_run, run_file_summary, write_run

ATTRIBUTES: dict[str, Any] = {
    "rate": 100.0,
    "duration": 0.36,
    "seed": 7,
    "noise": True,
    "noise_parameters": {"gyro_noise_density": 1e-4, "slots": ["imu_base", "imu_tool"]},
    "gravity": [0, 0, -9.81],
    "version": "0.1.0",
    "units": "SI; angles in rad",
    "tables": ["senSenDH", "senSenJ"],
    "one_item": [3],
    "missing": None,
    "config_json": "plain text stored as JSON",
}
TIME_SERIES = ("senSen", "q", "qd", "qdd", "tau", "base_wrench", "tool_pose")


def make_record(
    samples: int = 37, seed: int = 1, attributes: dict[str, Any] | None = None
) -> RunRecord:
    rng = np.random.default_rng(seed)
    sensen = rng.normal(size=(samples, 91))
    sensen[:, 0] = np.arange(samples) / 100.0
    return RunRecord(
        senSen=sensen,
        senSenDH=rng.normal(size=(8, 5)),
        senSenJ=rng.normal(size=(8, 5)),
        senSenB=rng.normal(size=(2, 4)),
        q=rng.normal(size=(samples, 6)),
        qd=rng.normal(size=(samples, 6)),
        qdd=rng.normal(size=(samples, 6)),
        tau=rng.normal(size=(samples, 6)),
        base_wrench=rng.normal(size=(samples, 6)),
        tool_pose=rng.normal(size=(samples, 4, 4)),
        imu_mount=rng.normal(size=(14, 4, 4)),
        attributes=dict(ATTRIBUTES if attributes is None else attributes),
    )


def assert_records_equal(read: RunRecord, expected: RunRecord) -> None:
    for name, array in expected.arrays().items():
        got = getattr(read, name)
        assert got.dtype == np.float64, name
        assert got.shape == array.shape, name
        np.testing.assert_array_equal(got, array, err_msg=name)
    assert read.attributes == expected.attributes


@pytest.mark.parametrize("suffix", [".h5", ".hdf5", ".mat", ".H5"])
def test_round_trip(tmp_path: Path, suffix: str) -> None:
    record = make_record()
    path = tmp_path / f"run{suffix}"
    assert write_run(path, record) == path
    read = read_run(path)
    assert_records_equal(read, record)
    assert list(read.attributes) == list(record.attributes)
    assert type(read.attributes["seed"]) is int
    assert type(read.attributes["noise"]) is bool
    assert type(read.attributes["rate"]) is float
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]


@pytest.mark.parametrize("suffix", [".h5", ".mat"])
def test_one_sample_run_keeps_shapes(tmp_path: Path, suffix: str) -> None:
    record = make_record(samples=1)
    path = tmp_path / f"run{suffix}"
    write_run(path, record)
    read = read_run(path)
    assert read.q.shape == (1, 6)
    assert read.senSen.shape == (1, 91)
    assert read.tool_pose.shape == (1, 4, 4)
    assert_records_equal(read, record)


def test_default_hdf5_is_uncompressed_and_contiguous(tmp_path: Path) -> None:
    record = make_record(samples=300)
    path = write_run(tmp_path / "run.h5", record)
    with h5py.File(path, "r") as handle:
        for name, array in record.arrays().items():
            assert handle[name].compression is None and handle[name].chunks is None
            np.testing.assert_array_equal(handle[name][()], array)


def test_lzf_compression_round_trips(tmp_path: Path) -> None:
    record = make_record(samples=300)
    path = write_run(tmp_path / "run.h5", record, compression="lzf")
    with h5py.File(path, "r") as handle:
        assert handle["senSen"].compression == "lzf"
    assert_records_equal(read_run(path), record)


def test_unknown_compression_is_refused(tmp_path: Path) -> None:
    with pytest.raises(OutputFileError, match="compression 'zstd' is not allowed"):
        write_run(tmp_path / "run.h5", make_record(samples=3), compression="zstd")
    assert list(tmp_path.iterdir()) == []


def test_hdf5_layout_with_plain_h5py(tmp_path: Path) -> None:
    record = make_record(samples=5000)
    path = write_run(tmp_path / "run.h5", record, compression="gzip")
    with h5py.File(path, "r") as handle:
        assert list(handle) == list(RunRecord.ARRAY_NAMES)
        assert handle.attrs["format"] == "aaria_pin run"
        assert handle.attrs["format_version"] == 1
        assert handle.attrs["rate"] == 100.0
        assert handle.attrs["seed"] == 7
        assert handle.attrs["version"] == "0.1.0"
        np.testing.assert_array_equal(handle.attrs["gravity"], [0, 0, -9.81])
        assert json.loads(handle.attrs["noise_parameters_json"]) == ATTRIBUTES["noise_parameters"]
        assert json.loads(handle.attrs["config_json_json"]) == ATTRIBUTES["config_json"]
        assert "noise_parameters" not in handle.attrs
        columns = handle["senSen"].attrs["columns"]
        assert [str(c) for c in columns] == list(SENSEN_COLUMNS)
        assert len(columns) == 91
        assert handle["q"].attrs["units"] == "rad or m"
        for name, array in record.arrays().items():
            dataset = handle[name]
            assert dataset.dtype == np.float64
            assert dataset.shape == array.shape
            assert isinstance(dataset.attrs["units"], str)
            np.testing.assert_array_equal(dataset[()], array)
            if name in TIME_SERIES:
                assert dataset.compression == "gzip"
                assert dataset.compression_opts == 1
                assert dataset.shuffle
                assert dataset.chunks is not None
                assert dataset.chunks[1:] == array.shape[1:]
                assert 1 <= dataset.chunks[0] <= 4096
                assert dataset.chunks[0] * array[0].nbytes <= 2**20
            else:
                assert dataset.chunks is None


def test_mat_layout_with_plain_loadmat(tmp_path: Path) -> None:
    record = make_record()
    path = write_run(tmp_path / "run.mat", record)
    contents = loadmat(path)
    for name, array in record.arrays().items():
        assert contents[name].shape == array.shape, name
        np.testing.assert_array_equal(contents[name], array, err_msg=name)
    columns = contents["senSen_columns"]
    assert columns.shape == (1, 91)
    assert [str(cell.item()) for cell in columns.ravel()] == list(SENSEN_COLUMNS)
    assert contents["attr_format"].item() == "aaria_pin run"
    assert contents["attr_format_version"].item() == 1
    assert contents["attr_rate"].item() == 100.0
    assert contents["attr_seed"].item() == 7
    assert contents["attr_version"].item() == "0.1.0"
    np.testing.assert_array_equal(contents["attr_gravity"], [[0, 0, -9.81]])
    noise = json.loads(contents["attr_noise_parameters_json"].item())
    assert noise == ATTRIBUTES["noise_parameters"]


def test_mat_resaved_squeezed_still_reads(tmp_path: Path) -> None:
    # a one-sample run as another tool might store it: singleton axes dropped
    record = make_record(samples=1)
    path = write_run(tmp_path / "run.mat", record)
    contents = {k: v for k, v in loadmat(path, squeeze_me=True).items() if not k.startswith("__")}
    assert contents["q"].shape == (6,)
    assert contents["tool_pose"].shape == (4, 4)
    contents["attr_format_version"] = 1.0  # MATLAB's default class is double
    savemat(path, contents)
    read = read_run(path)
    assert read.q.shape == (1, 6)
    assert read.tool_pose.shape == (1, 4, 4)
    np.testing.assert_array_equal(read.senSen, record.senSen)
    np.testing.assert_array_equal(read.tool_pose, record.tool_pose)


@pytest.mark.parametrize("suffix", [".h5", ".mat"])
def test_summary(tmp_path: Path, suffix: str) -> None:
    record = make_record(samples=1)
    path = write_run(tmp_path / f"run{suffix}", record)
    summary = run_file_summary(path)
    assert summary["path"] == str(path)
    assert summary["format"] == ("MATLAB v5" if suffix == ".mat" else "HDF5")
    assert summary["format_version"] == 1
    assert summary["samples"] == 1
    assert summary["arrays"] == {name: a.shape for name, a in record.arrays().items()}
    assert summary["attributes"] == record.attributes


def test_unknown_suffix_writes_nothing(tmp_path: Path) -> None:
    with pytest.raises(
        OutputFileError, match=r"unknown run file type '\.csv'.*\.h5, \.hdf5, \.mat"
    ):
        write_run(tmp_path / "run.csv", make_record())
    assert list(tmp_path.iterdir()) == []


def test_missing_folder(tmp_path: Path) -> None:
    with pytest.raises(OutputFileError, match="does not exist"):
        write_run(tmp_path / "nope" / "run.h5", make_record())


@pytest.mark.parametrize(
    ("changes", "pattern"),
    [
        ({"q": np.zeros((36, 6))}, r"array 'q' has shape \(36, 6\); expected \(37, 6\)"),
        ({"senSenDH": np.zeros((7, 5))}, r"'senSenDH' has shape \(7, 5\); expected \(8, 5\)"),
        ({"attributes": {"format": "x"}}, "attribute name 'format' is reserved"),
        ({"attributes": {"bad": object()}}, "attribute 'bad' cannot be stored"),
    ],
)
def test_bad_record_writes_nothing(tmp_path: Path, changes: dict[str, Any], pattern: str) -> None:
    record = make_record()
    for name, value in changes.items():
        setattr(record, name, value)
    with pytest.raises(OutputFileError, match=pattern):
        write_run(tmp_path / "run.h5", record)
    assert list(tmp_path.iterdir()) == []


def test_mat_needs_matlab_names(tmp_path: Path) -> None:
    record = make_record(attributes={"noise level": 1.0})
    with pytest.raises(OutputFileError, match="'noise level' cannot be a MATLAB variable"):
        write_run(tmp_path / "run.mat", record)
    assert list(tmp_path.iterdir()) == []
    assert read_run(write_run(tmp_path / "run.h5", record)).attributes == {"noise level": 1.0}


def test_failure_during_writing_leaves_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def explode(*args: Any, **kwargs: Any) -> None:
        raise RuntimeError("disk on fire")

    monkeypatch.setattr(h5py.Group, "create_dataset", explode)
    monkeypatch.setattr(scipy.io, "savemat", explode)
    for name in ("run.h5", "run.mat"):
        with pytest.raises(RuntimeError, match="disk on fire"):
            write_run(tmp_path / name, make_record())
    assert list(tmp_path.iterdir()) == []


def test_failure_keeps_previous_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = write_run(tmp_path / "run.h5", make_record(seed=1))
    before = path.read_bytes()

    def explode(*args: Any, **kwargs: Any) -> None:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(h5py.Group, "create_dataset", explode)
    with pytest.raises(OutputFileError, match=r"cannot be written .*No space left"):
        write_run(path, make_record(seed=2))
    assert path.read_bytes() == before
    assert list(tmp_path.iterdir()) == [path]


def test_read_missing_or_unknown(tmp_path: Path) -> None:
    with pytest.raises(InputFileError, match="no such file"):
        read_run(tmp_path / "missing.h5")
    with pytest.raises(InputFileError, match=r"unknown run file type '\.npz'"):
        read_run(tmp_path / "run.npz")


def test_read_non_run_files(tmp_path: Path) -> None:
    with h5py.File(tmp_path / "other.h5", "w") as handle:
        handle.create_dataset("x", data=np.zeros(3))
    with pytest.raises(InputFileError, match=r"not an aaria_pin run file \(no 'format' attribute"):
        read_run(tmp_path / "other.h5")
    with pytest.raises(InputFileError, match="not an aaria_pin run file"):
        run_file_summary(tmp_path / "other.h5")

    (tmp_path / "garbage.h5").write_bytes(b"not hdf5")
    with pytest.raises(InputFileError, match="cannot be read as an HDF5 run file"):
        read_run(tmp_path / "garbage.h5")

    savemat(tmp_path / "other.mat", {"senSenDH": np.zeros((8, 5))})
    with pytest.raises(InputFileError, match="not an aaria_pin run file"):
        read_run(tmp_path / "other.mat")
    (tmp_path / "garbage.mat").write_bytes(b"garbage")
    with pytest.raises(InputFileError, match=r"cannot be read as a \.mat run file"):
        read_run(tmp_path / "garbage.mat")


def test_read_incomplete_or_newer_run(tmp_path: Path) -> None:
    path = write_run(tmp_path / "run.h5", make_record())
    with h5py.File(path, "a") as handle:
        del handle["tau"]
    with pytest.raises(InputFileError, match="no dataset 'tau'"):
        read_run(path)

    path = write_run(tmp_path / "run.h5", make_record())
    with h5py.File(path, "a") as handle:
        handle.attrs["format_version"] = 2
    with pytest.raises(InputFileError, match="format_version 2 is not supported"):
        read_run(path)

    path = write_run(tmp_path / "run.h5", make_record())
    with h5py.File(path, "a") as handle:
        del handle["q"]
        handle.create_dataset("q", data=np.zeros((37, 5)))
    with pytest.raises(InputFileError, match=r"'q' has shape \(37, 5\); expected \(37, 6\)"):
        read_run(path)
