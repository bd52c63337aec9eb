"""Task 1, ``structure``: the link types and DH table of an unseen random arm from its sensors.

Inputs: the encoders ``q`` and the IMU signals ``imu`` (with the data set's fixed IMU names
and parents); target: the extended DH table ``senSenDH`` (8 × 5: ``[alpha [rad], a [m],
theta [rad], d [m], link type]``, rows 1–6 the modules, 7 the tool, 8 the base). The score is
the link types' accuracy (per module and per arm: all six right) and the tool tip's position
RMS error over the run of the predicted table against the true one, as ``aaria identify``
measures it (:func:`~aaria_pin.apps.identify.geometry_truth.truth_errors`: both tables' forward
kinematics along the run's joint values, so equivalent tables score alike); a table that makes
no arm (a negative length, an unknown link type) counts as infinitely wrong.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin.apps.bench_tasks.metrics import share_summary
from aaria_pin.apps.bench_tasks.task import TaskSpec
from aaria_pin.apps.identify._json import json_number

if TYPE_CHECKING:
    from aaria_pin.files.dataset.reader import DatasetReader

__all__ = ["StructureTask"]


_SPEC = TaskSpec(n_runs=100, seed=2701, duration=10.0, rate=100.0)
"""The task's data set: N random arms, seed, run length [s], rate [Hz], noise."""


@dataclass(frozen=True)
class StructureTask:
    """Task 1 (see the module docstring); its attributes as :class:`~.task.BenchTask`'s."""

    name: str = "structure"
    summary: str = "link types and DH table of an unseen random arm from its encoders and IMUs"
    spec: TaskSpec = _SPEC
    inputs: tuple[str, ...] = ("q", "imu")
    target: str = "senSenDH"
    metric: str = (
        "link-type accuracy (per module, per arm) and the tool tip's position RMS error of the "
        "predicted table over the run [m] (median, 95th percentile, share within 1 mm and 1 cm)"
    )

    def score(self, reader: DatasetReader, predictions: Mapping[int, np.ndarray]) -> dict[str, Any]:
        """Link-type accuracy and tool-tip error of the predicted tables (see the module)."""
        from aaria_pin.apps.identify.benchmark import WITHIN
        from aaria_pin.apps.identify.geometry_truth import truth_errors
        from aaria_pin.errors import InputFileError

        modules: list[bool] = []
        arms: list[bool] = []
        rms: list[float] = []
        per_run: dict[str, Any] = {}
        for run, table in sorted(predictions.items()):
            types = np.asarray(table, dtype=float)[:6, 4]
            if not np.isin(types, (0.0, 1.0, 2.0)).all():
                raise InputFileError(
                    f"run_{run}'s link types (column 5, rows 1-6) are {types.tolist()}; "
                    "allowed: 0, 1 or 2 (empty, revolute, prismatic)",
                    parameter="file",
                    value=run,
                )
            errors = truth_errors(reader.record(run), np.asarray(table, dtype=float))
            if errors is None:
                raise InputFileError(
                    f"run {run} holds no true DH table; allowed: a task's data set (aaria "
                    "bench-task make)",
                    parameter="file",
                    value=run,
                )
            tip = errors.tool_tip_rms if np.isfinite(errors.tool_tip_rms) else np.inf
            modules += errors.link_types_right
            arms.append(all(errors.link_types_right))
            rms.append(tip)
            per_run[f"run_{run}"] = {
                "link_types_right": arms[-1],
                "tool_tip_rms_m": json_number(tip),
            }
        tips = np.asarray(rms)
        return {
            "runs": len(arms),
            "link_type_accuracy": share_summary(modules),
            "link_types_arm_accuracy": share_summary(arms),
            "tool_tip_rms_median_m": json_number(np.median(tips)),
            "tool_tip_rms_p95_m": json_number(np.percentile(tips, 95, method="higher")),
            "tool_tip_rms_max_m": json_number(np.max(tips)),
            "within_1mm_share": share_summary(tips <= WITHIN[0]),
            "within_1cm_share": share_summary(tips <= WITHIN[1]),
            "per_run": per_run,
        }
