from __future__ import annotations

import json
import shutil
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest
import scipy.io
from scipy.io import loadmat, savemat

from aaria_pin.core.record import ColumnSource, ColumnView, ImuMount, RunRecord
from aaria_pin.errors import InputFileError, OutputFileError
from aaria_pin.files.runfile import (
    is_run_file,
    read_run,
    read_run_inputs,
    run_file_summary,
    write_run,
)

ATTRIBUTES: dict[str, Any] = {
    "kind": "dh",
    "robot": "aaria-fig2",
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
SERIES = ("time", "q", "qd", "qdd", "tau", "base_pose", "base_wrench", "tool_pose", "imu")
SIGNALS = ("wx", "wy", "wz", "fx", "fy", "fz")
SLOTS = ("imu_base", "imu_tool", *(f"imu_link{i}_{s}" for i in range(1, 7) for s in "ab"))
SENSEN_COLUMNS = (
    "time",
    *(f"q{i}" for i in range(1, 7)),
    *(f"{slot}_{signal}" for slot in SLOTS for signal in SIGNALS),
)


MAT73 = "v7.3"
"""A ``suffix`` parameter that means a ``.mat`` written as MAT-file v7.3."""


def target(tmp_path: Path, suffix: str) -> tuple[Path, dict[str, Any]]:
    """The run file of a ``suffix`` parameter and the ``write_run`` options it needs."""
    if suffix == MAT73:
        return tmp_path / "run.mat", {"mat_version": "7.3"}
    return tmp_path / f"run{suffix}", {}


def sensen_view() -> ColumnView:
    """The paper's 91 columns written out: time, q1..q6, six signals per slot."""
    sources = [ColumnSource("time", ())]
    sources += [ColumnSource("q", (j,)) for j in range(6)]
    sources += [ColumnSource("imu", (s, k)) for s in range(14) for k in range(6)]
    return ColumnView(SENSEN_COLUMNS, tuple(sources), "see columns")


def make_record(
    samples: int = 37,
    seed: int = 1,
    attributes: dict[str, Any] | None = None,
    joints: int = 6,
    imus: int = 14,
    views: bool = True,
    tables: bool = True,
) -> RunRecord:
    """A record of known random arrays: an Aaria-shaped one by default.

    Without ``tables`` (and without given ``attributes``) it has no ``kind``: a DH run keeps
    its tables, and a reader refuses one without them.
    """
    rng = np.random.default_rng(seed)
    if attributes is None and not tables:
        attributes = {key: value for key, value in ATTRIBUTES.items() if key != "kind"}
    time = np.arange(samples) / 100.0
    names = SLOTS[:imus] if imus <= 14 else tuple(f"imu{s}" for s in range(imus))
    mounts = tuple(
        ImuMount(name, "" if s == 4 else f"link{s}", rng.normal(size=(4, 4)))
        for s, name in enumerate(names)
    )
    record = RunRecord(
        time=time,
        joint_names=tuple(f"joint{j}" for j in range(1, joints + 1)),
        q=rng.normal(size=(samples, joints)),
        qd=rng.normal(size=(samples, joints)),
        qdd=rng.normal(size=(samples, joints)),
        tau=rng.normal(size=(samples, joints)),
        base_pose=rng.normal(size=(samples, 4, 4)),
        base_wrench=rng.normal(size=(samples, 6)),
        tool_pose=rng.normal(size=(samples, 4, 4)),
        imu=rng.normal(size=(samples, imus, 6)),
        imu_mounts=mounts,
        urdf='<robot name="r">\n  <link name="base"/>\n</robot>\n',
        tables=(
            {
                "senSenDH": rng.normal(size=(8, 5)),
                "senSenJ": rng.normal(size=(8, 5)),
                "senSenB": rng.normal(size=(2, 4)),
            }
            if tables
            else {}
        ),
        views={"senSen": sensen_view()} if views and joints == 6 and imus == 14 else {},
        attributes=dict(ATTRIBUTES if attributes is None else attributes),
    )
    return record


def assert_records_equal(read: RunRecord, expected: RunRecord) -> None:
    for name, array in expected.arrays().items():
        got = read.arrays()[name]
        assert got.dtype == np.float64, name
        assert got.shape == array.shape, name
        np.testing.assert_array_equal(got, array, err_msg=name)
    assert list(read.arrays()) == list(expected.arrays())
    assert read.joint_names == expected.joint_names
    assert read.imu_names == expected.imu_names
    assert [m.parent for m in read.imu_mounts] == [m.parent for m in expected.imu_mounts]
    assert read.urdf == expected.urdf
    assert list(read.views) == list(expected.views)
    for name, view in expected.views.items():
        assert read.views[name].columns == view.columns
        assert read.views[name].sources == view.sources
        np.testing.assert_array_equal(read.view(name), expected.view(name))
    assert read.attributes == expected.attributes


@pytest.mark.parametrize("suffix", [".h5", ".hdf5", ".mat", ".H5", MAT73])
def test_round_trip(tmp_path: Path, suffix: str) -> None:
    record = make_record()
    path, options = target(tmp_path, suffix)
    assert write_run(path, record, **options) == path
    read = read_run(path)
    assert_records_equal(read, record)
    assert list(read.attributes) == list(record.attributes)
    assert type(read.attributes["seed"]) is int
    assert type(read.attributes["noise"]) is bool
    assert type(read.attributes["rate"]) is float
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]
    assert is_run_file(path)


