"""Train a small learned baseline of a benchmark task on CPU, predict its test runs, write them.

    python examples/train_baseline.py TASK TASK_DIR -o OUT [--epochs N] [--seed S] [--tiny]
        [--train-data DATASET]

``TASK_DIR`` is a folder of ``aaria bench-task make TASK -o TASK_DIR``. The model (one per task,
:data:`MODELS`) trains on the card's training split, keeps the weights of its best validation
loss (the training loss when the validation split is empty) and predicts the test split, reading
only its inputs. ``OUT`` receives ``predictions.npz`` (for ``aaria bench-task score``),
``curve.png`` (training and validation loss per epoch) and ``settings.json`` (the settings, the
losses, the seconds). Deterministic on CPU for a seed (one thread, deterministic algorithms).

- ``structure``: a 1-D CNN over windows of the encoders and IMUs, pooled over time, gives per
  run a summary; heads classify each column of the DH table that takes few values (alpha, theta,
  link type: the training tables' distinct values) and regress the others (a, d); a test run's
  table is predicted from the mean of its windows' outputs;
- ``inverse-dynamics``: an MLP per sample from q, sin q, cos q, qd, qdd, the base pose and the
  DH table to the torques;
- ``sensor-to-state``: a fully convolutional 1-D CNN from the IMU series to q at every sample
  (trained on windows, applied to whole runs).

Inputs and targets are normalised with the training split's statistics
(``DatasetReader.statistics``); ``--tiny`` is a smoke test (2 epochs, short windows, small
models). ``--train-data`` trains on every run of another data set (``aaria dataset`` with the
task's settings and another seed: fresh arms) instead of the task's training split (its
statistics too); validation and test stay the task's. The training loop is in
``baseline_training.py`` beside this file.
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable, Iterable, Iterator
from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import torch
from baseline_training import Batch, Curve, Data, Settings, fit, plot_curve, tensor_batches
from torch import nn

from aaria_pin import DatasetReader
from aaria_pin.apps.bench_tasks.predictions import write_predictions
from aaria_pin.files.dataset.sampler import RunBlockSampler

# --- structure -----------------------------------------------------------------------------


def _encoder(channels: int, width: int) -> nn.Module:
    """Strided 1-D convolutions pooled (mean and max) over time: ``(B, C, T) -> (B, 2 width)``."""

    class Pool(nn.Module):
        def forward(self, x: torch.Tensor) -> torch.Tensor:
            return torch.cat([x.mean(dim=2), x.amax(dim=2)], dim=1)

    return nn.Sequential(
        nn.Conv1d(channels, width, 7, stride=2, padding=3),
        nn.ReLU(),
        nn.Conv1d(width, width, 7, stride=2, padding=3),
        nn.ReLU(),
        nn.Conv1d(width, width, 5, stride=2, padding=2),
        nn.ReLU(),
        Pool(),
    )


class StructureNet(nn.Module):
    """Summary of a window of encoders and IMUs → DH table class logits and regressed values."""

    def __init__(
        self, channels: int, width: int, n_classes: dict[int, int], n_real: int, dropout: float
    ) -> None:
        super().__init__()
        self.encoder = _encoder(channels, width)
        self.trunk = nn.Sequential(
            nn.Linear(2 * width + channels, 2 * width), nn.ReLU(), nn.Dropout(dropout)
        )
        self.heads = nn.ModuleDict(
            {str(c): nn.Linear(2 * width, 8 * n) for c, n in n_classes.items()}
        )
        self.real = nn.Linear(2 * width, n_real)

    def forward(self, x: torch.Tensor) -> dict[str, torch.Tensor]:
        """Logits (B × 8 × classes) per classified column, ``real``: the regressed entries."""
        spread = torch.log(x.std(dim=2) + 1e-3)  # per channel: a joint's range tells its type
        h = self.trunk(torch.cat([self.encoder(x), spread], dim=1))
        out = {c: head(h).view(len(x), 8, -1) for c, head in self.heads.items()}
        out["real"] = self.real(h)
        return out


@dataclass
class Table:
    """How the DH table (8 × 5) is learned: columns of few values classified, others regressed."""

    classes: dict[int, np.ndarray]  # column -> its distinct training values
    real: list[int]  # regressed columns
    mean: np.ndarray  # of the regressed entries (8 × len(real)), flattened
    std: np.ndarray

    @classmethod
    def from_tables(cls, tables: np.ndarray, max_classes: int = 4) -> Table:
        """From the training tables (N × 8 × 5)."""
        rounded = np.round(tables, 6)
        values = [np.unique(rounded[:, :, c]) for c in range(tables.shape[2])]
        classes = {c: v for c, v in enumerate(values) if len(v) <= max_classes}
        real = [c for c in range(tables.shape[2]) if c not in classes]
        entries = tables[:, :, real].reshape(len(tables), -1)
        std = entries.std(axis=0)
        return cls(classes, real, entries.mean(axis=0), np.where(std > 0, std, 1.0))

    def targets(self, tables: np.ndarray) -> Batch:
        """Class indices per classified column and normalised regressed entries."""
        out = {
            str(c): torch.as_tensor(
                np.abs(np.round(tables[:, :, c], 6)[..., None] - v).argmin(axis=-1)
            )
            for c, v in self.classes.items()
        }
        entries = tables[:, :, self.real].reshape(len(tables), -1)
        out["real"] = torch.as_tensor(((entries - self.mean) / self.std).astype(np.float32))
        return out

    def table(self, outputs: dict[str, np.ndarray]) -> np.ndarray:
        """The predicted table (8 × 5) from mean outputs of one run (logits, normalised values)."""
        table = np.zeros((8, 5))
        for c, v in self.classes.items():
            table[:, c] = v[outputs[str(c)].argmax(axis=-1)]
        real = outputs["real"] * self.std + self.mean
        table[:, self.real] = np.clip(real.reshape(8, len(self.real)), 0.0, None)
        return table


def _structure_windows(
    data: Data, split: str, s: Settings, names: list[str], epoch: int
) -> Iterator[Batch]:
    """Batches of normalised ``q`` + ``imu`` windows ``(B, 90, L)`` (and the tables), run blocks."""
    ds = data.windows(split, names, s.window, max(s.window // 4, 1))
    order = RunBlockSampler.for_windows(ds, seed=s.seed).order(epoch)
    for first in range(0, len(order), s.batch):
        items = [ds[int(i)] for i in order[first : first + s.batch]]
        yield _stack_structure(data, items)


def _stack_structure(data: Data, items: list[dict[str, Any]]) -> Batch:
    q = np.stack([data.scaled("q", it["q"]) for it in items])
    imu = np.stack([data.scaled("imu", it["imu"]) for it in items])
    x = np.concatenate([q, imu.reshape(len(items), imu.shape[1], -1)], axis=2)
    out = {
        "x": torch.as_tensor(x.transpose(0, 2, 1).copy()),
        "run": torch.tensor([int(it["run"]) for it in items]),
    }
    if "senSenDH" in items[0]:
        out["table"] = torch.as_tensor(np.stack([it["senSenDH"] for it in items]))
    return out


def train_structure(data: Data, s: Settings) -> tuple[Curve, dict[int, np.ndarray]]:
    """Train the structure model; predict the test runs' tables."""
    layout = Table.from_tables(data.training_tables())
    s.notes["classified_columns"] = sorted(layout.classes)
    classes = {c: len(v) for c, v in layout.classes.items()}
    model = StructureNet(6 + 14 * 6, s.width, classes, 8 * len(layout.real), s.dropout)
    names = ["q", "imu", "senSenDH"]

    def loss(batch: Batch) -> torch.Tensor:
        out = model(batch["x"])
        target = layout.targets(batch["table"].numpy())
        total = nn.functional.mse_loss(out["real"], target["real"])
        for c in layout.classes:
            logits = out[str(c)]
            total = total + nn.functional.cross_entropy(
                logits.reshape(-1, logits.shape[-1]), target[str(c)].reshape(-1)
            )
        return total

    def batches(split: str, epoch: int) -> Iterable[Batch]:
        return _structure_windows(data, split, s, names, epoch)

    curve = fit(model, loss, batches, s)
    predictions: dict[int, list[dict[str, np.ndarray]]] = {}
    model.eval()
    with torch.no_grad():
        for batch in _structure_windows(data, "test", s, ["q", "imu"], 0):
            out = {k: v.numpy() for k, v in model(batch["x"]).items()}
            for i, run in enumerate(batch["run"].tolist()):
                predictions.setdefault(run, []).append({k: v[i] for k, v in out.items()})
    mean = {
        run: {k: np.mean([o[k] for o in outs], axis=0) for k in outs[0]}
        for run, outs in predictions.items()
    }
    return curve, {run: layout.table(m) for run, m in mean.items()}


