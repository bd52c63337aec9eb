"""The sensor-to-state task's learned baseline: the IMU series → q at every sample, per joint kind.

Imported by ``train_baseline.py``. A fully convolutional 1-D CNN (4 dilated convolutions,
receptive field 61 samples) over the 14 IMUs' series (each channel normalised with the
training statistics) feeds two heads:

- per sample and joint, two values: the joint's q were it revolute, and were it prismatic, each
  in its own kind's units (q less the mean, over the std, of the training samples of that kind:
  about 0.5 rad and 0.05 m; one scale for every channel would leave a prismatic q ten times
  smaller than a revolute one, its error lost in the loss);
- per joint, the link type (empty, revolute, prismatic): the task's inputs are the IMUs alone,
  so the type is predicted too, from what does not depend on the IMUs' random mounts
  (:func:`invariants`: an empty module's IMUs read zeros; a prismatic joint leaves the norm of
  the angular rate as it is, a revolute one adds its rate), over the window (the whole run
  when predicting).

The loss is the cross-entropy of the types plus, per kind, the mean squared error of that
kind's value over the joints of that kind only (an empty module's q, zeros, is not a target).
A prediction is the value of the predicted type (zero for an empty module). Trained on windows
(the task's training split, another data set, or fresh arms simulated in the loop:
``--online N``, :class:`aaria_pin.ml.OnlineWindows`), applied to whole runs.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from typing import Any

import numpy as np
import torch
from baseline_training import Batch, Curve, Data, Settings, fit
from torch import nn

from aaria_pin.files.dataset.sampler import RunBlockSampler

JOINTS = 6
KINDS = (1, 2)
"""The link type codes whose q is predicted (revolute, prismatic; empty is 0)."""

_NAMES = ["imu", "q", "link_types"]


class StateNet(nn.Module):
    """Inputs ``(B, 96, T)`` → per-kind q ``(B, 2, 6, T)`` and type logits ``(B, 6, 3)``.

    The type head, a small MLP shared by the modules, reads a module's flag and the log of the
    RMS over the window of its rate-norm difference (:func:`invariants`): over the standard
    data set's 200 arms, 1.1 to 1.3 mrad/s (the gyros' noise) across every prismatic joint,
    18 mrad/s to 1.9 rad/s across a revolute one.
    """

    def __init__(self, width: int) -> None:
        super().__init__()
        layers: list[nn.Module] = []
        channels = 14 * 6 + 12
        for dilation in (1, 2, 4, 8):
            layers += [
                nn.Conv1d(channels, width, 5, padding=2 * dilation, dilation=dilation),
                nn.ReLU(),
            ]
            channels = width
        self.trunk = nn.Sequential(*layers)
        self.values = nn.Conv1d(width, len(KINDS) * JOINTS, 1)
        self.types = nn.Sequential(nn.Linear(2, 16), nn.ReLU(), nn.Linear(16, 3))

    def forward(self, x: torch.Tensor) -> dict[str, torch.Tensor]:
        """Each kind's normalised q at every sample, and each joint's type logits."""
        h = self.trunk(x)
        values = self.values(h).reshape(len(x), len(KINDS), JOINTS, -1)
        invariant = x[:, -12:]  # the flags and the rate-norm differences (:func:`invariants`)
        spread = invariant[:, 6:].square().mean(dim=2).add(1e-8).sqrt()  # (B, 6) [rad/s]
        module = torch.stack([invariant[:, :6, 0], torch.log10(spread + 1e-4)], dim=2)
        return {"q": values, "type": self.types(module)}


def kind_statistics(data: Data) -> np.ndarray:
    """Mean and std of q over the training samples of each kind: ``(2, 2)`` [rad; m]."""
    reader, asked = data.source("train")
    runs = data.split("train") if asked else reader.split_runs(None).tolist()
    q = np.stack([reader.run(k, ["q"])["q"] for k in runs])  # (N, T, 6)
    types = np.stack([reader.labels(k, ["link_types"])["link_types"] for k in runs])
    rows = []
    for kind in KINDS:
        values = q.transpose(0, 2, 1)[types == kind]  # (joints of that kind, T)
        std = float(values.std()) if values.size else 1.0
        rows.append([float(values.mean()) if values.size else 0.0, std if std > 0 else 1.0])
    return np.asarray(rows)


def invariants(imu: np.ndarray) -> np.ndarray:
    """Per module, whether its IMUs read anything and how its angular rate's norm differs.

    ``imu``: ``(B, T, 14, 6)`` raw (slot 0 the base, 2 + 2m and 3 + 2m module m's A and B;
    angular rate [rad/s] first). Returns ``(B, T, 12)``: 6 flags (an empty module's IMUs read
    zeros) and, per module, ``|ω|`` of its IMU A less ``|ω|`` of its parent's IMU B (the
    previous present module's, or the base's) [rad/s]: zero at every sample across a prismatic
    joint (it does not turn the child), the joint rate's share across a revolute one. Rotation
    invariant, so blind to the IMUs' mounts, which every arm draws anew.
    """
    rate = np.linalg.norm(np.asarray(imu, dtype=np.float64)[..., :3], axis=-1)  # (B, T, 14)
    present = np.abs(np.asarray(imu)[:, :, 2::2]).max(axis=(1, 3)) > 0  # (B, 6)
    parent = rate[:, :, 0]
    difference = np.zeros((*rate.shape[:2], 6))
    for m in range(6):
        here = present[:, m, None]
        difference[:, :, m] = np.where(here, rate[:, :, 2 + 2 * m] - parent, 0.0)
        parent = np.where(here, rate[:, :, 3 + 2 * m], parent)
    flags = np.broadcast_to(present[:, None, :], difference.shape)
    return np.concatenate([flags, difference], axis=2)


def _imu_input(data: Data, imu: np.ndarray) -> np.ndarray:
    """Scaled IMU windows ``(B, T, 14, 6)`` and their :func:`invariants` as ``(B, 96, T)``."""
    x = data.scaled("imu", imu)
    x = np.concatenate([x.reshape(*x.shape[:2], -1), invariants(imu)], axis=2)
    return x.transpose(0, 2, 1).astype(np.float32)


def _state_batch(data: Data, items: list[dict[str, Any]], stats: np.ndarray) -> Batch:
    """Scaled IMU windows, each kind's scaled q ``(B, 2, 6, L)`` and the types ``(B, 6)``."""
    imu = np.stack([np.asarray(it["imu"]) for it in items])
    q = np.stack([np.asarray(it["q"], dtype=np.float64) for it in items]).transpose(0, 2, 1)
    scaled = (q[:, None] - stats[None, :, 0, None, None]) / stats[None, :, 1, None, None]
    return {
        "x": torch.as_tensor(_imu_input(data, imu)),
        "q": torch.as_tensor(scaled.astype(np.float32)),
        "type": torch.as_tensor(np.stack([np.asarray(it["link_types"]) for it in items])),
    }


