"""Files written by aaria_pin 0.3.0 still read, and the present code re-makes every array of
each run bit for bit from the inputs it stores (fixtures: tests/fixtures/v0_3_0, written before
the run engine moved into the core): DH runs (sine, Fourier, trajectory, torque drive; .h5 and
.mat), ur5 (sine, Fourier), the wrist, the pick-place arm and three data sets."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from aaria_pin.apps.remake import remake_record
from aaria_pin.files.dataset.reader import DatasetReader
from aaria_pin.files.runfile import read_run

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures" / "v0_3_0"
ARRAYS = ("time", "q", "qd", "qdd", "tau", "base_pose", "base_wrench", "tool_pose", "imu")
RUNS = [
    "dh_run.h5",
    "dh_run.mat",
    "dh_fourier.h5",
    "dh_torque.h5",
    "dh_traj.h5",
    "ur5_run.h5",
    "ur5_fourier.h5",
    "wrist_run.h5",
    "pick_place_run.h5",
]


@pytest.mark.parametrize("name", RUNS)
def test_a_0_3_run_file_is_made_again_bit_for_bit(name: str) -> None:
    stored = read_run(FIXTURES / name)
    again = remake_record(stored)
    assert again.joint_names == stored.joint_names
    for array in ARRAYS:
        np.testing.assert_array_equal(getattr(again, array), getattr(stored, array), array)
    for name_, table in stored.tables.items():
        # the wrist's 3-vector of targets is stored as a 1 × 3 table
        made = np.reshape(again.tables[name_], np.shape(table))
        np.testing.assert_array_equal(made, table, name_)


@pytest.mark.parametrize("name", ["dh_dataset.h5", "ur5_dataset.h5", "dh_fourier_dataset.h5"])
def test_a_0_3_data_set_run_is_made_again_bit_for_bit(name: str) -> None:
    with DatasetReader(FIXTURES / name) as reader:
        assert reader.complete.all()
        for k in range(len(reader)):
            stored = reader.record(k)
            again = remake_record(stored)
            for array in ("q", "qd", "qdd", "tau", "imu", "base_wrench", "tool_pose"):
                # stored as float32: the re-made float64 run rounds to the stored numbers
                np.testing.assert_array_equal(
                    getattr(again, array).astype(np.float32), getattr(stored, array), array
                )
