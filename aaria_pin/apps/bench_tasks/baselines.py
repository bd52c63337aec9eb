"""The baselines of the benchmark tasks: predictions of the test runs written as a task wants.

Per task, by name (:data:`BASELINES`):

- ``structure``: ``identify``, the classical identification (``aaria identify``'s
  :func:`~aaria_pin.apps.identify.geometry.identify_kinematics`, from the run's encoders and
  IMUs) of each test arm, its table as the prediction (an arm it refuses gets the ``nominal``
  table, the refused arms counted in a warning); ``nominal``, the ``aaria-fig2`` preset's
  table for every arm (a floor);
- ``inverse-dynamics``: ``zero`` (no torque: relative RMS 1 exactly), ``train-mean``, each
  joint's mean torque over the training runs, at every sample, ``rigid-body``, the classical
  physics: the RNEA torques of the arm built from its table along the motion differentiated
  from its encoders (:func:`~.rigid_body.rigid_body`, the filter's window chosen on the
  training runs), and ``rigid-body-truth``, the ceiling: the same physics along the hidden true
  motion (:func:`~.rigid_body.rigid_body_truth`; it reads what the task hides);
- ``sensor-to-state``: ``train-mean``, each joint's mean value over the training runs.

Each baseline reads the task's folder only (its card, and of its data set the training runs'
targets or the test runs' inputs), never a test run's target (``rigid-body-truth`` reads the
test runs' true motion: the ceiling, labelled so).
"""

from __future__ import annotations

import functools
import os
import warnings
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.apps.bench_tasks.card import task_card
from aaria_pin.apps.bench_tasks.predictions import write_predictions
from aaria_pin.apps.bench_tasks.rigid_body import rigid_body, rigid_body_truth

__all__ = ["BASELINES", "Baseline", "run_baseline"]

Baseline = Callable[[Path, dict[str, Any], int], dict[int, np.ndarray]]
"""A baseline: (the data set, the task's card, worker processes) → run index → prediction."""

_NOMINAL = "aaria-fig2"
"""The preset whose table the ``nominal`` structure baseline predicts."""


def _nominal_table() -> np.ndarray:
    from aaria_pin.aaria.presets import get_preset

    return np.array(get_preset(_NOMINAL).table, dtype=float)


def _nominal(_dataset: Path, card: dict[str, Any], _workers: int) -> dict[int, np.ndarray]:
    return {int(run): _nominal_table() for run in card["splits"]["test"]}


def _identified_table(task: tuple[str, int, np.ndarray | None]) -> np.ndarray | None:
    """The identified table of one run (None when the identification refuses it).

    ``task``: the data set, the run and its start table (None: a cold start).
    """
    from aaria_pin.apps.identify.geometry import identify_kinematics
    from aaria_pin.errors import AariaError
    from aaria_pin.files.dataset.reader import DatasetReader

    path, run, start = task
    with DatasetReader(path) as reader:
        record = reader.record(run)
    try:
        result = identify_kinematics(record, with_truth=False, start=start)
        return np.asarray(result.table, dtype=float)
    except AariaError:
        return None


def _identify(
    dataset: Path,
    card: dict[str, Any],
    workers: int,
    starts: Mapping[int, np.ndarray] | None = None,
) -> dict[int, np.ndarray]:
    """``aaria identify`` of each test run, from its start table in ``starts`` if given."""
    runs = [int(run) for run in card["splits"]["test"]]
    from aaria_pin.apps.pool import completed

    tasks = [(str(dataset), run, None if starts is None else starts[run]) for run in runs]
    tables = {runs[index]: table for index, table in completed(_identified_table, tasks, workers)}
    refused = sorted(run for run, table in tables.items() if table is None)
    if refused:  # counted and said: the score includes the nominal tables as predictions
        warnings.warn(
            f"identify refused {len(refused)} of {len(runs)} test arms (runs "
            f"{', '.join(map(str, refused))}): the nominal {_NOMINAL} table predicted for "
            "them",
            stacklevel=2,
        )
    return {run: _nominal_table() if table is None else table for run, table in tables.items()}


