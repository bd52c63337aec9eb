"""Task 3, ``sensor-to-state``: the joint values from the IMU signals alone.

Input: the IMU signals ``imu`` (``T × S × 6``: specific force [m/s²] and angular rate [rad/s]
of each IMU in its own frame, ADIS16485 noise); target: the joint values ``q`` (``T × 6``,
rad for a revolute module, m for a prismatic one, zeros for an empty one). The score is the RMS
error of each joint column over the samples of the test runs, apart for the runs where that
module is revolute [rad] and prismatic [m] (empty modules are not scored).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin.apps.bench_tasks.metrics import rms_per_joint
from aaria_pin.apps.bench_tasks.task import TaskSpec

if TYPE_CHECKING:
    from aaria_pin.files.dataset.reader import DatasetReader

__all__ = ["SensorToStateTask"]

_KINDS = {1: "revolute_rad", 2: "prismatic_m"}
"""Link type code → the key of its RMS per joint (empty modules, code 0, are not scored)."""


_SPEC = TaskSpec(n_runs=200, seed=2703, duration=5.0, rate=100.0)
"""The task's data set: N random arms, seed, run length [s], rate [Hz], noise."""


@dataclass(frozen=True)
class SensorToStateTask:
    """Task 3 (see the module docstring); its attributes as :class:`~.task.BenchTask`'s."""

    name: str = "sensor-to-state"
    summary: str = "joint values from the IMUs alone"
    spec: TaskSpec = _SPEC
    inputs: tuple[str, ...] = ("imu",)
    target: str = "q"
    metric: str = "RMS error per joint over the test runs, revolute [rad] and prismatic [m] apart"

    def score(self, reader: DatasetReader, predictions: Mapping[int, np.ndarray]) -> dict[str, Any]:
        """RMS error per joint, per joint kind (see the module docstring)."""
        runs = sorted(predictions)
        truths = [reader.run(run, [self.target])[self.target] for run in runs]
        kinds = [reader.labels(run, ["link_types"])["link_types"] for run in runs]
        by_kind = rms_per_joint(truths, [predictions[run] for run in runs], kinds)
        result: dict[str, Any] = {"runs": len(runs)}
        for code, key in _KINDS.items():
            values = by_kind.get(code, [None] * len(truths[0][0]))
            result[f"rms_per_joint_{key}"] = values
            finite = [v for v in values if v is not None]
            result[f"rms_mean_{key}"] = float(np.mean(finite)) if finite else None
        return result
