"""One run layout for every robot: a DH preset, ur5, the wrist and the pick-place arm write the
same dataset names and shapes to ``.h5`` and ``.mat``, and read back as the same record."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import h5py
import numpy as np
import pytest
from scipy.io import loadmat, whosmat

from aaria_pin.core.record import RunRecord
from aaria_pin.files.runfile import read_run, write_run

SERIES = ("time", "q", "qd", "qdd", "tau", "base_pose", "base_wrench", "tool_pose", "imu")
NAMES = ("joint_names", "imu_names", "imu_parents", "urdf")


def dh_preset() -> RunRecord:
    from aaria_pin.aaria.presets import get_preset
    from aaria_pin.aaria.simulate import simulate_run

    table = get_preset("aaria-fig3").table
    return simulate_run(table, duration=0.1, rate=100.0, seed=3, robot_name="aaria-fig3")


def ur5() -> RunRecord:
    from aaria_pin.core.catalogue import find_robot
    from aaria_pin.core.urdf_robot import read_urdf_file
    from aaria_pin.core.urdf_run import simulate_urdf_run

    file = find_robot("ur5").urdf
    return simulate_urdf_run(read_urdf_file(file), urdf_dir=file.parent, duration=0.1, rate=100.0)


def wrist() -> RunRecord:
    from aaria_pin.apps.wrist.run import simulate_wrist, wrist_record

    return wrist_record(simulate_wrist(np.radians([10.0, 20.0, 30.0]), duration=0.5, rate=20.0))


def pick_place() -> RunRecord:
    from aaria_pin.apps.arm.run import pick_place_record, simulate_pick_place
    from aaria_pin.apps.arm.task import Cylinder

    return pick_place_record(simulate_pick_place(Cylinder(0.5, 0.2), (-0.3, 0.4), rate=5.0))


PRODUCERS: dict[str, Callable[[], RunRecord]] = {
    "dh": dh_preset,
    "urdf": ur5,
    "wrist": wrist,
    "pick-place": pick_place,
}


def hdf5_shapes(path: Path) -> dict[str, tuple[int, ...]]:
    with h5py.File(path, "r") as handle:
        return {name: tuple(handle[name].shape) for name in handle}


def mat_shapes(path: Path) -> dict[str, tuple[int, ...]]:
    return {
        name: tuple(shape)
        for name, shape, _ in whosmat(path)
        if not name.startswith("attr_") and not name.endswith("_columns")
    }


@pytest.mark.parametrize("kind", list(PRODUCERS))
def test_same_names_and_shapes_in_h5_and_mat(tmp_path: Path, kind: str) -> None:
    record = PRODUCERS[kind]()
    assert record.attributes["kind"] == kind
    h5 = write_run(tmp_path / "run.h5", record)
    mat = write_run(tmp_path / "run.mat", record)
    in_h5, in_mat = hdf5_shapes(h5), mat_shapes(mat)
    samples, joints, imus = record.n_samples, len(record.joint_names), len(record.imu_mounts)
    assert set(in_h5) == set(in_mat)
    assert set(in_h5) >= {*SERIES, "imu_mount", *NAMES}
    assert set(in_h5) == {*SERIES, "imu_mount", *NAMES, *record.tables, *record.views}
    expected = {
        "time": (samples,),
        "q": (samples, joints),
        "tau": (samples, joints),
        "base_pose": (samples, 4, 4),
        "base_wrench": (samples, 6),
        "tool_pose": (samples, 4, 4),
        "imu": (samples, imus, 6),
        "imu_mount": (imus, 4, 4),
    }
    for name, shape in expected.items():
        assert in_h5[name] == shape, name
    for name in in_h5:
        if name == "time":
            assert in_mat[name] == (1, samples)  # a MATLAB row vector
        elif name in ("joint_names", "imu_names", "imu_parents"):
            assert np.prod(in_mat[name]) == in_h5[name][0], name  # 1 × n cell array
        elif name != "urdf":
            assert in_mat[name] == in_h5[name], name
    for path in (h5, mat):
        read = read_run(path)
        for name, array in record.arrays().items():
            if name in record.tables:
                array = np.atleast_2d(array)  # a 1-D table is stored as a 1 × k row
            got = read.arrays()[name]
            assert got.shape == array.shape, f"{path} {name}"
            np.testing.assert_array_equal(got, array, err_msg=f"{path} {name}")
        for name in record.views:
            np.testing.assert_array_equal(read.view(name), record.view(name))
        assert read.joint_names == record.joint_names
        assert read.imu_names == record.imu_names
        assert read.urdf == record.urdf


def test_dh_sensen_imu_columns_are_the_imu_array(tmp_path: Path) -> None:
    record = dh_preset()
    h5 = write_run(tmp_path / "run.h5", record)
    mat = write_run(tmp_path / "run.mat", record)
    with h5py.File(h5, "r") as handle:
        sensen = handle["senSen"][()]
        columns = [str(c) for c in handle["senSen"].attrs["columns"]]
        assert handle["senSen"].is_virtual
    samples = record.n_samples
    assert sensen.shape == (samples, 91)
    assert columns[:7] == ["time", "q1", "q2", "q3", "q4", "q5", "q6"]
    np.testing.assert_array_equal(sensen[:, 0], record.time)
    np.testing.assert_array_equal(sensen[:, 1:7], record.q)
    np.testing.assert_array_equal(sensen[:, 7:], record.imu.reshape(samples, 84))
    np.testing.assert_array_equal(loadmat(mat)["senSen"], sensen)


@pytest.mark.parametrize("suffix", [".h5", ".mat"])
def test_compressed_series_are_chunked_alike_in_both_formats(tmp_path: Path, suffix: str) -> None:
    """At most 4096 samples and 1 MiB a chunk, along time (the .mat v7.3 stores it transposed)."""
    from aaria_pin.aaria.presets import get_preset
    from aaria_pin.aaria.simulate import simulate_run

    record = simulate_run(get_preset("aaria-fig3").table, duration=50.0, rate=100.0, seed=3)
    version = "7.3" if suffix == ".mat" else None
    path = write_run(tmp_path / f"run{suffix}", record, compression="gzip", mat_version=version)
    samples = record.time.shape[0]
    limits: set[int] = set()
    with h5py.File(path, "r") as handle:
        for name in ("q", "imu"):
            data = getattr(record, name)
            row_bytes = 8 * data[0].size
            rows = max(1, min(samples, 4096, 2**20 // row_bytes))
            chunks = handle[name].chunks
            along_time = chunks[0] if suffix == ".h5" else chunks[-1]
            assert along_time == rows, (name, chunks)
            limits.add(rows)
    assert 4096 in limits and len(limits) == 2  # the 4096-sample and the 1 MiB limits met