@pytest.mark.parametrize("suffix", [".h5", ".mat", MAT73])
@pytest.mark.parametrize(
    ("joints", "imus", "views", "tables"),
    [(1, 0, False, False), (3, 2, False, True), (7, 0, False, True), (6, 14, True, False)],
)
def test_round_trip_of_every_shape(
    tmp_path: Path, suffix: str, joints: int, imus: int, views: bool, tables: bool
) -> None:
    record = make_record(samples=23, joints=joints, imus=imus, views=views, tables=tables)
    path, options = target(tmp_path, suffix)
    read = read_run(write_run(path, record, **options))
    assert_records_equal(read, record)
    assert read.imu.shape == (23, imus, 6)
    assert read.imu_mount.shape == (imus, 4, 4)


@pytest.mark.parametrize("suffix", [".h5", ".mat"])
def test_view_by_joint_names_and_other_series(tmp_path: Path, suffix: str) -> None:
    record = make_record(samples=9, joints=2, imus=1, views=False, tables=False)
    record.joint_names = ("lift", "hand:roll")
    columns = ("time", "q:hand:roll", "tau:lift", "qd2", "imu_base_fz", "imu_base_wx")
    sources = (
        ColumnSource("time", ()),
        ColumnSource("q", (1,)),
        ColumnSource("tau", (0,)),
        ColumnSource("qd", (1,)),
        ColumnSource("imu", (0, 5)),
        ColumnSource("imu", (0, 0)),
    )
    record.views["mine"] = ColumnView(columns, sources)
    expected = np.column_stack(
        [
            record.time,
            record.q[:, 1],
            record.tau[:, 0],
            record.qd[:, 1],
            record.imu[:, 0, 5],
            record.imu[:, 0, 0],
        ]
    )
    path = write_run(tmp_path / f"run{suffix}", record)
    read = read_run(path)
    np.testing.assert_array_equal(read.view("mine"), expected)
    assert read.views["mine"].sources == sources
    if suffix == ".h5":
        with h5py.File(path, "r") as handle:
            np.testing.assert_array_equal(handle["mine"][()], expected)
    else:
        np.testing.assert_array_equal(loadmat(path)["mine"], expected)


def test_sensen_is_a_virtual_dataset_that_survives_moves(tmp_path: Path) -> None:
    record = make_record(samples=50)
    expected = np.column_stack([record.time, record.q, record.imu.reshape(50, 84)])
    path = write_run(tmp_path / "run.h5", record, compression="gzip")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    moved = elsewhere / "moved.h5"
    path.rename(moved)
    copied = tmp_path / "copy.h5"
    shutil.copy(moved, copied)
    for file in (moved, copied):
        with h5py.File(file, "r") as handle:
            dataset = handle["senSen"]
            assert dataset.is_virtual
            assert {source.file_name for source in dataset.virtual_sources()} == {"."}
            assert dataset.shape == (50, 91)
            assert dataset.dtype == np.float64
            assert [str(c) for c in dataset.attrs["columns"]] == list(SENSEN_COLUMNS)
            data = dataset[()]
        assert data.tobytes() == expected.tobytes()
        assert data.tobytes() == record.view("senSen").tobytes()
        assert_records_equal(read_run(file), record)