# --- inverse dynamics ----------------------------------------------------------------------

_ID_SERIES = ("q", "qd", "qdd", "base_pose")


def _dynamics_samples(data: Data, split: str) -> tuple[np.ndarray, np.ndarray | None]:
    """Per-sample features (N × F) of a split's runs, and their normalised torques (None: test)."""
    names = [*_ID_SERIES, "senSenDH"] + ([] if split == "test" else ["tau"])
    ds = data.windows(split, names, 0, None)  # one window: the whole run
    features, targets = [], []
    for i in range(len(ds)):
        run = ds[i]
        features.append(_dynamics_features(data, run))
        if "tau" in run:
            targets.append(data.scaled("tau", run["tau"]))
    if not features:  # an empty split (a tiny task's validation)
        return np.zeros((0, 1), dtype=np.float32), np.zeros((0, 6), dtype=np.float32)
    return np.concatenate(features), np.concatenate(targets) if targets else None


def _dynamics_features(data: Data, run: dict[str, Any]) -> np.ndarray:
    """One run's features per sample: scaled series, sin/cos of q, the scaled table repeated."""
    q = np.asarray(run["q"], dtype=np.float64)
    series = [data.scaled(name, run[name]).reshape(len(q), -1) for name in _ID_SERIES]
    table = np.broadcast_to(data.scaled("senSenDH", run["senSenDH"]).ravel(), (len(q), 40))
    return np.concatenate([*series, np.sin(q), np.cos(q), table], axis=1).astype(np.float32)


