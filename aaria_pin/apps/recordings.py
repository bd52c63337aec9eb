"""A simulated run as a robot would have recorded it, and its export to a recording.

:func:`recorded_from_run` keeps what the robot's sensors measured: each IMU's signals (the
slots that exist), the joint states (``q_measured`` and ``tau_measured`` where the run has
encoders and torque sensors, else the true ``q`` and ``tau``; ``qd`` as computed), and the
base wrench (``base``). :func:`export_run` writes them as a ROS 1 bag, an MCAP file or a ROS 2
sqlite3 file (:func:`~aaria_pin.files.recordings.bag_write.write_bag`), so Foxglove and
PlotJuggler open a simulated run, and :func:`~aaria_pin.files.recordings.bag_read.read_bag`
reads it back to the same arrays.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from aaria_pin.core.record import RunRecord
from aaria_pin.core.recording import STREAM_COLUMNS, RecordedRun, SensorStream

__all__ = ["export_run", "recorded_from_run"]


def recorded_from_run(record: RunRecord) -> RecordedRun:
    """The streams a robot would have recorded of a simulated run (module docstring)."""
    time = np.asarray(record.time, dtype=np.float64)
    streams = [
        SensorStream(mount.name, "imu", time, record.imu[:, slot], STREAM_COLUMNS["imu"])
        for slot, mount in enumerate(record.imu_mounts)
        if mount.parent
    ]
    q = record.tables.get("q_measured", record.q)
    tau = record.tables.get("tau_measured", record.tau)
    joints = record.joint_names
    columns = tuple(f"{group}:{j}" for group in ("q", "qd", "tau") for j in joints)
    values = np.concatenate([q, record.qd, tau], axis=1)
    streams.append(SensorStream("joints", "joints", time, values, columns))
    streams.append(
        SensorStream("base", "wrench", time, record.base_wrench, STREAM_COLUMNS["wrench"])
    )
    return RecordedRun(streams, source=str(record.attributes.get("robot", "")))


def export_run(record: RunRecord, path: str | Path) -> Path:
    """Write a run's recorded streams to ``path`` (``.bag``, ``.mcap``, ``.db3``).

    Raises:
        InputFileError: a suffix that is no recording format, or ``rosbags`` missing.
    """
    from aaria_pin.files.recordings.bag_write import write_bag

    return write_bag(path, recorded_from_run(record))
