"""The stored standard inertial parameters against Pinocchio: the run's own torques and base
wrench are Pinocchio's torque regressor (``computeJointTorqueRegressor``, one call a sample) on
the stored motion times the stored table, and the table is Pinocchio's
``Inertia.toDynamicParameters`` of the model rebuilt from the file's tables (random DH arms, the
``aaria-fig3`` preset with a prismatic joint and an empty module, a ur5 on a fixed base)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from pinocchio_oracles import reference_torque_regressor

from aaria_pin.apps.dataset.generate import generate_dataset
from aaria_pin.apps.dataset.spec_sources import DatasetSources
from aaria_pin.apps.record_model import (
    record_base,
    record_columns,
    record_model,
)
from aaria_pin.core.record import RunRecord
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory
from aaria_pin.errors import ParameterError
from aaria_pin.files.dataset.reader import DatasetReader

TABLE = "inertial_parameters"
SPECS = {
    "random": {"seed": 1},
    "fig3": {"preset": "aaria-fig3"},
    "ur5_fixed": {"robot": "ur5", "fixed_base": True},
}
FIXTURES = Path(__file__).resolve().parent.parent / "fixtures"


@pytest.fixture(scope="module", params=sorted(SPECS))
def dataset(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Three runs of 0.2 s at 100 Hz of one of :data:`SPECS`."""
    path = tmp_path_factory.mktemp("inertia") / f"{request.param}.h5"
    sources = DatasetSources(n_runs=3, duration=0.2, rate=100.0, **SPECS[request.param])
    generate_dataset(path, sources.spec(), workers=1)
    return path


def _model_order(record: RunRecord) -> tuple[object, list[int], np.ndarray]:
    """The model rebuilt from the record, its joints' record columns and the table's parameters
    in the model's body order (the base body first on a moving base)."""
    robot = record_model(record)  # a free-flyer root: a fixed base's is at rest
    columns = record_columns(record, robot)
    table = record.tables[TABLE]
    rows = [table[c] for c in columns]
    if robot.moving_base:
        rows.insert(0, table[-1])
    return robot, columns, np.concatenate(rows)


def test_torques_and_base_wrench_are_the_regressor_times_the_table(dataset: Path) -> None:
    with DatasetReader(dataset) as reader:
        assert TABLE in reader.names and TABLE in reader.stored_names
        for k in range(len(reader)):
            record = reader.record(k)
            assert record.tables[TABLE].shape == (len(record.joint_names) + 1, 10)
            robot, columns, pi = _model_order(record)
            base = record_base(record) or BaseMotion.resting(record.n_samples)
            motion = (
                np.ascontiguousarray(x[:, columns]) for x in (record.q, record.qd, record.qdd)
            )
            trajectory = JointTrajectory(record.time, *motion)
            generalized = reference_torque_regressor(robot, base, trajectory) @ pi
            tau = record.tau[:, columns]  # float32 numbers: float32 precision
            skip = 6 if robot.moving_base else 0
            scale = np.abs(tau).max()
            np.testing.assert_allclose(generalized[:, skip:], tau, rtol=0, atol=2e-6 * scale)
            if robot.moving_base:  # the base's rows, in base axes: the record's world-aligned
                rotation = record.base_pose[:, :3, :3]
                force = np.einsum("tij,tj->ti", rotation, generalized[:, :3])
                moment = np.einsum("tij,tj->ti", rotation, generalized[:, 3:6])
                wrench = record.base_wrench
                np.testing.assert_allclose(
                    np.hstack([force, moment]), wrench, rtol=0, atol=2e-6 * np.abs(wrench).max()
                )


def test_the_table_is_the_rebuilt_models_parameters_zeros_where_no_joint(dataset: Path) -> None:
    with DatasetReader(dataset) as reader:
        for k in range(len(reader)):
            record = reader.record(k)
            robot, columns, pi = _model_order(record)
            expected = np.concatenate(
                [
                    np.asarray(robot.model.inertias[j].toDynamicParameters())
                    for j in range(1, robot.model.njoints)
                ]
            )
            np.testing.assert_allclose(pi, expected, rtol=1e-12, atol=1e-12)
            table = record.tables[TABLE]
            missing = [c for c in range(len(record.joint_names)) if c not in columns]
            assert not np.any(table[missing])  # an empty module: zeros
            assert np.all(table[columns, 0] > 0)  # every joint moves a body of some mass
            assert table[-1, 0] > 0  # the base body: its mass
            if "senSenDH" in reader.names:  # an empty module is one of link type 0
                empty = reader.labels(k)["empty_mask"]
                assert sorted(missing) == np.flatnonzero(empty).tolist()


def test_the_preset_with_an_empty_module_has_a_zero_row(tmp_path: Path) -> None:
    sources = DatasetSources(n_runs=1, duration=0.1, rate=100.0, preset="aaria-fig3")
    spec = sources.spec()
    table = spec.arrays(0)[TABLE]
    dh = spec.arrays(0)["senSenDH"]
    empty = np.flatnonzero(np.rint(dh[:6, 4]) == 0)
    assert empty.size >= 1 and not np.any(table[empty])
    assert table.dtype == np.float64


@pytest.mark.parametrize("version", ["v0_2_0", "v0_3_0"])
def test_older_files_read_without_the_table(version: str) -> None:
    with DatasetReader(FIXTURES / version / "dh_dataset.h5") as reader:
        assert TABLE not in reader.names
        with pytest.raises(ParameterError) as caught:
            reader.windows(5, names=("imu", TABLE))
        assert caught.value.parameter == "names"
        assert TABLE not in str(caught.value).split("allowed:")[1]