@pytest.mark.parametrize("suffix", [".h5", ".mat", MAT73])
def test_one_sample_run_keeps_shapes(tmp_path: Path, suffix: str) -> None:
    record = make_record(samples=1)
    path, options = target(tmp_path, suffix)
    write_run(path, record, **options)
    read = read_run(path)
    assert read.time.shape == (1,)
    assert read.q.shape == (1, 6)
    assert read.view("senSen").shape == (1, 91)
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
        assert handle["imu"].compression == "lzf"
        np.testing.assert_array_equal(handle["senSen"][()], record.view("senSen"))
    assert_records_equal(read_run(path), record)


def test_unknown_compression_is_refused(tmp_path: Path) -> None:
    with pytest.raises(OutputFileError, match="compression 'zstd' is not allowed"):
        write_run(tmp_path / "run.h5", make_record(samples=3), compression="zstd")
    assert list(tmp_path.iterdir()) == []


def test_hdf5_layout_with_plain_h5py(tmp_path: Path) -> None:
    record = make_record(samples=5000)
    path = write_run(tmp_path / "run.h5", record, compression="gzip")
    with h5py.File(path, "r") as handle:
        assert list(handle) == [
            *SERIES,
            "imu_mount",
            "senSenDH",
            "senSenJ",
            "senSenB",
            "senSen",
            "joint_names",
            "imu_names",
            "imu_parents",
            "urdf",
        ]
        assert handle.attrs["format"] == "aaria_pin run"
        assert handle.attrs["format_version"] == 2
        assert handle.attrs["kind"] == "dh"
        assert handle.attrs["robot"] == "aaria-fig2"
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
        assert handle["joint_names"].asstr()[()].tolist() == list(record.joint_names)
        assert handle["imu_names"].asstr()[()].tolist() == list(SLOTS)
        assert handle["imu_parents"].asstr()[()].tolist() == [m.parent for m in record.imu_mounts]
        assert handle["urdf"].asstr()[()] == record.urdf
        for name, array in record.arrays().items():
            dataset = handle[name]
            assert dataset.dtype == np.float64
            assert dataset.shape == array.shape
            assert isinstance(dataset.attrs["units"], str)
            np.testing.assert_array_equal(dataset[()], array)
            if name in SERIES:
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
        stored = contents[name]
        assert stored.shape == ((1, 37) if name == "time" else array.shape), name
        np.testing.assert_array_equal(stored.reshape(array.shape), array, err_msg=name)
    np.testing.assert_array_equal(
        contents["senSen"], np.column_stack([record.time, record.q, record.imu.reshape(37, 84)])
    )
    columns = contents["senSen_columns"]
    assert columns.shape == (1, 91)
    assert [str(cell.item()) for cell in columns.ravel()] == list(SENSEN_COLUMNS)
    assert [str(cell.item()) for cell in contents["joint_names"].ravel()] == [
        f"joint{j}" for j in range(1, 7)
    ]
    assert [str(cell.item()) for cell in contents["imu_names"].ravel()] == list(SLOTS)
    parents = [
        "" if cell.size == 0 else str(cell.item()) for cell in contents["imu_parents"].ravel()
    ]
    assert parents == [m.parent for m in record.imu_mounts]
    assert contents["urdf"].item() == record.urdf
    assert contents["attr_format"].item() == "aaria_pin run"
    assert contents["attr_format_version"].item() == 2
    assert contents["attr_kind"].item() == "dh"
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
    contents["attr_format_version"] = 2.0  # MATLAB's default class is double
    savemat(path, contents)
    read = read_run(path)
    assert read.q.shape == (1, 6)
    assert read.tool_pose.shape == (1, 4, 4)
    assert read.imu.shape == (1, 14, 6)
    np.testing.assert_array_equal(read.view("senSen"), record.view("senSen"))
    np.testing.assert_array_equal(read.tool_pose, record.tool_pose)


