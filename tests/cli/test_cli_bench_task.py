"""``aaria bench-task``: list, make a shrunk task, score a baseline, refusals (one line, exit 2)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from conftest import run_cli


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("bench") / "torques"
    code, out, err = run_cli(
        "bench-task", "make", "inverse-dynamics", "-o", str(path), "--runs", "3",
        "--duration", "0.2", "--workers", "1",
    )  # fmt: skip
    assert code == 0, err
    assert out.strip() == f"wrote {path / 'task.json'}"
    return path


def test_list_gives_one_line_per_task() -> None:
    code, out, _ = run_cli("bench-task", "list")
    assert code == 0
    names = [line.split()[0] for line in out.splitlines()]
    assert names == ["structure", "inverse-dynamics", "sensor-to-state"]


def test_the_zero_baseline_scores_one(folder: Path, tmp_path: Path) -> None:
    predictions = tmp_path / "zero.npz"
    code, _, err = run_cli(
        "bench-task", "baseline", "inverse-dynamics", str(folder), "-o", str(predictions),
        "--baseline", "zero",
    )  # fmt: skip
    assert code == 0, err
    card = json.loads((folder / "task.json").read_text())
    with np.load(predictions) as archive:
        assert archive.files == [f"run_{k}" for k in card["splits"]["test"]]
    code, out, err = run_cli(
        "bench-task", "score", "inverse-dynamics", str(folder), str(predictions), "--json"
    )
    assert code == 0, err
    score = json.loads(out)
    assert score["relative_rms_median"] == 1.0 and score["standard"] is False
    code, out, _ = run_cli("bench-task", "score", "inverse-dynamics", str(folder), str(predictions))
    assert "relative_rms_mean: 1.0" in out.splitlines()


@pytest.mark.parametrize(
    ("args", "wanted"),
    [
        (("score", "inverse-dynamics", "{folder}", "{bad}"), "has no array run_"),
        (("score", "structure", "{folder}", "{bad}"), "allowed: 'inverse-dynamics'"),
        (("score", "no-such-task", "{folder}", "{bad}"), "task is 'no-such-task'"),
        (("make", "structure", "-o", "{tmp}", "--runs", "2"), "--runs is 2"),
        (("baseline", "inverse-dynamics", "{folder}", "-o", "{tmp}/p.npz", "--baseline", "x"),
         "--baseline is 'x'"),
        (("make", "inverse-dynamics", "-o", "{folder}", "--runs", "3", "--duration", "0.2"),
         "holds a task's data set already; allowed: another folder, or overwrite it (--overwrite)"),
        (("baseline", "inverse-dynamics", "{folder}", "-o", "{tmp}/p.txt", "--baseline", "zero"),
         "is not an .npz file"),
        (("baseline", "inverse-dynamics", "{folder}", "-o", "{tmp}/p.npz", "--baseline", "zero",
          "--start", "{bad}"), "--start is '"),
    ],
)  # fmt: skip
def test_refusals_are_one_line_exit_2(
    folder: Path, tmp_path: Path, args: tuple[str, ...], wanted: str
) -> None:
    bad = tmp_path / "bad.npz"
    np.savez(bad, other=np.zeros(3))
    filled = [a.format(folder=folder, bad=bad, tmp=tmp_path) for a in args]
    code, out, err = run_cli("bench-task", *filled)
    assert code == 2
    assert out == "" and len(err.strip().splitlines()) == 1
    assert err.startswith("aaria: error:") and wanted in err
    assert not (tmp_path / "p.npz").exists()


def test_the_baseline_help_lists_every_baseline_of_the_registry() -> None:
    from aaria_pin.apps.bench_tasks.baselines import BASELINES

    code, out, _ = run_cli("bench-task", "baseline", "--help")
    assert code == 0
    # the help is written by hand (nothing imported at --help): kept in step with the registry
    option = " ".join(out.split()).split("--baseline TEXT")[1].split("--workers")[0]
    for task, baselines in BASELINES.items():
        listed = option.split(f"{task}:")[1].split(";")[0]
        names = [name.split("(")[0].split("[")[0].strip(" ,.") for name in listed.split(",")]
        assert names == list(baselines), (task, names)
