"""The learned baselines of the ``inverse-dynamics`` task: a hybrid over the physics, a black box.

Imported by ``examples/train_baseline.py`` (its folder is on ``sys.path`` when it runs).

- :func:`train_hybrid` (``MODELS["inverse-dynamics"]``): the ``rigid-body`` baseline's torques
  (:func:`~aaria_pin.apps.bench_tasks.rigid_body.table_torques`: RNEA of the table's arm along
  the encoders' Savitzky-Golay motion, its window chosen as that baseline chooses it on the
  training runs) plus a per-sample MLP's residual. The MLP reads what the physics does not use:
  the 14 IMUs (angular velocity, specific force, and the angular acceleration from the gyros by
  the same filter), the encoders' raw readings less their filtered value, beside the physics'
  own torques, q, qd, qdd and the DH table; its target is ``tau`` less the rigid-body torques,
  scaled by the training residual's per-joint mean and std. An untrained residual (zero) gives
  the rigid-body baseline back.
- :func:`train_black_box` (``MODELS["inverse-dynamics-black-box"]``): an MLP per sample from what
  the task gives (the encoders' q, qd, qdd by the same filter, sin and cos q, the base pose, the
  base's velocity, acceleration and angular rates from its table, the DH table) to the torques.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any

import numpy as np
import torch
from baseline_training import Batch, Curve, Data, Settings, fit, tensor_batches
from torch import nn

from aaria_pin.apps.bench_tasks.rigid_body import (
    WINDOWS,
    choose_window,
    encoder_motion,
    table_torques,
)
from aaria_pin.core.oscillation import base_motion
from aaria_pin.files.dataset.normalisation import normalised

_BLACK_BOX_INPUTS = ("time", "q_measured", "base_pose", "senSenB", "senSenDH")
"""What the black box reads of a run (the task's inputs, the sample times; not the true q)."""

_HYBRID_INPUTS = ("time", "q_measured", "senSenB", "senSenDH", "imu")
"""What the hybrid reads of a run (the rigid-body baseline's inputs and the IMUs)."""

Features = Callable[[Data, dict[str, Any], int, tuple[str, ...]], np.ndarray]
"""A run's features per sample: (data, run arrays, filter window, joint names) → T × F."""


def _samples(
    data: Data, split: str, inputs: tuple[str, ...], features: Features, window: int
) -> tuple[np.ndarray, np.ndarray]:
    """Per-sample features (N × F) of a split's runs and their torques (N × 6, none: test)."""
    reader, _ = data.source(split)
    names = [*inputs] + ([] if split == "test" else ["tau"])
    ds = data.windows(split, names, 0, None)  # one window: the whole run
    x, y = [], []
    for i in range(len(ds)):
        run = ds[i]
        x.append(features(data, run, window, reader.layout.joint_names))
        if "tau" in run:
            y.append(np.asarray(run["tau"], dtype=np.float64))
    if not x:  # an empty split (a tiny task's validation)
        return np.zeros((0, 1)), np.zeros((0, 6))
    return np.concatenate(x), np.concatenate(y) if y else np.zeros((0, 6))


def _standardised(x: np.ndarray, mean: np.ndarray, std: np.ndarray) -> np.ndarray:
    """Features standardised with the training split's per-feature mean and std, float32."""
    return normalised(np.asarray(x, dtype=np.float64), mean, std).astype(np.float32)


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


def black_box_features(
    data: Data, run: dict[str, Any], window: int, _joints: tuple[str, ...]
) -> np.ndarray:
    """The black box's features per sample, unscaled.

    The encoders' q, qd, qdd (Savitzky-Golay), sin/cos of q, the base pose and motion, the DH
    table repeated.
    """
    readings = np.asarray(run["q_measured"], dtype=np.float64)
    q, qd, qdd = encoder_motion(readings, float(data.card["spec"]["rate"]), window)
    base = base_motion(run["senSenB"], np.asarray(run["time"], dtype=np.float64))
    pose = np.asarray(run["base_pose"], dtype=np.float64).reshape(len(q), -1)
    table = np.broadcast_to(np.asarray(run["senSenDH"], dtype=np.float64).ravel(), (len(q), 40))
    moving = [base.velocity, base.acceleration, base.omega, base.omega_dot]
    return np.concatenate([q, qd, qdd, np.sin(q), np.cos(q), pose, *moving, table], axis=1)


def _neighbours(window: int, samples: int) -> tuple[int, ...]:
    """The filter's window and its two neighbours each side in :data:`WINDOWS` (within a run)."""
    fitting = [w for w in WINDOWS if w <= samples]
    at = fitting.index(window)
    return (window, *fitting[max(at - 2, 0) : at], *fitting[at + 1 : at + 3])


def hybrid_features(
    data: Data, run: dict[str, Any], window: int, joints: tuple[str, ...]
) -> np.ndarray:
    """The hybrid's features per sample, unscaled.

    Columns 0-5: the rigid-body torques of the filter's window; 6: their RMS over the run (the
    run's scale, > 0); then the rigid-body torques of the neighbouring windows less the
    window's, over the run's scale (the filter's bias shows in how they differ), the IMUs'
    readings (14 × 6) and the gyros' rates (14 × 3, the same filter), the encoders' q, qd, qdd
    and readings less q, the DH table repeated.
    """
    rate = float(data.card["spec"]["rate"])
    readings = np.asarray(run["q_measured"], dtype=np.float64)
    torques, *others = table_torques(run, joints, rate, _neighbours(window, len(readings)))
    scale = np.full((len(readings), 1), max(float(np.sqrt(np.mean(torques**2))), 1e-12))
    q, qd, qdd = encoder_motion(readings, rate, window)
    imu = np.asarray(run["imu"], dtype=np.float64).reshape(len(q), -1)
    gyro = np.asarray(run["imu"], dtype=np.float64)[:, :, :3].reshape(len(q), -1)
    omega_dot = encoder_motion(gyro, rate, window)[1]
    table = np.broadcast_to(np.asarray(run["senSenDH"], dtype=np.float64).ravel(), (len(q), 40))
    biases = [(t - torques) / scale for t in others]
    parts = [torques, scale, torques / scale, *biases, imu, omega_dot, q, qd, qdd, readings - q]
    return np.concatenate([*parts, table], axis=1)


def _train_per_sample(
    data: Data, s: Settings, inputs: tuple[str, ...], features: Features, hybrid: bool
) -> tuple[Curve, dict[int, np.ndarray]]:
    """Train a per-sample MLP on the torques (``hybrid``: on their residual over the physics).

    The hybrid's target is the residual over the run's scale (feature 6): its squared error is
    the task's relative RMS squared, so that runs of small torques weigh as much as large ones.
    Its predicted residual stays within the training residuals' range, per joint, and is 0 on a
    joint whose rigid-body torque is 0 over the run (an empty module).
    """
    rate = float(data.card["spec"]["rate"])  # the rigid-body baseline's filter window
    window = choose_window(data.reader.path, data.split("train"), rate, 1)
    s.notes["filter_window"] = window
    x_train, tau_train = _samples(data, "train", inputs, features, window)
    x_held, tau_held = _samples(data, "validation", inputs, features, window)
    x_held = x_held.reshape(-1, x_train.shape[1])  # an empty split: no row of F features

    def physics(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The physics' torques and the run's scale of each sample (black box: 0 and 1)."""
        if hybrid:
            return x[:, :6], x[:, 6:7]
        return np.zeros((len(x), 6)), np.ones((len(x), 1))

    def residual(x: np.ndarray, tau: np.ndarray) -> np.ndarray:
        torques, run_scale = physics(x)
        return (tau - torques) / run_scale

    target = residual(x_train, tau_train)
    shift, scale = (target.mean(axis=0), target.std(axis=0)) if hybrid else data.stats["tau"]
    scale = np.where(scale > 0, scale, 1.0)
    mean, std = x_train.mean(axis=0), x_train.std(axis=0)
    train = (_standardised(x_train, mean, std), ((target - shift) / scale).astype(np.float32))
    bounds = (train[1].min(axis=0), train[1].max(axis=0)) if hybrid else (-np.inf, np.inf)
    held_target = ((residual(x_held, tau_held) - shift) / scale).astype(np.float32)
    held = (_standardised(x_held, mean, std), held_target)
    model = _mlp(train[0].shape[1], s.width, 6, s.dropout)

    def loss(batch: Batch) -> torch.Tensor:
        return nn.functional.mse_loss(model(batch["x"]), batch["y"])

    def batches(split: str, epoch: int) -> Iterable[Batch]:
        x, y = train if split == "train" else held
        return tensor_batches(x, y, s.batch, s.seed, epoch)

    curve = fit(model, loss, batches, s)
    model.eval()
    out = {}
    reader, _ = data.source("test")
    with torch.no_grad():
        for k in data.split("test"):
            x = features(data, reader.run(k, list(inputs)), window, reader.layout.joint_names)
            y = model(torch.as_tensor(_standardised(x, mean, std))).numpy().astype(np.float64)
            torques, run_scale = physics(x)
            y = np.clip(y, *bounds)  # no correction beyond the training residuals' range
            moving = (torques != 0).any(axis=0) if hybrid else True  # an empty module's: 0
            out[k] = torques + np.where(moving, run_scale * (y * scale + shift), 0.0)
    return curve, out


def train_hybrid(data: Data, s: Settings) -> tuple[Curve, dict[int, np.ndarray]]:
    """Train the residual MLP over the rigid-body torques; predict the test runs' torques."""
    return _train_per_sample(data, s, _HYBRID_INPUTS, hybrid_features, hybrid=True)


def train_black_box(data: Data, s: Settings) -> tuple[Curve, dict[int, np.ndarray]]:
    """Train the per-sample MLP on the torques themselves; predict the test runs' torques."""
    return _train_per_sample(data, s, _BLACK_BOX_INPUTS, black_box_features, hybrid=False)