@pytest.mark.parametrize("suffix", [".h5", ".mat", MAT73])
def test_summary(tmp_path: Path, suffix: str) -> None:
    record = make_record(samples=1)
    path, options = target(tmp_path, suffix)
    write_run(path, record, **options)
    summary = run_file_summary(path)
    assert summary["path"] == str(path)
    assert summary["format"] == {".mat": "MATLAB v5", MAT73: "MATLAB v7.3"}.get(suffix, "HDF5")
    assert summary["format_version"] == 2
    assert summary["layout"] == "aaria_pin run"
    assert summary["kind"] == "dh"
    assert summary["robot"] == "aaria-fig2"
    assert summary["samples"] == 1
    assert summary["rate"] == 100.0
    assert summary["joints"] == list(record.joint_names)
    assert summary["imus"] == list(SLOTS)
    assert summary["arrays"] == {name: a.shape for name, a in record.arrays().items()}
    assert summary["views"] == {"senSen": (1, 91)}
    assert summary["attributes"] == record.attributes


def test_summary_rate_from_the_times(tmp_path: Path) -> None:
    record = make_record(samples=4, attributes={"kind": "urdf"})
    record.time = np.array([0.0, 0.04, 0.08, 0.12])
    for suffix in (".h5", ".mat"):
        assert run_file_summary(write_run(tmp_path / f"run{suffix}", record))["rate"] == 25.0


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
        ({"imu": np.zeros((37, 13, 6))}, r"'imu' has shape \(37, 13, 6\); expected \(37, 14, 6\)"),
        ({"tables": {"q": np.zeros(3)}}, "table name 'q' is not allowed"),
        ({"tables": {"a b": np.zeros(3)}}, "table name 'a b' is not allowed"),
        ({"tables": {"senSen": np.zeros(3)}}, "view name 'senSen' is not allowed"),
        ({"attributes": {"format": "x"}}, "attribute name 'format' is reserved"),
        ({"attributes": {"bad": object()}}, "attribute 'bad' cannot be stored"),
    ],
)
def test_bad_record_writes_nothing(tmp_path: Path, changes: dict[str, Any], pattern: str) -> None:
    record = make_record()
    for name, value in changes.items():
        setattr(record, name, value)
    for suffix in (".h5", ".mat"):
        with pytest.raises(OutputFileError, match=pattern):
            write_run(tmp_path / f"run{suffix}", record)
    assert list(tmp_path.iterdir()) == []


def test_view_whose_names_do_not_read_back_writes_nothing(tmp_path: Path) -> None:
    record = make_record(views=False)
    record.views["bad"] = ColumnView(("time", "speed"), (ColumnSource("time", ()),) * 2)
    with pytest.raises(OutputFileError, match=r"view 'bad' column 'speed' is time\[\] but"):
        write_run(tmp_path / "run.h5", record)
    record.views["bad"] = ColumnView(("q2",), (ColumnSource("q", (0,)),))
    with pytest.raises(OutputFileError, match=r"'q2' is q\[0\] but its name reads back as q\[1\]"):
        write_run(tmp_path / "run.mat", record)
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
    monkeypatch.setattr(h5py.h5d, "create", explode)  # the run file's low-level datasets
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
    monkeypatch.setattr(h5py.h5d, "create", explode)
    with pytest.raises(OutputFileError, match=r"no space left on device writing .*run\.h5"):
        write_run(path, make_record(seed=2))
    assert path.read_bytes() == before
    assert list(tmp_path.iterdir()) == [path]


def test_read_missing_or_unknown(tmp_path: Path) -> None:
    with pytest.raises(InputFileError, match="no such file"):
        read_run(tmp_path / "missing.h5")
    with pytest.raises(InputFileError, match=r"unknown run file type '\.npz'"):
        read_run(tmp_path / "run.npz")
    assert not is_run_file(tmp_path / "missing.h5")


