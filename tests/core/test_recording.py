"""A recorded run in memory (``core/recording``): streams checked, an estimator's accessors."""

from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.core.recording import STREAM_COLUMNS, RecordedRun, SensorStream
from aaria_pin.errors import ParameterError


def test_an_imu_and_the_joint_groups_by_joint() -> None:
    imu = SensorStream("tool", "imu", [0.0, 0.005], np.ones((2, 6)), STREAM_COLUMNS["imu"])
    values = np.array([[1.0, 2.0, 10.0, 20.0], [3.0, 4.0, 30.0, 40.0]])
    joints = SensorStream("joints", "joints", [0.001, 0.011], values, ("q:a", "q:b", "tau:a",
                                                                      "tau:b"))  # fmt: skip
    run = RecordedRun([imu, joints])
    assert run.imu_names == ("tool",)
    time, signals = run.imu("tool")
    np.testing.assert_array_equal(time, [0.0, 0.005])
    assert signals.shape == (2, 6) and signals.dtype == np.float64
    states = run.joint_states()
    assert states.names == ("a", "b") and states.qd is None
    np.testing.assert_array_equal(states.q, [[1.0, 2.0], [3.0, 4.0]])
    np.testing.assert_array_equal(states.tau, [[10.0, 20.0], [30.0, 40.0]])
    np.testing.assert_array_equal(states.time, [0.001, 0.011])
    with pytest.raises(ParameterError, match="stream is 'hand'; allowed: tool, joints"):
        run.imu("hand")


def test_a_stream_is_checked_when_made() -> None:
    columns = STREAM_COLUMNS["imu"]
    with pytest.raises(ParameterError, match=r"time at sample 1 is 0\.0 s after 0\.0 s"):
        SensorStream("a", "imu", [0.0, 0.0], np.zeros((2, 6)), columns)
    with pytest.raises(ParameterError, match="sample 0 fz is inf"):
        SensorStream("a", "imu", [0.0], [[0, 0, 0, 0, 0, np.inf]], columns)
    with pytest.raises(ParameterError, match=r"has values \(1, 5\)"):
        SensorStream("a", "imu", [0.0], np.zeros((1, 5)), columns)
    stream = SensorStream("a", "imu", [0.0], np.zeros((1, 6)), columns)
    with pytest.raises(ParameterError, match="stream a is recorded twice"):
        RecordedRun([stream, stream])