def state_loss(model: nn.Module, batch: Batch) -> torch.Tensor:
    """Type cross-entropy + each kind's q MSE over the joints of that kind (normalised units)."""
    out = model(batch["x"])
    types = batch["type"]
    total = nn.functional.cross_entropy(out["type"].reshape(-1, 3), types.reshape(-1))
    for i, kind in enumerate(KINDS):
        mask = types == kind
        if bool(mask.any()):
            error = (out["q"][:, i] - batch["q"][:, i]) ** 2  # (B, 6, L)
            total = total + error[mask].mean()
    return total


def predicted_q(out: dict[str, np.ndarray], stats: np.ndarray) -> np.ndarray:
    """One run's q ``(T, 6)`` from its outputs: the predicted type's value, 0 for an empty one."""
    types = out["type"].argmax(axis=-1)  # (6,)
    values = out["q"] * stats[:, 1, None, None] + stats[:, 0, None, None]  # (2, 6, T)
    q = np.zeros(values.shape[1:])
    for i, kind in enumerate(KINDS):
        q[types == kind] = values[i][types == kind]
    return q.T


def _state_windows(data: Data, split: str, s: Settings, epoch: int) -> Iterator[list[Any]]:
    if split == "train" and data.online is not None:
        yield from _online_state_windows(data, s, epoch)
        return
    ds = data.windows(split, _NAMES, s.window, max(s.window // 2, 1))
    order = RunBlockSampler.for_windows(ds, seed=s.seed).order(epoch)
    for first in range(0, len(order), s.batch):
        yield [ds[int(i)] for i in order[first : first + s.batch]]


def _online_state_windows(data: Data, s: Settings, epoch: int) -> Iterator[list[Any]]:
    """Windows of the epoch's fresh arms (``--online``), shuffled within a buffer of 8 batches."""
    length = min(s.window, data.online.samples)
    windows = data.online.windows(length, max(length // 2, 1), names=_NAMES)
    windows.set_epoch(epoch)
    loader = torch.utils.data.DataLoader(windows.torch(), batch_size=None, num_workers=s.workers)
    rng = np.random.default_rng([s.seed, epoch])
    buffer: list[dict[str, Any]] = []
    for item in loader:
        buffer.append(item)
        if len(buffer) == 8 * s.batch:
            rng.shuffle(buffer)  # type: ignore[arg-type]
            yield buffer[: s.batch]
            del buffer[: s.batch]
    rng.shuffle(buffer)  # type: ignore[arg-type]
    for first in range(0, len(buffer), s.batch):
        yield buffer[first : first + s.batch]


def train_state(data: Data, s: Settings) -> tuple[Curve, dict[int, np.ndarray]]:
    """Train the convolutional IMU → q model; predict the test runs' joint values."""
    model = StateNet(s.width)
    stats = kind_statistics(data)
    s.notes["q_mean_std_revolute_prismatic"] = stats.round(4).tolist()

    def loss(batch: Batch) -> torch.Tensor:
        return state_loss(model, batch)

    def batches(split: str, epoch: int) -> Iterable[Batch]:
        return (_state_batch(data, items, stats) for items in _state_windows(data, split, s, epoch))

    curve = fit(model, loss, batches, s)
    model.eval()
    out = {}
    with torch.no_grad():
        for k in data.split("test"):
            imu = data.reader.run(k, ["imu"])["imu"][None]
            y = model(torch.as_tensor(_imu_input(data, imu)))
            out[k] = predicted_q({name: v[0].numpy() for name, v in y.items()}, stats)
    return curve, out
