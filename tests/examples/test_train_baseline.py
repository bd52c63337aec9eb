"""examples/train_baseline.py --tiny trains on a 3-run task and writes predictions score accepts."""

from __future__ import annotations

import json
import subprocess
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from aaria_pin import DatasetReader
from aaria_pin.apps.bench_tasks.make import make_task
from aaria_pin.apps.bench_tasks.registry import get_task
from aaria_pin.apps.bench_tasks.rigid_body import rigid_body
from aaria_pin.apps.bench_tasks.scoring import score_task
from aaria_pin.apps.dataset.generate import generate_dataset

pytest.importorskip("torch")
pytest.importorskip("matplotlib")

SCRIPT = Path(__file__).resolve().parents[2] / "examples" / "train_baseline.py"


def train(task: str, folder: Path, out: Path, *extra: str) -> dict[str, Any]:
    subprocess.run(
        [sys.executable, str(SCRIPT), task, str(folder), "-o", str(out), "--tiny", *extra],
        check=True,
        capture_output=True,
    )
    settings: dict[str, Any] = json.loads((out / "settings.json").read_text())
    return settings


@pytest.mark.parametrize(
    "task",
    [
        "structure",
        pytest.param("inverse-dynamics-black-box", marks=pytest.mark.slow),
        pytest.param("sensor-to-state", marks=pytest.mark.slow),
    ],
)
def test_a_tiny_training_writes_predictions_the_scorer_accepts(tmp_path: Path, task: str) -> None:
    folder = tmp_path / "task"
    name = task.removesuffix("-black-box")  # the task the model is a baseline of
    card = json.loads(make_task(name, folder, n_runs=3, duration=0.5).read_text())
    settings = train(task, folder, tmp_path / "out")
    assert settings["epochs_run"] == 2 and len(settings["train_loss"]) == 2
    assert all(np.isfinite(settings["train_loss"]))
    assert (tmp_path / "out" / "curve.png").read_bytes()[:4] == b"\x89PNG"
    with np.load(tmp_path / "out" / "predictions.npz") as stored:
        predictions = dict(stored)
    assert sorted(predictions) == sorted(f"run_{k}" for k in card["splits"]["test"])
    assert all(p.shape == tuple(card["target_shape"]) for p in predictions.values())
    score = score_task(name, folder, tmp_path / "out" / "predictions.npz")
    assert score["runs"] == len(card["splits"]["test"]) == 1
    if task == "structure":  # a table making an arm: known types, no negative length
        table = next(iter(predictions.values()))
        assert set(np.unique(table[:, 4])) <= {0.0, 1.0, 2.0}
        assert (table[:, [1, 3]] >= 0).all()
        # the same seed gives the same predictions (deterministic on CPU)
        train(task, folder, tmp_path / "again")
        with np.load(tmp_path / "again" / "predictions.npz") as again:
            assert all(np.array_equal(again[k], v) for k, v in predictions.items())


def test_the_hybrid_adds_a_learned_residual_to_the_rigid_body_torques(tmp_path: Path) -> None:
    """A tiny hybrid scores near the rigid-body baseline (its physics), far below the torques."""
    folder = tmp_path / "task"
    card = json.loads(make_task("inverse-dynamics", folder, n_runs=4, duration=0.5).read_text())
    settings = train("inverse-dynamics", folder, tmp_path / "out", "--epochs", "3")
    assert settings["epochs_run"] == 3 and all(np.isfinite(settings["train_loss"]))
    physics = rigid_body(folder / card["dataset"], card, 1)  # the rigid-body baseline's torques
    with np.load(tmp_path / "out" / "predictions.npz") as stored:
        hybrid = {int(k.removeprefix("run_")): stored[k] for k in stored}
    assert sorted(hybrid) == sorted(physics)
    with DatasetReader(folder / card["dataset"]) as reader:
        for k, torques in hybrid.items():
            tau = reader.run(k, ["tau"])["tau"]
            scale = float(np.sqrt(np.mean(tau**2)))
            # the learned residual is a correction of the physics' size, not of the torques'
            assert 0 < np.sqrt(np.mean((torques - physics[k]) ** 2)) < 0.05 * scale
    score = score_task("inverse-dynamics", folder, tmp_path / "out" / "predictions.npz")
    assert score["runs"] == len(card["splits"]["test"])
    assert score["relative_rms_median"] < 0.05  # the black box's is about 1