def _mlp(inputs: int, width: int, outputs: int, dropout: float) -> nn.Module:
    return nn.Sequential(
        nn.Linear(inputs, width),
        nn.ReLU(),
        nn.Dropout(dropout),
        nn.Linear(width, width),
        nn.ReLU(),
        nn.Dropout(dropout),
        nn.Linear(width, outputs),
    )


def train_dynamics(data: Data, s: Settings) -> tuple[Curve, dict[int, np.ndarray]]:
    """Train the per-sample MLP; predict the test runs' torques."""
    train = _dynamics_samples(data, "train")
    validation = _dynamics_samples(data, "validation")
    model = _mlp(train[0].shape[1], s.width, 6, s.dropout)

    def loss(batch: Batch) -> torch.Tensor:
        return nn.functional.mse_loss(model(batch["x"]), batch["y"])

    def batches(split: str, epoch: int) -> Iterable[Batch]:
        x, y = train if split == "train" else validation
        return tensor_batches(x, y if y is not None else x, s.batch, s.seed, epoch)

    curve = fit(model, loss, batches, s)
    model.eval()
    out = {}
    with torch.no_grad():
        for k in data.split("test"):
            run = data.reader.run(k, [*_ID_SERIES, "senSenDH"])
            y = model(torch.as_tensor(_dynamics_features(data, run))).numpy()
            out[k] = data.unscaled("tau", y)
    return curve, out


# --- sensor to state -----------------------------------------------------------------------


class StateNet(nn.Module):
    """Fully convolutional: IMU series ``(B, 84, T)`` → q series ``(B, 6, T)`` (same length)."""

    def __init__(self, width: int) -> None:
        super().__init__()
        layers: list[nn.Module] = []
        channels = 14 * 6
        for dilation in (1, 2, 4, 8):
            layers += [
                nn.Conv1d(channels, width, 5, padding=2 * dilation, dilation=dilation),
                nn.ReLU(),
            ]
            channels = width
        layers.append(nn.Conv1d(width, 6, 1))
        self.net = nn.Sequential(*layers)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        """Joint values (normalised) at every sample."""
        return self.net(x)


def _imu_input(data: Data, imu: np.ndarray) -> np.ndarray:
    """Scaled IMU windows ``(B, T, 14, 6)`` as ``(B, 84, T)``."""
    x = data.scaled("imu", imu)
    return x.reshape(*x.shape[:2], -1).transpose(0, 2, 1).copy()


