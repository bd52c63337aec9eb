"""Task 2, ``inverse-dynamics``: the joint torques of unseen arms from what they measure.

Inputs: what a real arm measures and knows, never the simulator's truth:

- the encoder readings ``q_measured`` (``T × 6``): a 17-bit absolute encoder (2^17 counts per
  turn, 4.8e-5 rad a count) on a revolute joint, a 10 µm linear scale (1e5 counts per metre)
  on a prismatic one, white noise of 1e-5 rad or m (1σ) before the counting and a zero offset
  drawn per run and joint (1σ 1e-3 rad or m: the residual of a zero calibration), as
  :data:`ENCODER` sets them (:mod:`aaria_pin.core.encoder`);
- the IMU signals ``imu`` (``T × S × 6``, ADIS16485 noise);
- the base's pose ``base_pose`` and its motion as the base oscillation table ``senSenB``: a
  mounted arm knows where it is mounted, and the base's motion is the rig's commanded motion
  (a table), known as the structure is; it enters the dynamics;
- the structure ``senSenDH`` (the DH table, link types included).

Not inputs: the true ``q``, ``qd``, ``qdd`` (no joint rate or acceleration is measured: a model
differentiates the encoders or learns from the IMUs) and the encoders' offsets
``encoder_offset``. So the inputs no longer give the answer by a known formula: the classical
baseline (the rigid-body model of the table, on differentiated encoder readings) has an error
from the counts, the noise and the offsets; the same model on the hidden true motion is the
ceiling (the float32 storage, ~1e-8).

Target: the joint torques ``tau`` (``T × 6``, N·m, or N for a prismatic joint; zeros in an
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
from aaria_pin.core.joint_sensors import EncoderModel

if TYPE_CHECKING:
    from aaria_pin.files.dataset.reader import DatasetReader

__all__ = ["ENCODER", "InverseDynamicsTask"]


ENCODER = EncoderModel(counts_per_revolution=2.0**17, counts_per_metre=1e5, noise=1e-5, offset=1e-3)
"""The task's joint encoders (see the module docstring)."""

_SPEC = TaskSpec(n_runs=200, seed=2702, duration=5.0, rate=100.0, encoder=ENCODER)
"""The task's data set: N random arms, seed, run length [s], rate [Hz], noise, encoders."""


@dataclass(frozen=True)
class InverseDynamicsTask:
    """Task 2 (see the module docstring); its attributes as :class:`~.task.BenchTask`'s."""

    name: str = "inverse-dynamics"
    summary: str = "joint torques of unseen arms from their encoders, IMUs and structure"
    spec: TaskSpec = _SPEC
    inputs: tuple[str, ...] = ("q_measured", "imu", "base_pose", "senSenB", "senSenDH")
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