@pytest.mark.slow
def test_train_data_replaces_the_training_split(tmp_path: Path) -> None:
    folder = tmp_path / "task"
    card = json.loads(make_task("inverse-dynamics", folder, n_runs=3, duration=0.5).read_text())
    extra = tmp_path / "extra.h5"  # the task's settings (its encoders), other arms
    spec = replace(get_task("inverse-dynamics").spec, n_runs=4, seed=5, duration=0.5)
    generate_dataset(extra, spec.dataset_spec(), workers=1)
    out = tmp_path / "out"
    argv = [sys.executable, str(SCRIPT), "inverse-dynamics", str(folder), "-o", str(out)]
    subprocess.run(
        [*argv, "--tiny", "--train-data", str(extra)],
        check=True,
        capture_output=True,
    )
    settings = json.loads((out / "settings.json").read_text())
    assert settings["training_arms"] == 4 != len(card["splits"]["train"])
    score = score_task("inverse-dynamics", folder, out / "predictions.npz")
    assert score["runs"] == len(card["splits"]["test"])


@pytest.mark.parametrize(
    "task", ["structure", pytest.param("sensor-to-state", marks=pytest.mark.slow)]
)
def test_online_trains_on_fresh_arms_in_a_worker(tmp_path: Path, task: str) -> None:
    folder = tmp_path / "task"
    card = json.loads(make_task(task, folder, n_runs=3, duration=0.5).read_text())
    settings = train(task, folder, tmp_path / "out", "--online", "3", "--workers", "1")
    # 2 epochs of 3 arms each, simulated with a seed that is not the task's
    assert settings["training_arms"] == 6 and settings["online"] == 3
    assert settings["online_seed"] != card["spec"]["seed"]
    assert all(np.isfinite(settings["train_loss"]))
    score = score_task(task, folder, tmp_path / "out" / "predictions.npz")
    assert score["runs"] == len(card["splits"]["test"])


def test_structure_features_read_the_arm_from_its_imus(monkeypatch: pytest.MonkeyPatch) -> None:
    """The features' estimates of alpha (revolute rotation) and a match the true table."""
    monkeypatch.syspath_prepend(str(SCRIPT.parent))
    from structure_features import ESTIMATES, run_features

    from aaria_pin.ml import OnlineRuns

    run = OnlineRuns.defaults(1, seed=1, duration=5.0)[0]
    table = run["senSenDH"]
    features = run_features(run["q"], run["imu"], 100.0)
    assert np.array_equal(features[:6, 0] > 0, table[:6, 4] > 0)  # empty modules' IMUs read 0
    # revolute modules after a link (module 1's parent is the base, turned by R_WORLD_DH)
    revolute = [row for row in range(6) if table[row, 4] == 1 and table[:row, 4].any()]
    excited = [row for row in revolute if features[row, 42] * 5 > -2]
    assert excited  # the seed gives some (the check below is not empty)
    for row in excited:
        rotation = features[row, 6:15].reshape(3, 3)  # Kabsch, revolute hypothesis: Rx(alpha)
        assert abs(np.arctan2(rotation[2, 1], rotation[1, 1]) - table[row, 0]) < 0.05
        scaled_a = (table[row, 1] - 0.85) / 0.05  # a in half-ranges of RandomConfig().a
        assert abs(features[row, ESTIMATES[0]] - scaled_a) < 0.2


@pytest.mark.parametrize("flag", ["--online-seed", "--train-data"])
def test_training_on_the_task_arms_is_refused(tmp_path: Path, flag: str) -> None:
    folder = tmp_path / "task"
    card = json.loads(make_task("structure", folder, n_runs=3, duration=0.5).read_text())
    seed = int(card["spec"]["seed"])
    if flag == "--train-data":  # a data set of the task's seed holds its test arms
        value = tmp_path / "same.h5"
        spec = replace(get_task("structure").spec, n_runs=3, duration=0.5)
        generate_dataset(value, spec.dataset_spec(), workers=1)
        extra = [flag, str(value)]
    else:
        extra = ["--online", "3", flag, str(seed)]
    argv = [sys.executable, str(SCRIPT), "structure", str(folder), "-o", str(tmp_path / "out")]
    result = subprocess.run([*argv, "--tiny", *extra], capture_output=True, text=True)
    assert result.returncode == 1
    assert "the task's" in result.stderr and "allowed: " in result.stderr
    assert not (tmp_path / "out").exists()