def test_read_non_run_files(tmp_path: Path) -> None:
    with h5py.File(tmp_path / "other.h5", "w") as handle:
        handle.create_dataset("x", data=np.zeros(3))
    with pytest.raises(InputFileError, match=r"not an aaria_pin run file \(no 'format' attribute"):
        read_run(tmp_path / "other.h5")
    with pytest.raises(InputFileError, match="not an aaria_pin run file"):
        run_file_summary(tmp_path / "other.h5")
    assert not is_run_file(tmp_path / "other.h5")

    with h5py.File(tmp_path / "dataset.h5", "w") as handle:
        handle.attrs["format"] = "aaria_pin dataset"
        handle.attrs["format_version"] = 2
    with pytest.raises(InputFileError, match="format is 'aaria_pin dataset'"):
        read_run(tmp_path / "dataset.h5")
    assert not is_run_file(tmp_path / "dataset.h5")

    (tmp_path / "garbage.h5").write_bytes(b"not hdf5")
    with pytest.raises(InputFileError, match="cannot be read as an HDF5 run file"):
        read_run(tmp_path / "garbage.h5")
    assert not is_run_file(tmp_path / "garbage.h5")

    savemat(tmp_path / "other.mat", {"senSenDH": np.zeros((8, 5))})
    with pytest.raises(InputFileError, match="not an aaria_pin run file"):
        read_run(tmp_path / "other.mat")
    assert not is_run_file(tmp_path / "other.mat")
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
        handle.attrs["format_version"] = 3
    with pytest.raises(InputFileError, match="format_version 3 is not supported"):
        read_run(path)

    path = write_run(tmp_path / "run.h5", make_record())
    with h5py.File(path, "a") as handle:
        del handle["q"]
        handle.create_dataset("q", data=np.zeros((37, 5)))
    with pytest.raises(InputFileError, match=r"'q' has shape \(37, 5\); expected \(37, 6\)"):
        read_run(path)

    path = write_run(tmp_path / "run.mat", make_record())
    contents = {k: v for k, v in loadmat(path).items() if not k.startswith("__")}
    contents["senSen_columns"] = np.array(["time", "speed"], dtype=object)
    savemat(path, contents)
    with pytest.raises(InputFileError, match="view 'senSen': view column 'speed' names no column"):
        read_run(path)


@pytest.mark.parametrize("suffix", [".h5", ".mat", MAT73])
def test_one_dimensional_table_is_a_row(tmp_path: Path, suffix: str) -> None:
    record = make_record(samples=3, views=False, tables=False)
    record.tables["targets"] = np.array([0.1, 0.2, 0.3])
    path, options = target(tmp_path, suffix)
    write_run(path, record, **options)
    read = read_run(path)
    assert read.tables["targets"].shape == (1, 3)
    np.testing.assert_array_equal(read.tables["targets"][0], [0.1, 0.2, 0.3])
    assert run_file_summary(path)["arrays"]["targets"] == (1, 3)


@pytest.mark.parametrize("suffix", [".h5", ".mat", MAT73])
def test_the_inputs_of_a_run_are_read_without_its_series(tmp_path: Path, suffix: str) -> None:
    record = make_record()
    path, options = target(tmp_path, suffix)
    write_run(path, record, **options)
    inputs = read_run_inputs(path)
    assert inputs.n_samples == 0
    assert inputs.q.shape == (0, 6) and inputs.imu.shape == (0, 14, 6)
    np.testing.assert_array_equal(inputs.imu_mount, record.imu_mount)
    assert inputs.tables.keys() == record.tables.keys()
    for name, table in record.tables.items():
        np.testing.assert_array_equal(inputs.tables[name], table)
    assert [(m.name, m.parent) for m in inputs.imu_mounts] == [
        (m.name, m.parent) for m in record.imu_mounts
    ]
    assert inputs.joint_names == record.joint_names and inputs.urdf == record.urdf
    assert inputs.attributes == record.attributes
    assert inputs.views["senSen"].sources == record.views["senSen"].sources


@pytest.mark.parametrize("suffix", [".h5", MAT73])
def test_read_run_inputs_does_not_touch_the_series(tmp_path: Path, suffix: str) -> None:
    """A file whose ``imu`` is replaced by a wrong shape: unreadable whole, its inputs read."""
    record = make_record()
    path, options = target(tmp_path, suffix)
    write_run(path, record, **options)
    with h5py.File(path, "r+") as handle:
        attributes = dict(handle["imu"].attrs)
        del handle["imu"]
        handle.create_dataset("imu", data=np.zeros((5, 5)))
        handle["imu"].attrs.update(attributes)
    with pytest.raises(InputFileError, match="imu"):
        read_run(path)
    np.testing.assert_array_equal(
        read_run_inputs(path).tables["senSenDH"], record.tables["senSenDH"]
    )
