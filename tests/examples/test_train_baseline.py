"""examples/train_baseline.py --tiny trains on a 3-run task and writes predictions score accepts."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from aaria_pin.apps.bench_tasks.make import make_task
from aaria_pin.apps.bench_tasks.scoring import score_task

pytest.importorskip("torch")
pytest.importorskip("matplotlib")

SCRIPT = Path(__file__).resolve().parents[2] / "examples" / "train_baseline.py"


def train(task: str, folder: Path, out: Path) -> dict[str, object]:
    subprocess.run(
        [sys.executable, str(SCRIPT), task, str(folder), "-o", str(out), "--tiny"],
        check=True,
        capture_output=True,
    )
    return json.loads((out / "settings.json").read_text())


@pytest.mark.parametrize(
    "task",
    [
        "structure",
        pytest.param("inverse-dynamics", marks=pytest.mark.slow),
        pytest.param("sensor-to-state", marks=pytest.mark.slow),
    ],
)
def test_a_tiny_training_writes_predictions_the_scorer_accepts(tmp_path: Path, task: str) -> None:
    folder = tmp_path / "task"
    card = json.loads(make_task(task, folder, n_runs=3, duration=0.5).read_text())
    settings = train(task, folder, tmp_path / "out")
    assert settings["epochs_run"] == 2 and len(settings["train_loss"]) == 2
    assert all(np.isfinite(settings["train_loss"]))
    assert (tmp_path / "out" / "curve.png").read_bytes()[:4] == b"\x89PNG"
    with np.load(tmp_path / "out" / "predictions.npz") as stored:
        predictions = dict(stored)
    assert sorted(predictions) == sorted(f"run_{k}" for k in card["splits"]["test"])
    assert all(p.shape == tuple(card["target_shape"]) for p in predictions.values())
    score = score_task(task, folder, tmp_path / "out" / "predictions.npz")
    assert score["runs"] == len(card["splits"]["test"]) == 1
    if task == "structure":  # a table making an arm: known types, no negative length
        table = next(iter(predictions.values()))
        assert set(np.unique(table[:, 4])) <= {0.0, 1.0, 2.0}
        assert (table[:, [1, 3]] >= 0).all()
        # the same seed gives the same predictions (deterministic on CPU)
        train(task, folder, tmp_path / "again")
        with np.load(tmp_path / "again" / "predictions.npz") as again:
            assert all(np.array_equal(again[k], v) for k, v in predictions.items())


@pytest.mark.slow
def test_train_data_replaces_the_training_split(tmp_path: Path) -> None:
    folder = tmp_path / "task"
    card = json.loads(make_task("inverse-dynamics", folder, n_runs=3, duration=0.5).read_text())
    extra = tmp_path / "extra.h5"
    subprocess.run(
        [*"aaria dataset -n 4 --seed 5 --duration 0.5 --rate 100 -o".split(), str(extra)],
        check=True,
        capture_output=True,
    )
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
