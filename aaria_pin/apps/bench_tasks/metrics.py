"""The metrics of the benchmark tasks over arrays (independent of files and tasks).

Each takes the truth and the prediction of some runs and returns plain numbers; a value that
is not finite becomes None in JSON (:func:`~aaria_pin.apps.identify._json.json_number`).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from aaria_pin.apps.identify._json import json_number

__all__ = ["relative_rms", "relative_rms_summary", "rms_per_joint", "share_summary"]


def relative_rms(truth: np.ndarray, prediction: np.ndarray) -> float:
    """RMS of the error over RMS of the truth, over every element (inf for a zero truth).

    Every element counts alike: a run's torques [N·m] and forces [N] are pooled as numbers
    (an arm's prismatic forces carry 0 to 100 % of its Σ tau², median 15 % on the standard
    ``inverse-dynamics`` test arms), as a loss over the whole target would pool them.

    Args:
        truth: the true array (a run's ``T × n`` torques)
        prediction: the predicted array of the same shape
    """
    truth = np.asarray(truth, dtype=float)
    error = np.sqrt(np.mean((np.asarray(prediction, dtype=float) - truth) ** 2))
    scale = np.sqrt(np.mean(truth**2))
    if scale == 0.0:
        return 0.0 if error == 0.0 else float("inf")
    return float(error / scale)


def relative_rms_summary(values: Sequence[float]) -> dict[str, Any]:
    """The median, mean and largest of per-run relative RMS errors."""
    array = np.asarray(values, dtype=float)
    return {
        "relative_rms_median": json_number(np.median(array)),
        "relative_rms_mean": json_number(np.mean(array)),
        "relative_rms_max": json_number(np.max(array)),
    }


def rms_per_joint(
    truths: Sequence[np.ndarray], predictions: Sequence[np.ndarray], kinds: Sequence[np.ndarray]
) -> dict[int, list[float | None]]:
    """RMS error per joint column over the runs, apart per joint kind.

    Args:
        truths: per run the true ``T × n`` joint values
        predictions: per run the predicted ones
        kinds: per run the kind code of each of the ``n`` columns (e.g. link types)

    Returns:
        Per kind code found, the RMS error of each column over the samples of the runs where
        the column has that kind (None where it never has).
    """
    columns = np.asarray(truths[0]).shape[1]
    sums: dict[int, np.ndarray] = {}
    counts: dict[int, np.ndarray] = {}
    for truth, prediction, kind in zip(truths, predictions, kinds, strict=True):
        squared = np.sum((np.asarray(prediction, float) - np.asarray(truth, float)) ** 2, axis=0)
        for code in np.unique(kind):
            mask = np.asarray(kind) == code
            sums.setdefault(int(code), np.zeros(columns))[mask] += squared[mask]
            counts.setdefault(int(code), np.zeros(columns))[mask] += len(truth)
    return {
        code: [
            float(np.sqrt(s / c)) if c else None
            for s, c in zip(sums[code], counts[code], strict=True)
        ]
        for code in sorted(sums)
    }


def share_summary(values: Sequence[bool] | np.ndarray) -> float:
    """The share of true values (0 for none)."""
    return float(np.mean(np.asarray(values, dtype=bool))) if len(values) else 0.0