def _train_mean(dataset: Path, card: dict[str, Any], _workers: int) -> dict[int, np.ndarray]:
    """Each column's mean of the target over the training runs, at every sample of a test run."""
    from aaria_pin.files.dataset.reader import DatasetReader

    target = card["target"]
    with DatasetReader(dataset) as reader:
        train = [
            reader.run(int(k), [target])[target].astype(float) for k in card["splits"]["train"]
        ]
    mean = np.mean(np.concatenate(train), axis=0)
    shape = tuple(card["target_shape"])
    return {int(run): np.broadcast_to(mean, shape).copy() for run in card["splits"]["test"]}


def _zero(_dataset: Path, card: dict[str, Any], _workers: int) -> dict[int, np.ndarray]:
    return {int(run): np.zeros(card["target_shape"]) for run in card["splits"]["test"]}


BASELINES: Mapping[str, Mapping[str, Baseline]] = {
    "structure": {"identify": _identify, "nominal": _nominal},
    "inverse-dynamics": {
        "zero": _zero,
        "train-mean": _train_mean,
        "rigid-body": rigid_body,
        "rigid-body-truth": rigid_body_truth,
    },
    "sensor-to-state": {"train-mean": _train_mean},
}
"""Per task, its baselines by name (the module docstring says what each predicts)."""


def _start_tables(path: str | os.PathLike[str], card: dict[str, Any]) -> dict[int, np.ndarray]:
    """The start tables of the test runs from a predictions file; its errors name ``start``."""
    from aaria_pin.apps.bench_tasks.predictions import read_predictions
    from aaria_pin.apps.identify.geometry_warm import checked_start
    from aaria_pin.errors import AariaError, InputFileError

    runs = [int(run) for run in card["splits"]["test"]]
    try:
        tables = read_predictions(path, runs, tuple(card["target_shape"]))
    except InputFileError as error:
        raise InputFileError(f"start {error}", parameter="start", value=str(path)) from None
    for run, table in tables.items():
        try:
            checked_start(table)
        except AariaError as error:  # "start row 1, ..." → "start run_5: row 1, ..."
            message = f"start {path}: run_{run}'s {str(error).removeprefix('start ')}"
            raise InputFileError(message, parameter="start", value=str(path)) from None
    return tables


def run_baseline(
    name: str,
    directory: str | os.PathLike[str],
    output: str | os.PathLike[str],
    baseline: str | None = None,
    workers: int = 1,
    start: str | os.PathLike[str] | None = None,
) -> Path:
    """Write a baseline's predictions of a task's test runs as a predictions file.

    Args:
        name: the task
        directory: the task's folder (``aaria bench-task make``)
        output: the predictions file to write (``.npz``)
        baseline: the baseline's name (None: the task's first, ``identify`` for ``structure``)
        workers: processes (the ``identify`` baseline's arms in parallel)
        start: a structure predictions file (``run_<k>`` tables, as ``score`` reads it): the
            ``identify`` baseline starts each run's fit from its table (a warm start,
            :mod:`~aaria_pin.apps.identify.geometry_warm`)

    Returns:
        The predictions file's path.

    Raises:
        ParameterError: an unknown task or baseline, a folder of another task, ``start``
            with another baseline than ``identify``.
        InputFileError: no card, a damaged data set, a ``start`` file ``score`` would refuse
            (its ``parameter`` is ``start``).
        OutputFileError: the output cannot be written.
    """
    from aaria_pin.errors import ParameterError

    task, card = task_card(name, directory)
    known = BASELINES[task.name]
    chosen = next(iter(known)) if baseline is None else baseline
    if chosen not in known:
        raise ParameterError(parameter="baseline", value=chosen, allowed=", ".join(known))
    predict = known[chosen]
    if start is not None:
        if predict is not _identify:
            raise ParameterError(
                f"start is given with the {chosen} baseline; allowed: with the identify baseline "
                "of the structure task",
                parameter="start",
                value=str(start),
                allowed="with the identify baseline of the structure task",
            )
        predict = functools.partial(_identify, starts=_start_tables(start, card))
    write_predictions(output, predict(Path(directory) / card["dataset"], card, workers))
    return Path(output)
