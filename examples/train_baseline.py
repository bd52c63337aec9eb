"""Train a small learned baseline of a benchmark task on CPU, predict its test runs, write them.

    python examples/train_baseline.py TASK TASK_DIR -o OUT [--epochs N] [--seed S] [--tiny]
        [--train-data DATASET | --online N [--online-seed S] [--workers W]]

``TASK_DIR`` is a folder of ``aaria bench-task make TASK -o TASK_DIR``. The model (one per task,
:data:`MODELS`) trains on the card's training split, keeps the weights of its best validation
loss (the training loss when the validation split is empty) and predicts the test split, reading
only its inputs. ``OUT`` receives ``predictions.npz`` (for ``aaria bench-task score``),
``curve.png`` (training and validation loss per epoch) and ``settings.json`` (the settings, the
losses, the seconds). Deterministic on CPU for a seed (one thread, deterministic algorithms).

- ``structure``: per table row (modules 1–6, the tool), features the rigid-body physics offers
  (``structure_features.py``: the encoders' spread, rotations between consecutive links'
  angular velocities, lever arms between IMUs) into one MLP shared by the rows that classifies
  the link type, alpha and theta among the random arms' choices and regresses a and d
  (``baseline_structure.py``);
- ``inverse-dynamics``: a hybrid, the ``rigid-body`` baseline's torques plus a per-sample MLP's
  residual from what the physics does not use (the IMUs, the encoders' raw readings, the
  torques of neighbouring filter windows); ``inverse-dynamics-black-box``: an MLP per sample
  from the task's inputs to the torques (``baseline_dynamics.py``; score either with
  ``aaria bench-task score inverse-dynamics``);
- ``sensor-to-state``: a fully convolutional 1-D CNN from the IMU series to q at every sample,
  each joint's value per kind (revolute, prismatic, scaled apart) and its link type
  (``baseline_state.py``; trained on windows, applied to whole runs).

Inputs and targets are normalised with the training split's statistics
(``DatasetReader.statistics``); ``--tiny`` is a smoke test (2 epochs, short windows, small
models). ``--train-data`` trains on every run of another data set (``aaria dataset`` with the
task's settings and another seed: fresh arms) instead of the task's training split (its
statistics too). ``--online N`` trains on N fresh arms per epoch simulated inside the loop
(:class:`aaria_pin.ml.OnlineWindows` of the task's spec with the seed ``--online-seed``,
default :data:`ONLINE_SEED`, not the task's: epoch e takes runs ``k + e·N``, so no arm is seen
twice) in ``--workers`` ``DataLoader`` workers (structure, sensor-to-state). Validation and
test stay the task's. The training loop is in ``baseline_training.py`` beside this file.
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable
from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import torch
from baseline_dynamics import train_black_box, train_hybrid
from baseline_state import train_state
from baseline_structure import train_structure
from baseline_training import Curve, Data, Settings, plot_curve

from aaria_pin import DatasetReader
from aaria_pin.apps.bench_tasks.card import split_arguments
from aaria_pin.apps.bench_tasks.predictions import write_predictions


@dataclass(frozen=True)
class Model:
    """A task's learned baseline: its trainer, the statistics it needs, its default settings."""

    train: Callable[[Data, Settings], tuple[Curve, dict[int, np.ndarray]]]
    normalise: tuple[str, ...]
    epochs: int
    window: int = 0
    batch: int = 32
    width: int = 64
    weight_decay: float = 0.0
    dropout: float = 0.0


MODELS: dict[str, Model] = {
    "structure": Model(train_structure, (), 60, batch=32, width=128, weight_decay=1e-3),
    "inverse-dynamics": Model(
        train_hybrid, (), 40, batch=512, width=256, weight_decay=1e-2, dropout=0.3
    ),
    "inverse-dynamics-black-box": Model(
        train_black_box, ("tau",), 40, batch=512, width=256, weight_decay=1e-2, dropout=0.3
    ),
    "sensor-to-state": Model(train_state, ("imu",), 40, window=128, batch=32, width=64),
}
"""The learned baseline of each task."""


ONLINE_SEED = 9127
"""The seed of the arms ``--online`` simulates (not a task's: the test arms stay unseen)."""


@dataclass(frozen=True)
class Options:
    """How a model is trained (the command line's options, see the module docstring)."""

    epochs: int | None = None
    seed: int = 0
    tiny: bool = False
    train_data: Path | None = None
    online: int = 0
    online_seed: int = ONLINE_SEED
    workers: int = 1


def _online_runs(card: dict[str, Any], o: Options) -> Any:
    """The task's spec with ``o.online`` runs and the online seed (``None`` without --online)."""
    if not o.online:
        return None
    from aaria_pin.apps.dataset.spec_sources import DatasetSources
    from aaria_pin.ml import OnlineRuns

    return OnlineRuns(DatasetSources(**{**card["spec"], "n_runs": o.online, "seed": o.online_seed}))


