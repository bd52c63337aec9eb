"""The look-ups of a run record by name (``aaria_pin.core.record``)."""

from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.core.record import ImuMount, RunRecord
from aaria_pin.errors import ParameterError


def small_record() -> RunRecord:
    """Three samples of two joints and two IMUs, every array a known ramp; no views."""
    samples, joints, imus = 3, 2, 2
    ramp = np.arange(samples * imus * 6, dtype=float).reshape(samples, imus, 6)
    zeros = np.zeros((samples, joints))
    return RunRecord(
        time=np.arange(samples) / 10.0,
        joint_names=("shoulder", "elbow"),
        q=zeros,
        qd=zeros,
        qdd=zeros,
        tau=zeros,
        base_pose=np.tile(np.eye(4), (samples, 1, 1)),
        base_wrench=np.zeros((samples, 6)),
        tool_pose=np.tile(np.eye(4), (samples, 1, 1)),
        imu=ramp,
        imu_mounts=(ImuMount("imu_a", "link1", np.eye(4)), ImuMount("imu_b", "link2", np.eye(4))),
        urdf='<robot name="r">\n  <link name="base"/>\n</robot>\n',
    )


def test_lookups_by_name_find_their_columns() -> None:
    record = small_record()
    assert record.joint("elbow") == 1
    np.testing.assert_array_equal(
        record.imu_signals("imu_b"), np.arange(36.0).reshape(3, 2, 6)[:, 1]
    )


@pytest.mark.parametrize(
    ("lookup", "message"),
    [
        ("joint", "joint 'wrist' is not in this run; allowed: shoulder, elbow"),
        ("imu_signals", "IMU 'wrist' is not in this run; allowed: imu_a, imu_b"),
        ("view", "view 'wrist' is not in this run; allowed: none"),
    ],
)
def test_an_unknown_name_lists_the_allowed_ones(lookup: str, message: str) -> None:
    with pytest.raises(ParameterError) as caught:
        getattr(small_record(), lookup)("wrist")
    assert str(caught.value) == message
    assert caught.value.parameter == "name"
