"""The structure task's learned baseline: per table row, physics features → the DH table.

Imported by ``train_baseline.py``. Each run is reduced to 7 rows (modules 1–6, the tool) of
:func:`structure_features.run_features` (what the model sees: the encoders' spread, the
rotations between consecutive links' angular velocities, the lever arms between IMUs; no
table entry). One MLP, shared by the rows (a one-hot of the row beside the features),
classifies each row's link type (empty, revolute, prismatic), its alpha among the random arms'
``alpha_choices`` and its theta among ``theta_choices`` (learned on prismatic rows only: a
revolute module's theta is not used), and regresses a and d scaled by their ranges
(``RandomConfig``; d learned on modules only, the tool has none) as a learned blend, per row,
of the features' own estimates of them and a free value. The predicted table keeps
the classes' values, the lengths clipped at 0, the tool row ``[0, a, 0, 0, 1]``.

The training arms come from the task's training split, another data set (``--train-data``)
or fresh arms simulated in the loop (``--online N``: N arms per epoch from
:class:`aaria_pin.ml.OnlineWindows`, featurised in ``DataLoader`` workers).
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Iterator
from typing import Any

import numpy as np
import torch
from baseline_training import Batch, Curve, Data, Settings, fit
from structure_features import CONFIG, ESTIMATES, FEATURES, ROWS, run_features, scaled
from torch import nn

ALPHAS = np.asarray(CONFIG.alpha_choices)
THETAS = np.asarray(CONFIG.theta_choices)


def _unscale(value: np.ndarray, bounds: tuple[float, float]) -> np.ndarray:
    low, high = bounds
    return value * max((high - low) / 2, 1e-6) + (low + high) / 2


def _nearest(values: np.ndarray, choices: np.ndarray) -> np.ndarray:
    return np.abs(values[..., None] - choices).argmin(axis=-1)


def structure_item(run: dict[str, Any], rate: float) -> dict[str, np.ndarray]:
    """One run's features (7 × F) and, when it holds its table, the targets per row."""
    item = {"x": run_features(run["q"], run["imu"], rate), "run": np.asarray(run.get("run", -1))}
    if "senSenDH" in run:
        table = np.asarray(run["senSenDH"], dtype=np.float64)[:ROWS]
        types = np.rint(table[:, 4]).astype(np.int64)
        lengths = np.stack(
            [
                np.r_[scaled(table[:6, 1], CONFIG.a), scaled(table[6:, 1], CONFIG.tool_a)],
                scaled(table[:, 3], CONFIG.d),
            ],
            axis=1,
        )
        item |= {
            "type": types,
            "alpha": _nearest(table[:, 0], ALPHAS),
            "theta": _nearest(table[:, 2], THETAS),
            "lengths": lengths.astype(np.float32),
        }
    return item


class RowNet(nn.Module):
    """Per row: features and the row's one-hot → type, alpha, theta logits, scaled a and d."""

    def __init__(self, width: int, dropout: float) -> None:
        super().__init__()
        self.trunk = nn.Sequential(
            nn.Linear(FEATURES + ROWS, width),
            nn.ReLU(),
            nn.Dropout(dropout),
            nn.Linear(width, width),
            nn.ReLU(),
            nn.Dropout(dropout),
        )
        self.out = nn.Linear(width, 3 + len(ALPHAS) + len(THETAS) + 4)

    def forward(self, x: torch.Tensor) -> dict[str, torch.Tensor]:
        """``x``: (B, 7, F) → logits and scaled lengths per row.

        The lengths blend the features' own estimates of a and d (columns
        :data:`~structure_features.ESTIMATES`) with free values, by a learned gate per row.
        """
        rows = torch.eye(ROWS, dtype=x.dtype).expand(len(x), ROWS, ROWS)
        h = self.out(self.trunk(torch.cat([x, rows], dim=2)))
        cuts = np.cumsum([3, len(ALPHAS), len(THETAS), 2]).tolist()
        gate = torch.sigmoid(h[..., cuts[3] :])
        lengths = gate * x[..., list(ESTIMATES)] + (1 - gate) * h[..., cuts[2] : cuts[3]]
        return {
            "type": h[..., : cuts[0]],
            "alpha": h[..., cuts[0] : cuts[1]],
            "theta": h[..., cuts[1] : cuts[2]],
            "lengths": lengths,
        }


def _masked_ce(logits: torch.Tensor, target: torch.Tensor, mask: torch.Tensor) -> torch.Tensor:
    if not bool(mask.any()):
        return logits.sum() * 0.0
    return nn.functional.cross_entropy(logits[mask], target[mask])