def _state_windows(data: Data, split: str, s: Settings, epoch: int) -> Iterator[Batch]:
    ds = data.windows(split, ["imu", "q"], s.window, max(s.window // 2, 1))
    order = RunBlockSampler.for_windows(ds, seed=s.seed).order(epoch)
    for first in range(0, len(order), s.batch):
        items = [ds[int(i)] for i in order[first : first + s.batch]]
        imu = np.stack([it["imu"] for it in items])
        q = np.stack([data.scaled("q", it["q"]) for it in items])
        yield {
            "x": torch.as_tensor(_imu_input(data, imu)),
            "y": torch.as_tensor(q.transpose(0, 2, 1).copy()),
        }


def train_state(data: Data, s: Settings) -> tuple[Curve, dict[int, np.ndarray]]:
    """Train the convolutional IMU → q model; predict the test runs' joint values."""
    model = StateNet(s.width)

    def loss(batch: Batch) -> torch.Tensor:
        return nn.functional.mse_loss(model(batch["x"]), batch["y"])

    def batches(split: str, epoch: int) -> Iterable[Batch]:
        return _state_windows(data, split, s, epoch)

    curve = fit(model, loss, batches, s)
    model.eval()
    out = {}
    with torch.no_grad():
        for k in data.split("test"):
            imu = data.reader.run(k, ["imu"])["imu"][None]
            y = model(torch.as_tensor(_imu_input(data, imu)))[0].numpy().T
            out[k] = data.unscaled("q", y)
    return curve, out


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
    "structure": Model(
        train_structure, ("q", "imu"), 60, window=256, width=64, weight_decay=1e-2, dropout=0.3
    ),
    "inverse-dynamics": Model(
        train_dynamics,
        ("q", "qd", "qdd", "base_pose", "senSenDH", "tau"),
        40,
        batch=512,
        width=256,
        weight_decay=1e-2,
        dropout=0.3,
    ),
    "sensor-to-state": Model(train_state, ("imu", "q"), 40, window=128, batch=32, width=64),
}
"""The learned baseline of each task."""


def run(
    task: str,
    folder: Path,
    out: Path,
    epochs: int | None,
    seed: int,
    tiny: bool,
    train_data: Path | None = None,
) -> dict[str, Any]:
    """Train the task's model, write predictions, curve and settings to ``out``; the settings."""
    torch.manual_seed(seed)
    torch.use_deterministic_algorithms(True)
    torch.set_num_threads(1)
    spec = MODELS[task]
    s = Settings(
        task,
        epochs or (2 if tiny else spec.epochs),
        seed,
        tiny,
        batch=spec.batch,
        width=16 if tiny else spec.width,
        window=16 if tiny else spec.window,
        weight_decay=spec.weight_decay,
        dropout=spec.dropout,
    )
    card = json.loads((folder / "task.json").read_text())
    out.mkdir(parents=True, exist_ok=True)
    with ExitStack() as files:
        reader = files.enter_context(DatasetReader(folder / card["dataset"]))
        extra = files.enter_context(DatasetReader(train_data)) if train_data else None
        splits = card["splits"]
        stats = (extra or reader).statistics(
            list(spec.normalise),
            split=None if extra else "train",
            seed=splits["seed"],
            fractions=splits["fractions"],
        )
        started = time.perf_counter()
        curve, predictions = spec.train(Data(card, reader, stats, extra), s)
        rest = time.perf_counter() - started - curve.seconds  # reading the splits, predicting
        s.notes["training_arms"] = (
            len(extra.split_runs(None)) if extra else len(card["splits"]["train"])
        )
    write_predictions(out / "predictions.npz", predictions)
    plot_curve(curve, task, out / "curve.png")
    settings = {
        **{k: v for k, v in vars(s).items() if k != "notes"},
        **s.notes,
        "task_dir": str(folder),
        "train_data": str(train_data) if train_data else None,
        "standard": card.get("standard"),
        "torch": torch.__version__,
        "train_seconds": round(curve.seconds, 1),
        "load_and_predict_seconds": round(rest, 2),
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
    parser.add_argument(
        "--train-data",
        type=Path,
        default=None,
        help="train on every run of this data set instead of the task's training split",
    )
    args = parser.parse_args()
    settings = run(
        args.task, args.task_dir, args.output, args.epochs, args.seed, args.tiny, args.train_data
    )
    print(f"{args.task}: {settings['epochs_run']} epochs, {settings['train_seconds']} s")


if __name__ == "__main__":
    main()
