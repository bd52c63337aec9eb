"""The recorded kind of run file (``files/runfile/_recorded``): written, read, verified."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

from aaria_pin.core.recording import STREAM_COLUMNS, RecordedRun, SensorStream
from aaria_pin.errors import InputFileError, OutputFileError
from aaria_pin.files.runfile import (
    is_recorded_file,
    read_recorded_run,
    read_run,
    recorded_summary,
    write_recorded_run,
)


@pytest.fixture
def run() -> RecordedRun:
    imu = SensorStream("tool", "imu", np.arange(5) * 0.005, np.arange(30.0).reshape(5, 6),
                       STREAM_COLUMNS["imu"], "/imu/tool")  # fmt: skip
    joints = SensorStream("joints", "joints", 0.001 + np.arange(3) * 0.01, np.ones((3, 2)),
                          ("q:a", "qd:a"), "/joint_states")  # fmt: skip
    return RecordedRun([imu, joints], time_origin_ns=1_700_000_000 * 10**9, source="lab.bag")


def test_written_and_read_back_float64_each_stream_its_own_time(
    run: RecordedRun, tmp_path: Path
) -> None:
    path = write_recorded_run(tmp_path / "rec.h5", run, "ros1", "time = 'header'\n")
    with h5py.File(path, "r") as handle:  # the layout, read without our reader
        assert handle.attrs["kind"] == "recorded" and handle.attrs["format"] == "aaria_pin run"
        assert int(handle.attrs["time_origin_ns"]) == run.time_origin_ns
        assert handle["imu0"].dtype == np.float64 and handle["joints0_time"].shape == (3,)
        np.testing.assert_array_equal(handle["joints0_time"][()], 0.001 + np.arange(3) * 0.01)
    back = read_recorded_run(path)
    assert back == RecordedRun(back.streams, run.time_origin_ns, "lab.bag")
    for stream in run.streams:
        got = back.stream(stream.name)
        assert (got.kind, got.columns, got.source) == (stream.kind, stream.columns, stream.source)
        np.testing.assert_array_equal(got.values, stream.values)
        np.testing.assert_array_equal(got.time, stream.time)
    assert is_recorded_file(path) and not is_recorded_file(tmp_path / "none.h5")
    summary, text = recorded_summary(path)
    assert [s["samples"] for s in summary["streams"]] == [5, 3]
    assert text.splitlines()[1].split()[:4] == ["imu", "tool", "5", "samples"]


def test_a_damaged_array_and_a_reader_of_simulated_runs_are_one_line(
    run: RecordedRun, tmp_path: Path
) -> None:
    path = write_recorded_run(tmp_path / "rec.h5", run)
    with pytest.raises(
        InputFileError, match=r"is a recorded run \(measured signals only\)"
    ) as caught:
        read_run(path)
    assert caught.value.parameter == "file"
    with h5py.File(path, "r+") as handle:
        handle["imu0"][0, 0] = 99.0
    with pytest.raises(InputFileError, match="array imu0 is damaged"):
        read_recorded_run(path)
    with pytest.raises(OutputFileError, match=r"is not \.h5 or \.hdf5"):
        write_recorded_run(tmp_path / "rec.mat", run)