def structure_loss(model: nn.Module, batch: Batch) -> torch.Tensor:
    """Cross-entropies (type; alpha of non-empty rows; theta of prismatic rows) + length MSEs."""
    out = model(batch["x"])
    types = batch["type"]
    filled, prismatic = types > 0, types == 2
    module = torch.zeros_like(filled)
    module[:, :6] = True
    total = nn.functional.cross_entropy(out["type"].reshape(-1, 3), types.reshape(-1))
    total = total + _masked_ce(out["alpha"], batch["alpha"], filled)
    total = total + _masked_ce(out["theta"], batch["theta"], prismatic)
    error = (out["lengths"] - batch["lengths"]) ** 2
    total = total + error[..., 0][filled].mean() + error[..., 1][filled & module].mean()
    return total


def predicted_table(out: dict[str, np.ndarray]) -> np.ndarray:
    """The 8 × 5 table of one run's outputs (rows 1–7; row 8, the base, zeros)."""
    table = np.zeros((8, 5))
    types = out["type"].argmax(axis=-1)
    a = np.r_[
        _unscale(out["lengths"][:6, 0], CONFIG.a), _unscale(out["lengths"][6:, 0], CONFIG.tool_a)
    ]
    d = _unscale(out["lengths"][:, 1], CONFIG.d)
    for row in range(6):
        if types[row]:
            theta = THETAS[out["theta"][row].argmax()] if types[row] == 2 else 0.0
            alpha = ALPHAS[out["alpha"][row].argmax()]
            table[row] = [alpha, max(a[row], 0.0), theta, max(d[row], 0.0), types[row]]
    table[6] = [0.0, max(a[6], 0.0), 0.0, 0.0, 1.0]
    return table


class OnlineItems(torch.utils.data.IterableDataset):  # type: ignore[type-arg]
    """Fresh arms of an :class:`~aaria_pin.ml.OnlineWindows` (whole runs), featurised where read.

    In a ``DataLoader`` worker, the windows give that worker's share of the runs (each run
    simulated once an epoch) and the features are computed there too.
    """

    def __init__(self, windows: Any, rate: float) -> None:
        self.windows = windows
        self.rate = rate

    def __iter__(self) -> Iterator[dict[str, np.ndarray]]:
        for window in self.windows:
            yield structure_item(window, self.rate)

    def __len__(self) -> int:
        return len(self.windows)


def _stack(items: list[dict[str, np.ndarray]]) -> Batch:
    return {k: torch.as_tensor(np.stack([it[k] for it in items])) for k in items[0]}


def _file_items(data: Data, split: str, rate: float) -> list[dict[str, np.ndarray]]:
    reader, asked = data.source(split)
    runs = data.split(split) if asked else reader.split_runs(None).tolist()
    names = ["q", "imu"] + ([] if split == "test" else ["senSenDH"])
    return [structure_item({**reader.run(k, names), "run": k}, rate) for k in runs]


def train_structure(data: Data, s: Settings) -> tuple[Curve, dict[int, np.ndarray]]:
    """Train the row model; predict the test runs' tables."""
    rate = float(data.card["spec"]["rate"])
    model = RowNet(s.width, s.dropout)
    cached: dict[str, list[dict[str, np.ndarray]]] = {
        "validation": _file_items(data, "validation", rate)
    }
    if data.online is None:
        cached["train"] = _file_items(data, "train", rate)
    else:
        windows = data.online.windows(data.online.samples, names=["q", "imu", "senSenDH"])
        stream = OnlineItems(windows, rate)
        s.notes["online_workers"] = s.workers

    def batches(split: str, epoch: int) -> Iterable[Batch]:
        if split == "train" and data.online is not None:
            windows.set_epoch(epoch)
            loader = torch.utils.data.DataLoader(
                stream, batch_size=s.batch, num_workers=s.workers, collate_fn=_stack
            )
            return iter(loader)
        items = cached[split]
        order = np.random.default_rng([s.seed, epoch]).permutation(len(items))
        return (
            _stack([items[i] for i in order[first : first + s.batch]])
            for first in range(0, len(items), s.batch)
        )

    curve = fit(model, lambda batch: structure_loss(model, batch), batches, s)
    model.eval()
    started = time.perf_counter()
    tests = _file_items(data, "test", rate)
    out: dict[int, np.ndarray] = {}
    with torch.no_grad():
        for first in range(0, len(tests), 64):
            batch = _stack(tests[first : first + 64])
            outputs = {k: v.numpy() for k, v in model(batch["x"]).items()}
            for i, run in enumerate(batch["run"].tolist()):
                out[int(run)] = predicted_table({k: v[i] for k, v in outputs.items()})
    s.notes["predict_seconds"] = time.perf_counter() - started  # reading, features, model
    return curve, out
