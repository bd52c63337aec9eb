"""``aaria check``: exit 0 intact, 1 damage found (one line per damaged run), 2 bad input.

Also the data set readers' doors on a damaged run through the command line: ``torques``,
``identify --run``, ``dataset-stats`` exit 2 with one line, writing nothing.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest
from conftest import run_cli
from dataset_damage import flip_chunk, small_dataset


@pytest.fixture(scope="module")
def made(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return small_dataset(tmp_path_factory.mktemp("cli_check") / "ds.h5")


@pytest.fixture
def damaged(made: Path, tmp_path: Path) -> Path:
    """Run 1's tau bytes flipped inside its stored chunk."""
    path = tmp_path / "bad.h5"
    shutil.copy(made, path)
    flip_chunk(path, "tau", 1)
    return path


def test_intact_exit_0(made: Path) -> None:
    status, out, err = run_cli("check", str(made))
    assert (status, err) == (0, "")
    assert out == f"{made}: data set, 3 of 3 runs complete: all intact\n"


def test_damage_exit_1_one_line_per_run(damaged: Path) -> None:
    status, out, _ = run_cli("check", str(damaged))
    lines = out.splitlines()
    assert status == 1 and lines[0] == f"{damaged}: data set, 3 of 3 runs complete: 1 damaged"
    assert len(lines) == 2 and lines[1].startswith(f"run 1 of {damaged} is damaged (tau")
    status, out, _ = run_cli("check", str(damaged), "--json")
    document = json.loads(out)
    assert status == 1 and [d["run"] for d in document["damaged"]] == [1]


def test_bad_input_exit_2(tmp_path: Path) -> None:
    status, out, err = run_cli("check", str(tmp_path / "missing.h5"))
    assert status == 2 and out == "" and err.startswith("aaria: error: ")
    assert len(err.splitlines()) == 1


@pytest.mark.parametrize(
    "args",
    [
        ("torques", "{file}", "--run", "1", "--plot", "{out}.png"),
        ("identify", "{file}", "--run", "1", "-o", "{out}.csv"),
        ("dataset-stats", "{file}", "--split", "all", "--names", "tau"),
    ],
)
def test_commands_refuse_a_damaged_run_in_one_line(
    damaged: Path, tmp_path: Path, args: tuple[str, ...]
) -> None:
    out = tmp_path / "out"
    argv = [a.format(file=damaged, out=out) for a in args]
    status, stdout, err = run_cli(*argv)
    assert status == 2 and stdout == ""
    assert (
        err == f"aaria: error: run 1 of {damaged} is damaged (tau: Can't synchronously read "
        "data (filter returned failure during read)); allowed: an intact run (aaria check lists "
        "the damaged runs; aaria dataset --resume makes them again)\n"
    )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.h5"]  # nothing written


def test_nan_through_the_command_line(made: Path, tmp_path: Path) -> None:
    path = tmp_path / "nan.h5"
    shutil.copy(made, path)
    with h5py.File(path, "r+") as handle:
        handle["tau"][0, 3, 4] = np.nan
    status, _, err = run_cli("torques", str(path), "--run", "0")
    assert status == 2
    assert (
        err == f"aaria: error: run 0 of {path}: tau has NaN at sample 3, joint 4; "
        "allowed: finite values\n"
    )


def test_dataset_stats_refuses_empty_names(made: Path) -> None:
    status, out, err = run_cli("dataset-stats", str(made), "--names", "")
    assert status == 2 and out == "" and len(err.splitlines()) == 1
    assert err.startswith("aaria: error: --names is ''; allowed: time, q, qd, qdd, tau,")


def test_identify_dataset_without_a_complete_run(made: Path, tmp_path: Path) -> None:
    path = tmp_path / "none.h5"
    shutil.copy(made, path)
    with h5py.File(path, "r+") as handle:
        handle["complete"][...] = 0
    status, out, err = run_cli("identify", "--dataset", str(path))
    assert status == 2 and out == ""
    assert (
        err == f"aaria: error: {path}: no complete run; allowed: a data set with a complete "
        "run (aaria dataset --resume completes it)\n"
    )


def test_a_damaged_mat_run_file_is_damage_exit_1(tmp_path: Path) -> None:
    """Bytes of a .mat's compressed variables that no longer inflate: damage, not bad input."""
    path = tmp_path / "run.mat"
    status, _, _ = run_cli(
        "simulate", "--preset", "aaria-fig2", "--duration", "0.3", "-o", str(path)
    )
    assert status == 0
    data = bytearray(path.read_bytes())
    middle = len(data) // 2
    data[middle : middle + 64] = bytes(b ^ 0xFF for b in data[middle : middle + 64])
    path.write_bytes(bytes(data))
    status, out, err = run_cli("check", str(path))
    assert status == 1 and err == ""
    assert out.splitlines()[0].startswith(f"{path}: run file") and "damaged" in out