def _refuse_the_task_arms(card: dict[str, Any], o: Options, extra: DatasetReader | None) -> None:
    """Stop when the extra training arms would be the task's own (its seed: its test arms)."""
    task_seed = int(card["spec"]["seed"])
    if o.online and o.online_seed == task_seed:
        raise SystemExit(
            f"train_baseline.py: --online-seed is {task_seed}, the task's seed (its test arms); "
            "allowed: another seed"
        )
    seed = extra.attributes.get("seed") if extra is not None else None
    if seed is not None and int(seed) == task_seed:
        raise SystemExit(
            f"train_baseline.py: --train-data's seed is {task_seed}, the task's (its test "
            "arms); allowed: a data set of another seed"
        )


def run(task: str, folder: Path, out: Path, o: Options) -> dict[str, Any]:
    """Train the task's model, write predictions, curve and settings to ``out``; the settings."""
    torch.manual_seed(o.seed)
    torch.use_deterministic_algorithms(True)
    torch.set_num_threads(1)
    spec = MODELS[task]
    s = Settings(
        task,
        o.epochs or (2 if o.tiny else spec.epochs),
        o.seed,
        o.tiny,
        batch=spec.batch,
        width=16 if o.tiny else spec.width,
        window=16 if o.tiny else spec.window,
        weight_decay=spec.weight_decay,
        dropout=spec.dropout,
        workers=o.workers,
    )
    card = json.loads((folder / "task.json").read_text())
    with ExitStack() as files:
        reader = files.enter_context(DatasetReader(folder / card["dataset"]))
        extra = files.enter_context(DatasetReader(o.train_data)) if o.train_data else None
        _refuse_the_task_arms(card, o, extra)
        out.mkdir(parents=True, exist_ok=True)
        stats = (
            (extra or reader).statistics(
                list(spec.normalise),
                split=None if extra else "train",
                **split_arguments(card),
            )
            if spec.normalise
            else {}
        )
        online = _online_runs(card, o)
        started = time.perf_counter()
        curve, predictions = spec.train(Data(card, reader, stats, extra, online), s)
        rest = time.perf_counter() - started - curve.seconds  # reading the splits, predicting
        s.notes["training_arms"] = (
            o.online * len(curve.train)
            if online
            else len(extra.split_runs(None))
            if extra
            else len(card["splits"]["train"])
        )
    write_predictions(out / "predictions.npz", predictions)
    plot_curve(curve, task, out / "curve.png")
    settings = {
        **{k: v for k, v in vars(s).items() if k != "notes"},
        **s.notes,
        "task_dir": str(folder),
        "train_data": str(o.train_data) if o.train_data else None,
        "online": o.online,
        "online_seed": o.online_seed if o.online else None,
        "standard": card.get("standard"),
        "torch": torch.__version__,
        "train_seconds": round(curve.seconds, 1),
        "load_and_predict_seconds": round(rest, 2),
        "predict_seconds_per_arm": round(
            s.notes.get("predict_seconds", rest) / len(predictions), 4
        ),
        "epochs_run": len(curve.train),
        "best_epoch": curve.best_epoch + 1,
        "train_loss": curve.train,
        "validation_loss": curve.validation,
    }
    (out / "settings.json").write_text(json.dumps(settings, indent=2) + "\n")
    return settings


def main() -> None:
    """The command line (see the module docstring)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("task", choices=sorted(MODELS))
    parser.add_argument("task_dir", type=Path)
    parser.add_argument("-o", "--output", type=Path, required=True)
    parser.add_argument("--epochs", type=int, default=None)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--tiny", action="store_true", help="smoke test: 2 epochs, tiny model")
    source = parser.add_mutually_exclusive_group()
    source.add_argument(
        "--train-data",
        type=Path,
        default=None,
        help="train on every run of this data set instead of the task's training split",
    )
    source.add_argument(
        "--online",
        type=int,
        default=0,
        metavar="N",
        help="train on N fresh arms per epoch, simulated in the loop (structure, sensor-to-state)",
    )
    parser.add_argument("--online-seed", type=int, default=ONLINE_SEED)
    parser.add_argument("--workers", type=int, default=1, help="DataLoader workers of --online")
    args = parser.parse_args()
    if args.online and args.task.startswith("inverse-dynamics"):
        parser.error("--online trains structure or sensor-to-state")
    options = Options(
        args.epochs,
        args.seed,
        args.tiny,
        args.train_data,
        args.online,
        args.online_seed,
        args.workers,
    )
    settings = run(args.task, args.task_dir, args.output, options)
    print(f"{args.task}: {settings['epochs_run']} epochs, {settings['train_seconds']} s")


if __name__ == "__main__":
    main()
