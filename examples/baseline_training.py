"""The training machinery of ``train_baseline.py``: settings, a task's data, the loop, the curve.

Imported by ``examples/train_baseline.py`` (its folder is on ``sys.path`` when it runs).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import torch
from torch import nn

from aaria_pin import DatasetReader
from aaria_pin.apps.bench_tasks.card import split_arguments
from aaria_pin.files.dataset.normalisation import normalised

Batch = dict[str, torch.Tensor]


@dataclass
class Settings:
    """What one training run used (written to ``settings.json``)."""

    task: str
    epochs: int
    seed: int
    tiny: bool
    lr: float = 1e-3
    batch: int = 32
    width: int = 64
    window: int = 0
    patience: int = 15
    weight_decay: float = 0.0
    dropout: float = 0.0
    workers: int = 1
    notes: dict[str, Any] = field(default_factory=dict)


@dataclass
class Data:
    """A task's data set opened for training: the card, the reader, the training statistics.

    ``extra``: another data set whose every run replaces the training split (``--train-data``),
    or None; ``online``: the :class:`~aaria_pin.ml.OnlineRuns` whose fresh arms replace it
    (``--online``), or None; the validation and test splits are the task's always.
    """

    card: dict[str, Any]
    reader: DatasetReader
    stats: dict[str, tuple[np.ndarray, np.ndarray]]
    extra: DatasetReader | None = None
    online: Any = None

    def source(self, split: str) -> tuple[DatasetReader, str | None]:
        """The reader of a split and the split to ask it for (None: all its runs)."""
        if split == "train" and self.extra is not None:
            return self.extra, None
        return self.reader, split

    def split(self, name: str) -> list[int]:
        """The card's runs of one split."""
        return [int(k) for k in self.card["splits"][name]]

    def scaled(self, name: str, array: np.ndarray) -> np.ndarray:
        """An array normalised with the training split's per-channel mean and std, float32."""
        mean, std = self.stats[name]
        return normalised(np.asarray(array, dtype=np.float64), mean, std).astype(np.float32)

    def windows(self, split: str, names: list[str], length: int, stride: int | None) -> Any:
        """Windows of a split (raw; :meth:`scaled` normalises them); length 0: whole runs."""
        reader, asked = self.source(split)
        return reader.windows(
            min(length, reader.samples) if length else reader.samples,
            stride,
            names=names,
            split=asked,
            **split_arguments(self.card),
        )


def tensor_batches(
    x: np.ndarray, y: np.ndarray, size: int, seed: int, epoch: int
) -> Iterator[Batch]:
    """Shuffled batches of per-sample arrays (``x``, ``y``), the order fixed by seed and epoch."""
    order = np.random.default_rng([seed, epoch]).permutation(len(x))
    for first in range(0, len(x), size):
        take = order[first : first + size]
        yield {"x": torch.as_tensor(x[take]), "y": torch.as_tensor(y[take])}


@dataclass
class Curve:
    """Mean loss per epoch (training, validation), the best epoch and the seconds taken."""

    train: list[float] = field(default_factory=list)
    validation: list[float] = field(default_factory=list)
    best_epoch: int = 0
    seconds: float = 0.0


def fit(
    model: nn.Module,
    loss: Callable[[Batch], torch.Tensor],
    batches: Callable[[str, int], Iterable[Batch]],
    s: Settings,
) -> Curve:
    """Adam on the training batches; keep the weights of the best validation loss (early stop)."""
    optimiser = torch.optim.AdamW(model.parameters(), lr=s.lr, weight_decay=s.weight_decay)
    curve, best, started = Curve(), float("inf"), time.perf_counter()
    state = {k: v.clone() for k, v in model.state_dict().items()}
    for epoch in range(s.epochs):
        model.train()
        losses = []
        for batch in batches("train", epoch):
            optimiser.zero_grad()
            value = loss(batch)
            value.backward()
            optimiser.step()
            losses.append(float(value.detach()))
        model.eval()
        with torch.no_grad():
            held = [float(loss(b)) for b in batches("validation", 0)]
        curve.train.append(float(np.mean(losses)))
        curve.validation.append(float(np.mean(held)) if held else float("nan"))
        score = curve.validation[-1] if held else curve.train[-1]
        if score < best:
            best, curve.best_epoch = score, epoch
            state = {k: v.clone() for k, v in model.state_dict().items()}
        elif epoch - curve.best_epoch >= s.patience:
            break
    model.load_state_dict(state)
    curve.seconds = time.perf_counter() - started
    return curve


def plot_curve(curve: Curve, task: str, path: Path) -> None:
    """Training and validation loss per epoch, log scale, the kept epoch marked."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5, 3.2))
    epochs = np.arange(1, len(curve.train) + 1)
    ax.semilogy(epochs, curve.train, label="training")
    ax.semilogy(epochs, curve.validation, label="validation")
    ax.axvline(curve.best_epoch + 1, color="grey", linestyle=":", label="kept")
    ax.set_xlabel("epoch")
    ax.set_ylabel("loss (normalised units)")
    ax.set_title(f"{task}: learned baseline")
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
