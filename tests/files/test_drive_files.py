"""Driven runs written after 0.3.0 (fixtures: tests/fixtures/drives_0_3_dev) are re-made bit for
bit from the inputs they store: closed-loop runs (pd with every joint model in the loop,
computed-torque on a moving base), torque runs by the ABA kernel on its stops and by
semi-implicit Euler, and a closed-loop data set with drawn gains."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from aaria_pin.apps.remake import remake_record
from aaria_pin.files.dataset.reader import DatasetReader
from aaria_pin.files.runfile import read_run

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures" / "drives_0_3_dev"
ARRAYS = ("time", "q", "qd", "qdd", "tau", "base_pose", "base_wrench", "tool_pose", "imu")
RUNS = {
    "ur5_pd.h5": ("pd", None),
    "dh_ct.h5": ("computed-torque", None),
    "dh_torque_aba.h5": ("torque", "aba"),
    "ur5_torque_euler.h5": ("torque", "aba"),
}


@pytest.mark.parametrize("name", sorted(RUNS))
def test_a_driven_run_is_made_again_bit_for_bit(name: str) -> None:
    stored = read_run(FIXTURES / name)
    drive, dynamics = RUNS[name]
    assert stored.attributes["drive"] == drive
    assert stored.attributes.get("dynamics") == dynamics
    again = remake_record(stored)
    for array in ARRAYS:
        np.testing.assert_array_equal(getattr(again, array), getattr(stored, array), array)
    assert set(again.tables) == set(stored.tables)
    for table, values in stored.tables.items():
        np.testing.assert_array_equal(again.tables[table], values, table)


def test_the_euler_run_records_its_integrator() -> None:
    stored = read_run(FIXTURES / "ur5_torque_euler.h5")
    assert (stored.attributes["integrator"], stored.attributes["substeps"]) == ("euler", 8)


def test_a_closed_loop_data_set_run_is_made_again_bit_for_bit() -> None:
    with DatasetReader(FIXTURES / "ur5_pd_dataset.h5") as reader:
        assert reader.complete.all()
        gains = []
        for k in range(len(reader)):
            stored = reader.record(k)
            again = remake_record(stored)
            for array in ("q", "qd", "qdd", "tau", "imu"):
                np.testing.assert_array_equal(
                    getattr(again, array).astype(np.float32), getattr(stored, array), array
                )
            for table in ("q_reference", "tau_command", "q_measured"):
                np.testing.assert_array_equal(
                    again.tables[table].astype(np.float32), stored.tables[table], table
                )
            gains.append(stored.tables["controller_kp"])
        assert not np.array_equal(gains[0], gains[1])
