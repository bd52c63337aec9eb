"""Score a predictions file against a task's folder (its card and data set)."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from aaria_pin.apps.bench_tasks.card import task_card
from aaria_pin.apps.bench_tasks.predictions import read_predictions

__all__ = ["score_lines", "score_task"]


def score_task(
    name: str, directory: str | os.PathLike[str], predictions: str | os.PathLike[str]
) -> dict[str, Any]:
    """The task's metric of the predictions of its test runs.

    Args:
        name: the task
        directory: the task's folder (``aaria bench-task make``)
        predictions: the predictions file (:mod:`.predictions`)

    Returns:
        ``task``, ``predictions``, ``standard`` (the task's own spec, not a shrunk one) and the
        task's metric (:meth:`~.task.BenchTask.score`).

    Raises:
        ParameterError: an unknown task, a folder made for another task.
        InputFileError: no card, a damaged data set, a predictions file that is refused.
    """
    from aaria_pin.files.dataset.reader import DatasetReader

    task, card = task_card(name, directory)
    runs = [int(k) for k in card["splits"]["test"]]
    chosen = read_predictions(predictions, runs, tuple(card["target_shape"]))
    with DatasetReader(Path(directory) / card["dataset"]) as reader:
        scores = task.score(reader, chosen)
    return {
        "task": task.name,
        "predictions": str(predictions),
        "standard": bool(card.get("standard", False)),
        **scores,
    }


def score_lines(score: dict[str, Any]) -> list[str]:
    """A score as ``key: value`` lines (lists and numbers as they are; per-run values left out)."""
    return [f"{key}: {value}" for key, value in score.items() if key != "per_run"]
