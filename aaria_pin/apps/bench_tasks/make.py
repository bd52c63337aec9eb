"""Make a benchmark task's folder: its data set (``aaria dataset``) and its card.

The data set is made by :func:`~aaria_pin.apps.dataset.generate.generate_dataset` from the
task's :class:`~.task.TaskSpec` (random Aaria DH arms, sine motion, the spec's encoders), so
``aaria dataset -n N --seed S --duration D --rate R [--no-noise] --dtype T`` (with
``--config FILE`` holding the ``[encoder]`` table of a spec with encoders) makes the same
file. Its splits are by run (:func:`~aaria_pin.files.dataset.windows.split_runs`, seed
:data:`~.task.SPLIT_SEED`, fractions :data:`~.task.FRACTIONS`).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from aaria_pin.apps.bench_tasks.card import DATASET_NAME, PREDICTIONS_FORMAT, write_card
from aaria_pin.apps.bench_tasks.registry import get_task
from aaria_pin.apps.bench_tasks.task import FRACTIONS, SPLIT_SEED

__all__ = ["make_task"]


def make_task(
    name: str,
    directory: str | os.PathLike[str],
    *,
    n_runs: int | None = None,
    duration: float | None = None,
    workers: int | None = None,
    overwrite: bool = False,
    quiet: bool = True,
) -> Path:
    """Write a task's data set and card into a folder (made if missing).

    Args:
        name: the task (:data:`~.registry.TASKS`)
        directory: the folder
        n_runs: fewer (or more) runs than the task's spec: the card is then not ``standard``
        duration: another run length [s] (idem)
        workers: local worker processes (None: the cores this process may use)
        overwrite: replace a data set already there
        quiet: no progress lines

    Returns:
        The card's path.

    Raises:
        ParameterError: an unknown task, a spec whose test split has no run.
        OutputFileError: the folder or its files cannot be written.
    """
    from aaria_pin.apps.dataset.generate import generate_dataset
    from aaria_pin.apps.dataset.job import DatasetJob
    from aaria_pin.apps.dataset.progress import progress_report
    from aaria_pin.errors import OutputFileError, ParameterError
    from aaria_pin.files.dataset.windows import SPLITS, split_runs

    task = get_task(name)
    spec = task.spec.shrunk(n_runs, duration)
    splits = {split: split_runs(spec.n_runs, split, SPLIT_SEED, FRACTIONS) for split in SPLITS}
    if not splits["test"].size:
        raise ParameterError(
            parameter="n_runs", value=spec.n_runs, allowed="enough runs for a test split (>= 3)"
        )
    dataset_spec = spec.dataset_spec()  # checked before anything is made
    folder = Path(directory)
    if (folder / DATASET_NAME).exists() and not overwrite:
        raise OutputFileError(
            f"{folder} holds a task's data set already; allowed: another folder, or overwrite "
            "it (--overwrite)",
            parameter="overwrite",
            value=str(folder),
        )
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputFileError(f"{folder}: cannot be made ({exc})", parameter="path") from None
    generate_dataset(
        folder / DATASET_NAME,
        dataset_spec,
        DatasetJob(workers=workers, overwrite=overwrite, progress=progress_report(quiet, None)),
    )
    card: dict[str, Any] = {
        "task": task.name,
        "summary": task.summary,
        "dataset": DATASET_NAME,
        "spec": spec.to_json(),
        "standard": spec == task.spec,
        "splits": {
            "seed": SPLIT_SEED,
            "fractions": list(FRACTIONS),
            **{split: [int(k) for k in runs] for split, runs in splits.items()},
        },
        "inputs": list(task.inputs),
        "target": task.target,
        "target_shape": _target_shape(folder / DATASET_NAME, int(splits["test"][0]), task.target),
        "metric": task.metric,
        "predictions": PREDICTIONS_FORMAT,
    }
    return write_card(folder, card)


def _target_shape(path: Path, run: int, target: str) -> list[int]:
    """One run's shape of the target array."""
    from aaria_pin.files.dataset.reader import DatasetReader

    with DatasetReader(path) as reader:
        return list(reader.run(run, [target])[target].shape)
