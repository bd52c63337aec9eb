"""Data sets of URDF robots: their layout, determinism, runs equal to single runs."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest
from click.testing import CliRunner

from aaria_pin.aaria.randomize import RandomConfig, random_urdf_joint_table
from aaria_pin.apps.dataset.generate import generate_dataset
from aaria_pin.apps.dataset.urdf_spec import UrdfDatasetSpec, UrdfSource
from aaria_pin.cli import main
from aaria_pin.core.catalogue import find_robot
from aaria_pin.core.urdf_robot import load_urdf_robot, read_urdf_file, urdf_joint_trajectory
from aaria_pin.core.urdf_run import simulate_urdf_run
from aaria_pin.errors import ParameterError
from aaria_pin.files.dataset.reader import DatasetReader


def _panda() -> UrdfSource:
    entry = find_robot("panda")
    return UrdfSource(read_urdf_file(entry.urdf), "panda", str(entry.urdf.parent))


@pytest.fixture(scope="module")
def panda_set(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("urdf") / "panda.h5"
    spec = UrdfDatasetSpec(n_runs=4, seed=5, duration=1.0, vary=("joints", "base"), robot=_panda())
    generate_dataset(path, spec, workers=2)
    return path


def test_layout_names_and_shapes(panda_set: Path) -> None:
    with h5py.File(panda_set, "r") as handle:
        assert handle["signals"].shape == (4, 101, 1 + 9 + 6 * 20)
        assert handle["joint_table"].shape == (4, 9, 5) and handle["tau"].shape == (4, 101, 9)
        assert handle["imu_mount"].shape == (4, 20, 4, 4)
        assert handle["joint_table"].dtype == np.float64 and handle["tau"].dtype == np.float32
        columns = [
            c.decode() if isinstance(c, bytes) else c for c in handle["signals"].attrs["columns"]
        ]
        assert (
            columns[:2] == ["time", "q:panda_joint1"]
            and columns[-1] == "imu_panda_rightfinger_b_fz"
        )
        assert handle["urdf"].asstr()[()] == _panda().urdf
    with DatasetReader(panda_set) as reader:
        assert next(iter(reader.layout.views)) == "signals"
        assert reader.attributes["robot_info"]["tool_frame"] == "panda_hand_tcp"
        windows = list(reader.windows(50, names=("signals", "tau")))
        assert len(windows) == 4 * 2 and windows[0][2]["signals"].shape == (50, 130)


def test_a_run_equals_the_single_run_of_its_inputs(panda_set: Path) -> None:
    source = _panda()
    spec = UrdfDatasetSpec(n_runs=4, seed=5, duration=1.0, vary=("joints", "base"), robot=source)
    inputs = spec.inputs(2)
    joint_table, base_table = inputs.tables["joint_table"], inputs.tables["base_table"]
    single = simulate_urdf_run(
        source.urdf, joint_table, base_table, duration=1.0, seed=inputs.noise_seed, noise=True
    )
    with DatasetReader(panda_set) as reader:
        run = reader.run(2, ("joint_table", "signals", "tau"))
    np.testing.assert_array_equal(run["joint_table"], joint_table)
    np.testing.assert_array_equal(run["signals"], single.signals().astype(np.float32))
    np.testing.assert_array_equal(run["tau"], single.tau.astype(np.float32))


def test_one_worker_gives_the_same_file_arrays(panda_set: Path, tmp_path: Path) -> None:
    spec = UrdfDatasetSpec(n_runs=4, seed=5, duration=1.0, vary=("joints", "base"), robot=_panda())
    generate_dataset(tmp_path / "one.h5", spec, workers=1)
    with DatasetReader(panda_set) as two, DatasetReader(tmp_path / "one.h5") as one:
        for k in range(4):
            for name, value in two.run(k).items():
                np.testing.assert_array_equal(one.run(k)[name], value)


def test_resume_redoes_missing_runs_and_refuses_another_robot(
    panda_set: Path, tmp_path: Path
) -> None:
    copy = tmp_path / "copy.h5"
    copy.write_bytes(panda_set.read_bytes())
    with h5py.File(copy, "r+") as handle:
        handle["complete"][1] = 0
    spec = UrdfDatasetSpec(n_runs=4, seed=5, duration=1.0, vary=("joints", "base"), robot=_panda())
    report = generate_dataset(copy, spec, workers=1, resume=True)
    assert report.written == 1 and report.complete == 4
    with DatasetReader(panda_set) as a, DatasetReader(copy) as b:
        np.testing.assert_array_equal(
            a.run(1, ("signals",))["signals"], b.run(1, ("signals",))["signals"]
        )
    entry = find_robot("ur5")
    other = UrdfDatasetSpec(
        n_runs=4, seed=5, duration=1.0, vary=("joints", "base"),
        robot=UrdfSource(read_urdf_file(entry.urdf), "ur5"),
    )  # fmt: skip
    with pytest.raises(ParameterError, match="robot"):
        generate_dataset(copy, other, workers=1, resume=True)


def test_structure_of_a_urdf_robot_cannot_vary() -> None:
    with pytest.raises(ParameterError, match="structure is fixed"):
        UrdfDatasetSpec(n_runs=2, robot=_panda())


def test_random_joint_tables_respect_position_and_velocity_limits() -> None:
    loaded = load_urdf_robot(_panda().urdf)
    time = np.linspace(0.0, 20.0, 2001)
    for k in range(50):
        table = random_urdf_joint_table(RandomConfig(), loaded.joints, np.random.default_rng(k))
        trajectory = urdf_joint_trajectory(table, loaded, time)  # validates the limits too
        for column, joint in enumerate(loaded.joints):
            if joint.mimic is None:
                assert joint.lower - 1e-12 <= trajectory.q[:, column].min()
                assert trajectory.q[:, column].max() <= joint.upper + 1e-12


def test_cli_dataset_of_a_robot_and_info(tmp_path: Path) -> None:
    out = tmp_path / "ur5.h5"
    result = CliRunner().invoke(
        main, ["dataset", "--robot", "ur5", "-n", "3", "-o", str(out), "--duration", "0.5",
               "--workers", "1", "--quiet"]
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    info = CliRunner().invoke(main, ["info", str(out)])
    assert "robot ur5 (ur5), 6 joints, 14 IMUs, tool tool0, moving base" in info.output
    refused = CliRunner().invoke(
        main, ["dataset", "--robot", "ur5", "--preset", "aaria-fig2", "-n", "2", "-o",
               str(tmp_path / "x.h5")]
    )  # fmt: skip
    assert refused.exit_code == 2 and not (tmp_path / "x.h5").exists()


def test_resume_refuses_other_imu_poses(panda_set: Path, tmp_path: Path) -> None:
    from aaria_pin.core.record import ImuMount

    copy = tmp_path / "copy.h5"
    copy.write_bytes(panda_set.read_bytes())
    with h5py.File(copy, "r+") as handle:
        handle["complete"][3] = 0
    default = _panda().load().imu_mounts
    moved = tuple(
        ImuMount(m.name, m.parent, m.T_parent_imu + np.pad([[0, 0, 0, 0.01]], ((2, 1), (0, 0))))
        if k == 0
        else m
        for k, m in enumerate(default)
    )
    source = _panda()
    other = UrdfDatasetSpec(
        n_runs=4, seed=5, duration=1.0, vary=("joints", "base"),
        robot=UrdfSource(source.urdf, "panda", source.urdf_dir, imu_layout=moved),
    )  # fmt: skip
    with pytest.raises(ParameterError, match="robot"):
        generate_dataset(copy, other, workers=1, resume=True)


def test_a_fixed_joint_table_is_checked_before_any_run() -> None:
    from aaria_pin.errors import TableError

    table = np.zeros((9, 5))
    table[3, 2] = 1.0  # panda_joint4 spans [-3.07, -0.07] rad
    with pytest.raises(TableError, match="panda_joint4"):
        UrdfDatasetSpec(n_runs=2, vary=("base",), joint_table=table, robot=_panda())
