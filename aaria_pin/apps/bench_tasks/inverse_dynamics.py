"""Task 2, ``inverse-dynamics``: the joint torques of unseen arms from their motion and structure.

Inputs: the joint values, rates and accelerations ``q``, ``qd``, ``qdd``, the base's pose
``base_pose`` and its motion as the base oscillation table ``senSenB`` (it moves: its motion
enters the dynamics), and the structure ``senSenDH``;
target: the joint torques ``tau`` (``T × 6``, N·m, or N for a prismatic joint; zeros in an
empty module's column). The score is per run the relative RMS error (the RMS of the error over
the RMS of the true torques, over every sample and joint), its median, mean and largest over
the test runs.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin.apps.bench_tasks.metrics import relative_rms, relative_rms_summary
from aaria_pin.apps.bench_tasks.task import TaskSpec
from aaria_pin.apps.identify._json import json_number

if TYPE_CHECKING:
    from aaria_pin.files.dataset.reader import DatasetReader

__all__ = ["InverseDynamicsTask"]


_SPEC = TaskSpec(n_runs=200, seed=2702, duration=5.0, rate=100.0)
"""The task's data set: N random arms, seed, run length [s], rate [Hz], noise."""


@dataclass(frozen=True)
class InverseDynamicsTask:
    """Task 2 (see the module docstring); its attributes as :class:`~.task.BenchTask`'s."""

    name: str = "inverse-dynamics"
    summary: str = "joint torques of unseen arms from their motion and structure"
    spec: TaskSpec = _SPEC
    inputs: tuple[str, ...] = ("q", "qd", "qdd", "base_pose", "senSenB", "senSenDH")
    target: str = "tau"
    metric: str = "relative RMS of the torques per run (RMS of error / RMS of truth): median, mean"

    def score(self, reader: DatasetReader, predictions: Mapping[int, np.ndarray]) -> dict[str, Any]:
        """Per-run relative RMS of the predicted torques, and its median, mean and largest."""
        values = {
            run: relative_rms(reader.run(run, [self.target])[self.target], predicted)
            for run, predicted in sorted(predictions.items())
        }
        return {
            "runs": len(values),
            **relative_rms_summary(list(values.values())),
            "per_run": {f"run_{run}": json_number(value) for run, value in values.items()},
        }
