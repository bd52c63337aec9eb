"""The ``.mat`` run file as a MAT-file v7.3, written in time pieces.

A run in pieces (noise on) written as v7.3 reads back as the run computed whole, array for array;
the file's layout is checked with h5py alone (user block header, ``MATLAB_class`` attributes,
reversed dims, cell references, empty markers), and its variables are those of the v5 file that
scipy writes and reads (names, classes, the sizes MATLAB sees, values).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import h5py
import numpy as np
import pytest

from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run, simulate_run_chunks
from aaria_pin.core.record import SERIES, RunRecord
from aaria_pin.core.run import CHUNK_SAMPLES
from aaria_pin.errors import OutputFileError
from aaria_pin.files.runfile import (
    RunFileWriter,
    is_run_file,
    mat_version_for,
    read_run,
    run_file_summary,
    write_run,
    write_run_chunks,
)

SAMPLES = 1000  # 9.99 s at 100 Hz: pieces of 137 samples
SETTINGS = {"duration": 9.99, "rate": 100.0, "seed": 4242, "noise": True}


@pytest.fixture(scope="module")
def whole() -> RunRecord:
    preset = get_preset("aaria-fig3")  # an empty module: empty IMU parents
    return simulate_run(
        preset.table, preset.joint_table, preset.base_table, robot_name="aaria-fig3", **SETTINGS
    )


def pieces(chunk: int = 137) -> list[RunRecord]:
    preset = get_preset("aaria-fig3")
    return list(
        simulate_run_chunks(
            preset.table,
            preset.joint_table,
            preset.base_table,
            robot_name="aaria-fig3",
            chunk=chunk,
            **SETTINGS,
        )
    )


def assert_same_run(a: RunRecord, b: RunRecord) -> None:
    for name in SERIES:
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert np.array_equal(a.imu_mount, b.imu_mount)
    assert [(m.name, m.parent) for m in a.imu_mounts] == [(m.name, m.parent) for m in b.imu_mounts]
    assert a.tables.keys() == b.tables.keys()
    for name in a.tables:
        assert np.array_equal(a.tables[name], b.tables[name]), name
    assert a.attributes == b.attributes
    assert a.joint_names == b.joint_names and a.urdf == b.urdf
    assert a.views.keys() == b.views.keys()
    for name in a.views:
        assert np.array_equal(a.view(name), b.view(name)), name


def test_a_chunked_mat73_run_is_the_one_piece_run(tmp_path: Path, whole: RunRecord) -> None:
    path = write_run_chunks(tmp_path / "run.mat", pieces(), SAMPLES, mat_version="7.3")
    assert_same_run(read_run(path), whole)
    assert is_run_file(path)
    summary = run_file_summary(path)
    assert summary["format"] == "MATLAB v7.3" and summary["samples"] == SAMPLES
    assert summary["views"] == {"senSen": (SAMPLES, 91)}
    one_piece = write_run(tmp_path / "one.mat", whole, mat_version="7.3")
    assert_same_run(read_run(one_piece), whole)


def _char(handle: h5py.File, dataset: h5py.Dataset) -> str:
    """A MATLAB char row read with h5py alone: UTF-16 code units, (L, 1) on disk."""
    assert dataset.attrs["MATLAB_class"] == b"char"
    if dataset.attrs.get("MATLAB_empty", 0):
        assert list(dataset[()]) == [0, 0]
        return ""
    assert dataset.attrs["MATLAB_int_decode"] == 2 and dataset.shape[1] == 1
    return dataset[()][:, 0].astype("<u2").tobytes().decode("utf-16-le")


def _cell(handle: h5py.File, name: str) -> list[str]:
    dataset = handle[name]
    assert dataset.attrs["MATLAB_class"] == b"cell" and dataset.shape[1] == 1  # 1 × n
    return [_char(handle, handle[reference]) for reference in dataset[:, 0]]


def test_the_mat73_layout_read_with_h5py_alone(tmp_path: Path, whole: RunRecord) -> None:
    path = write_run_chunks(tmp_path / "run.mat", pieces(300), SAMPLES, mat_version="7.3")
    with path.open("rb") as stream:
        header = stream.read(128)
    assert header.startswith(b"MATLAB 7.3 MAT-file, Platform: ")
    assert b"HDF5 schema 1.00" in header[:116]
    assert header[116:124] == bytes(8)  # no subsystem data
    assert header[124:126] == b"\x00\x02" and header[126:128] == b"IM"  # version 0x0200, LE
    with h5py.File(path, "r") as handle:
        assert handle.userblock_size == 512
        variables = [name for name in handle if not name.startswith("#")]
        for name in variables:
            assert "MATLAB_class" in handle[name].attrs, name
        # MATLAB's T × n is n × T on disk; time is 1 × T, so T × 1 on disk
        assert handle["time"].shape == (SAMPLES, 1)
        np.testing.assert_array_equal(handle["time"][:, 0], whole.time)
        for name in ("q", "qd", "qdd", "tau", "base_wrench"):
            np.testing.assert_array_equal(handle[name][()], getattr(whole, name).T, err_msg=name)
        for name in ("base_pose", "tool_pose"):  # T × 4 × 4 is 4 × 4 × T: [j, i, t] = pose[t, i, j]
            stored = handle[name][()]
            assert stored.shape == (4, 4, SAMPLES)
            assert stored[2, 0, 17] == getattr(whole, name)[17, 0, 2]
        imu = handle["imu"][()]
        assert imu.shape == (6, 14, SAMPLES)
        assert imu[4, 9, 500] == whole.imu[500, 9, 4]
        np.testing.assert_array_equal(handle["senSen"][()], whole.view("senSen").T)
        np.testing.assert_array_equal(handle["senSenDH"][()], whole.tables["senSenDH"].T)
        assert handle["imu_mount"].shape == (4, 4, 14)
        for name in (*SERIES, "senSen", "senSenDH"):
            assert handle[name].attrs["MATLAB_class"] == b"double"
        assert _cell(handle, "joint_names") == list(whole.joint_names)
        assert _cell(handle, "imu_names") == list(whole.imu_names)
        parents = _cell(handle, "imu_parents")
        assert parents == [m.parent for m in whole.imu_mounts] and "" in parents
        assert _cell(handle, "senSen_columns")[:3] == ["time", "q1", "q2"]
        assert _char(handle, handle["urdf"]) == whole.urdf
        assert _char(handle, handle["attr_format"]) == "aaria_pin run"
        version = handle["attr_format_version"]
        assert version.attrs["MATLAB_class"] == b"int64" and version.shape == (1, 1)
        noise = handle["attr_noise"]
        assert noise.attrs["MATLAB_class"] == b"logical" and noise.attrs["MATLAB_int_decode"] == 1
        assert noise.dtype == np.uint8 and noise[0, 0] == 1
        assert handle["attr_gravity"].shape == (3, 1)  # a 1 × 3 row


def test_the_mat73_variables_are_the_v5_variables(tmp_path: Path, whole: RunRecord) -> None:
    """Names, classes, the sizes MATLAB sees and values: v5 through scipy, v7.3 through h5py."""
    from scipy.io import loadmat

    from aaria_pin.files.runfile._mat73 import load_mat73

    v5 = write_run(tmp_path / "v5.mat", whole, mat_version="5")
    v73 = write_run(tmp_path / "v73.mat", whole, mat_version="7.3")
    a = {k: v for k, v in loadmat(v5, squeeze_me=False, mat_dtype=True).items() if k[0] != "_"}
    b = load_mat73(v73)
    assert a.keys() == b.keys()
    for name, value in a.items():
        other = b[name]
        assert (value.dtype, value.shape) == (other.dtype, other.shape), name
        if value.dtype == object:
            for x, y in zip(value.ravel(), other.ravel(), strict=True):
                assert np.array_equal(x, y) and x.shape == y.shape, name
        else:
            assert np.array_equal(value, other), name


def test_a_run_with_no_imu_is_stored_with_empty_markers(tmp_path: Path, whole: RunRecord) -> None:
    bare = dataclasses.replace(
        whole, imu=np.zeros((SAMPLES, 0, 6)), imu_mounts=(), views={}, urdf=""
    )
    path = write_run(tmp_path / "bare.mat", bare, mat_version="7.3")
    with h5py.File(path, "r") as handle:
        for name, size in (("imu", [SAMPLES, 0, 6]), ("imu_names", [0, 0]), ("urdf", [0, 0])):
            assert handle[name].attrs["MATLAB_empty"] == 1, name
            assert list(handle[name][()]) == size, name  # the MATLAB size, MATLAB order
    read = read_run(path)
    assert read.imu.shape == (SAMPLES, 0, 6) and read.imu_names == () and read.urdf == ""
    assert np.array_equal(read.q, whole.q)


def test_the_version_follows_the_run_length(tmp_path: Path, whole: RunRecord) -> None:
    assert mat_version_for(CHUNK_SAMPLES) == "5"
    assert mat_version_for(CHUNK_SAMPLES + 1) == "7.3"
    short = write_run(tmp_path / "short.mat", whole)  # 1,000 samples: v5, as before
    assert run_file_summary(short)["format"] == "MATLAB v5"
    streamed = write_run_chunks(tmp_path / "pieces.mat", pieces(), SAMPLES)  # short: v5
    assert run_file_summary(streamed)["format"] == "MATLAB v5"
    with pytest.raises(OutputFileError, match="written whole"):
        RunFileWriter(tmp_path / "v5.mat", whole)
    with pytest.raises(OutputFileError, match="cannot be read by MATLAB") as caught:
        RunFileWriter(tmp_path / "lzf.mat", whole, compression="lzf", mat_version="7.3")
    assert caught.value.parameter == "compression"
    with pytest.raises(OutputFileError, match="MAT-file version '6'"):
        write_run(tmp_path / "v6.mat", whole, mat_version="6")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pieces.mat", "short.mat"]


def test_a_gzip_mat73_file_is_chunked_along_time(tmp_path: Path, whole: RunRecord) -> None:
    path = write_run_chunks(
        tmp_path / "z.mat", pieces(), SAMPLES, compression="gzip", mat_version="7.3"
    )
    with h5py.File(path, "r") as handle:
        assert handle["imu"].compression == "gzip" and handle["imu"].chunks[:2] == (6, 14)
        assert handle["time"].chunks[1] == 1
    assert_same_run(read_run(path), whole)
