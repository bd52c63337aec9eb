"""The task card: a JSON file beside a task's data set naming what a model reads and predicts.

``aaria bench-task make TASK -o DIR`` writes ``DIR/dataset.h5`` (the data set) and
``DIR/task.json``, whose keys are: ``task`` (its name), ``summary``, ``dataset``
(``"dataset.h5"``, relative to the card), ``spec`` (the data set's ``n_runs``, ``seed``,
``duration`` [s], ``rate`` [Hz], ``noise``, ``dtype`` and, for a task whose runs have
encoders, ``encoder``, the encoder's fields; random Aaria DH arms, sine motion),
``standard`` (false when the spec was shrunk: not the benchmark), ``splits`` (``seed``,
``fractions`` and the run indices of ``train``, ``validation``, ``test``), ``inputs`` (the
fields a model may read), ``target`` (the field it predicts), ``target_shape`` (one run's),
``metric`` (in words) and ``predictions`` (the predictions file's format).
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

from aaria_pin.apps.bench_tasks.registry import get_task
from aaria_pin.apps.bench_tasks.task import BenchTask
from aaria_pin.errors import InputFileError, ParameterError

__all__ = [
    "CARD_NAME",
    "DATASET_NAME",
    "PREDICTIONS_FORMAT",
    "read_card",
    "split_arguments",
    "task_card",
    "write_card",
]

CARD_NAME = "task.json"
"""The card's file name in a task's folder."""

DATASET_NAME = "dataset.h5"
"""The data set's file name in a task's folder."""

PREDICTIONS_FORMAT = (
    "NPZ (numpy.savez), one array run_<k> per test run k (splits.test), of shape target_shape, "
    "finite real numbers, no other array"
)
"""The predictions file's format in one line (:mod:`.predictions` has it in full)."""


def write_card(directory: str | os.PathLike[str], card: dict[str, Any]) -> Path:
    """Write a task's card into its folder (atomically); returns its path.

    Raises:
        OutputFileError: the file cannot be written.
    """
    from aaria_pin.files.paths import write_text_atomic

    path = Path(directory) / CARD_NAME
    write_text_atomic(path, json.dumps(card, indent=2) + "\n")
    return path


def read_card(directory: str | os.PathLike[str]) -> dict[str, Any]:
    """The card of a task's folder.

    Raises:
        InputFileError: no card, or one that is not a task card's JSON.
    """
    path = Path(directory) / CARD_NAME
    try:
        card = json.loads(path.read_text())
    except OSError:
        raise InputFileError(
            f"{path}: no such file; allowed: a folder of aaria bench-task make",
            parameter="directory",
            value=str(directory),
        ) from None
    except ValueError as exc:
        raise InputFileError(
            f"{path}: not JSON ({exc}); allowed: a task card", parameter="directory"
        ) from None
    keys = ("task", "dataset", "splits", "target_shape")
    missing = [key for key in keys if key not in card] if isinstance(card, dict) else list(keys)
    if missing:
        raise InputFileError(
            f"{path}: no key {missing[:1]}; allowed: a task card (aaria bench-task make)",
            parameter="directory",
        )
    return card


def split_arguments(card: dict[str, Any]) -> dict[str, Any]:
    """The split keywords of a task's card, ``{"seed": …, "fractions": …}``, to pass as they are.

    ``reader.windows(200, split="train", **split_arguments(card))`` cuts the task's training
    runs (so do ``reader.split_runs``, ``reader.statistics`` and ``OnlineRuns.windows``): the
    runs of each split are those the card lists (``splits.train`` …).

    Args:
        card: a task card (:func:`read_card`)
    """
    splits = card["splits"]
    return {"seed": int(splits["seed"]), "fractions": tuple(float(f) for f in splits["fractions"])}


def task_card(name: str, directory: str | os.PathLike[str]) -> tuple[BenchTask, dict[str, Any]]:
    """A task and the card of its folder, which must be the same task's, as defined now.

    A folder whose card lists other inputs was made by an older definition of the task (the
    ``inverse-dynamics`` task read the true ``q``, ``qd``, ``qdd`` before it read the
    encoders): it is refused, in one line naming the way out, never scored as the task.

    Raises:
        ParameterError: an unknown task, a folder made for another task.
        InputFileError: no card, not a task card, or the card of an older definition.
    """
    task = get_task(name)
    card = read_card(directory)
    if card["task"] != task.name:
        raise ParameterError(
            f"task is {task.name!r}; allowed: {card['task']!r} (the task of {directory})",
            parameter="task",
            value=task.name,
        )
    if card.get("inputs", list(task.inputs)) != list(task.inputs):
        raise InputFileError(
            f"{Path(directory) / CARD_NAME}: the task's inputs are {card['inputs']}; allowed: "
            f"{list(task.inputs)} (a folder of an older definition of the task: make it again, "
            "aaria bench-task make)",
            parameter="directory",
            value=str(directory),
        )
    return task, card
