"""Files written by aaria_pin 0.2.0 (run and data-set format 2) still read, and the present code
re-makes their numbers bit for bit from the inputs they store (fixtures: tests/fixtures/v0_2_0)."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

from aaria_pin.apps.remake import remake_record
from aaria_pin.files.dataset.reader import DatasetReader
from aaria_pin.files.runfile import read_run

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures" / "v0_2_0"


@pytest.mark.parametrize("name", ["dh_run.h5", "dh_run.mat", "ur5_run.h5"])
def test_a_0_2_run_file_reads_and_is_made_again_bit_for_bit(name: str) -> None:
    stored = read_run(FIXTURES / name)
    assert stored.n_samples == 21
    again = remake_record(stored)
    for array in ("time", "q", "qd", "qdd", "tau", "base_pose", "base_wrench", "tool_pose", "imu"):
        np.testing.assert_array_equal(getattr(again, array), getattr(stored, array), array)


def test_a_0_2_h5_run_matches_its_raw_datasets() -> None:
    record = read_run(FIXTURES / "dh_run.h5")
    with h5py.File(FIXTURES / "dh_run.h5", "r") as handle:  # h5py alone, not our reader
        np.testing.assert_array_equal(record.imu, handle["imu"][()])
        np.testing.assert_array_equal(record.view("senSen"), handle["senSen"][()])


def test_a_0_2_data_set_reads_and_its_runs_are_made_again() -> None:
    path = FIXTURES / "dh_dataset.h5"
    with DatasetReader(path) as reader:
        assert len(reader) == 3 and reader.complete.all()
        for k in range(3):
            stored = reader.record(k)
            again = remake_record(stored)
            for array in ("q", "tau", "imu", "base_wrench"):
                # stored as float32: the re-made float64 run rounds to the stored numbers
                np.testing.assert_array_equal(
                    getattr(again, array).astype(np.float32), getattr(stored, array), array
                )
        windows = reader.windows(10, stride=5, names=("imu",))
        assert len(windows) == 3 * 3
    with h5py.File(path, "r") as handle:
        np.testing.assert_array_equal(windows[4]["imu"], handle["imu"][1, 5:15])
