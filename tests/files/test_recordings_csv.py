"""CSV recordings (``files/recordings/csv_io``): out and back bit for bit, a lab's CSV by a map."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from aaria_pin.core.recording import STREAM_COLUMNS, RecordedRun, SensorStream
from aaria_pin.errors import InputFileError, ParameterError
from aaria_pin.files.recordings.csv_io import read_csv, write_csv
from aaria_pin.files.recordings.mapping import RecordingMap, SensorMap


def test_a_run_goes_out_and_back_bit_for_bit(tmp_path: Path) -> None:
    rng = np.random.default_rng(0)
    time = np.arange(7) / 300.0  # 300 Hz: not whole nanoseconds, still exact as text
    imu = SensorStream("tool", "imu", time, rng.normal(size=(7, 6)), STREAM_COLUMNS["imu"])
    joints = SensorStream("joints", "joints", time, rng.normal(size=(7, 2)), ("q:a", "tau:a"))
    run = RecordedRun([imu, joints], time_origin_ns=1_700_000_000_123_456_789)
    back = read_csv(write_csv(tmp_path / "run.csv", run))
    assert back.time_origin_ns == run.time_origin_ns
    for stream in run.streams:
        got = back.stream(stream.name)
        assert got.columns == stream.columns
        np.testing.assert_array_equal(got.values, stream.values)
        np.testing.assert_array_equal(got.time, time)
    other = SensorStream("ft", "wrench", time + 0.001, np.zeros((7, 6)), STREAM_COLUMNS["wrench"])
    with pytest.raises(ParameterError, match="form csv needs one time axis; stream ft"):
        write_csv(tmp_path / "two.csv", RecordedRun([imu, other]))


def test_a_lab_csv_through_a_map(tmp_path: Path) -> None:
    path = tmp_path / "lab.csv"
    path.write_text("t,gx,gy,gz,ax,ay,az,other\n0.0,1,2,3,4,5,6,9\n0.01,1.5,2,3,4,5,6.5,9\n")
    columns = ("gx", "gy", "gz", "ax", "ay", "az")
    back = read_csv(path, RecordingMap((SensorMap("hand", columns=columns),), time_column="t"))
    np.testing.assert_array_equal(back.stream("hand").values, [[1, 2, 3, 4, 5, 6],
                                                               [1.5, 2, 3, 4, 5, 6.5]])  # fmt: skip
    np.testing.assert_array_equal(back.stream("hand").time, [0.0, 0.01])
    with pytest.raises(InputFileError, match="has no column time; allowed: a header row"):
        read_csv(path)
    bad = RecordingMap((SensorMap("hand", columns=(*columns[:5], "az2")),), time_column="t")
    with pytest.raises(InputFileError, match=r"column az2 \(imu hand\) is not in the header"):
        read_csv(path, bad)
    path.write_text("t,gx,gy,gz,ax,ay,az\n0.0,1,2,3,4,5,6\n0.01,nan,2,3,4,5,6\n")
    with pytest.raises(InputFileError, match="stream hand sample 1 wx is nan"):
        read_csv(path, RecordingMap((SensorMap("hand", columns=columns),), time_column="t"))
