"""``aaria info --card``: the data card of a data set (DH, URDF, format 1), JSON, run files refused.

The lines printed are checked against the files read here with h5py.
"""

from __future__ import annotations

import json
from collections import Counter
from pathlib import Path

import h5py
import numpy as np
import pytest
from conftest import run_cli

FIXTURES = Path(__file__).parents[1] / "fixtures" / "v0_1_0"
LETTERS = {0: "0", 1: "R", 2: "P"}


@pytest.fixture(scope="module")
def failing(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A DH data set whose runs with a prismatic module fail (a fixed 0.2 m joint swing)."""
    folder = tmp_path_factory.mktemp("info")
    joints = np.zeros((8, 5))
    joints[:6] = [0.5, 0.2, 0.0, 1.0, 0.0]
    np.savetxt(folder / "j.csv", joints, delimiter=",")
    path = folder / "failing.h5"
    code, _, _ = run_cli(
        "dataset", "-n", "12", "--seed", "2", "--duration", "0.1", "--rate", "50",
        "--vary", "structure,base", "--joints", str(folder / "j.csv"), "--workers", "1",
        "--quiet", "-o", str(path),
    )  # fmt: skip
    assert code == 1  # some runs failed
    return path


def test_card_of_a_dh_data_set_with_failures(failing: Path) -> None:
    code, out, _ = run_cli("info", "--card", str(failing))
    assert code == 0, out
    with h5py.File(failing, "r") as handle:
        complete = handle["complete"][()].astype(bool)
        types = np.rint(handle["senSenDH"][()][complete][:, :6, 4]).astype(int)
        failed = sorted(int(k) for k in json.loads(handle.attrs["failures_json"]))
        version = handle.attrs["version"]
        command = handle.attrs.get("command") or f"not recorded (written by aaria_pin {version})"
    structures = Counter(" ".join(LETTERS[t] for t in row) for row in types.tolist())
    assert f"# Data card: {failing}" in out
    assert f"command: {command}\n" in out  # the command line, where the engine records it
    assert "robot: random Aaria DH arms (aaria-arm)" in out
    assert f"runs: 12 ({complete.sum()} complete, {len(failed)} failed, 0 not done)" in out
    assert "samples: 6 a run at 50 Hz (0.1 s), series in float32; seed 2" in out
    assert "vary: structure, base (fixed: joints)" in out
    for label, count in structures.items():  # few: only runs without a prismatic module
        assert f"  {label}: {count} run" in out
    assert f"{len(failed)} runs: joint oscillation table: row # (prismatic module #)" in out
    assert "runs " + ", ".join(map(str, failed)) in out
    for heading in ("## Drawn from", "## Noise", "## Columns", "## Structures", "## Failures"):
        assert heading in out
    assert "base_wrench" in out and "world-aligned axes, about the base origin" in out
    assert "angular velocity: 42 columns (imu_base_wx … imu_link6_b_wz) [rad/s]" in out


def test_card_as_json_is_the_card(failing: Path) -> None:
    from aaria_pin.apps.dataset.card_file import dataset_card

    code, out, _ = run_cli("info", "--card", "--json", str(failing))
    assert code == 0
    assert json.loads(out) == dataset_card(failing).to_dict()


def test_card_of_a_urdf_data_set(tmp_path: Path) -> None:
    path = tmp_path / "ur5.h5"
    code, _, err = run_cli(
        "dataset", "-n", "2", "--robot", "ur5", "--duration", "0.1", "--rate", "50",
        "--seed", "4", "--workers", "1", "--quiet", "-o", str(path),
    )  # fmt: skip
    assert code == 0, err
    code, out, _ = run_cli("info", "--card", str(path))
    assert code == 0
    assert "robot: URDF robot ur5 (source ur5), 6 joints, 14 IMUs, tool tool0, moving base" in out
    assert "vary: joints, base (fixed: structure)" in out
    assert "one robot: ur5" in out
    assert "joint_table" in out and "link_type_probabilities" not in out


def test_card_of_a_format_1_data_set() -> None:
    code, out, _ = run_cli("info", "--card", str(FIXTURES / "dh_dataset.h5"))
    assert code == 0
    assert "format version 1, written by aaria_pin 0.1.0" in out
    assert "command: not recorded (written by aaria_pin 0.1.0)" in out
    assert "runs: 3 (3 complete, 0 failed, 0 not done)" in out
    assert "(not stored; the record's convention)" in out


def test_stored_card_is_printed_when_current(failing: Path, tmp_path: Path) -> None:
    import shutil

    from aaria_pin.apps.dataset.card import CARD_ATTRIBUTE
    from aaria_pin.apps.dataset.card_file import store_card

    path = tmp_path / "stored.h5"
    shutil.copy(failing, path)
    store_card(path)
    with h5py.File(path, "r+") as handle:
        data = json.loads(handle.attrs[CARD_ATTRIBUTE])
        data["robot_description"] = "as stored"
        handle.attrs[CARD_ATTRIBUTE] = json.dumps(data)
    assert "robot: as stored" in run_cli("info", "--card", str(path))[1]
    with h5py.File(path, "r+") as handle:
        handle["failed"][0] = 0  # not what the card counted: computed again
        handle.attrs["failures_json"] = "{}"
    assert "robot: as stored" not in run_cli("info", "--card", str(path))[1]


def test_card_of_a_run_file_is_refused_in_one_line() -> None:
    code, out, err = run_cli("info", "--card", str(FIXTURES / "dh_run.h5"))
    assert code == 2 and not out
    assert err.count("\n") == 1
    assert "--card" in err and "is a run file" in err


def test_plain_info_is_unchanged_by_the_card_option(failing: Path) -> None:
    code, out, _ = run_cli("info", str(failing))
    assert code == 0 and "# Data card" not in out and out.startswith(f"{failing}: data set")
