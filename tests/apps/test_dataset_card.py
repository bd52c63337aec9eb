"""The data card: counts by structure, failures, units and frames, stored and re-read.

Every number of a card is checked against the file read here with h5py and NumPy (run by run,
with Python's Counter), not through the package's reader.
"""

from __future__ import annotations

import json
import shutil
from collections import Counter
from pathlib import Path

import h5py
import numpy as np
import pytest

from aaria_pin.aaria.presets import get_preset
from aaria_pin.apps.dataset.card import CARD_ATTRIBUTE, MAX_LISTED_STRUCTURES, DatasetCard
from aaria_pin.apps.dataset.card_file import (
    current_card,
    dataset_card,
    read_stored_card,
    store_card,
)
from aaria_pin.apps.dataset.card_text import card_text
from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.apps.dataset.generate import generate_dataset

FIXTURES = Path(__file__).parents[1] / "fixtures" / "v0_1_0"
SHORT = {"duration": 0.1, "rate": 50.0}
LETTERS = {0: "0", 1: "R", 2: "P"}
BOOKKEEPING = ("joint_names", "imu_names", "imu_parents", "urdf", "checksum", "complete", "failed")


def _independent_counts(path: Path) -> tuple[Counter[str], Counter[str]]:
    """Complete runs by structure and by active modules, run by run from the raw file."""
    with h5py.File(path, "r") as handle:
        complete = handle["complete"][()]
        tables = handle["senSenDH"][()]
    structures: Counter[str] = Counter()
    active: Counter[str] = Counter()
    for run in range(len(complete)):
        if complete[run]:
            types = [round(float(tables[run, module, 4])) for module in range(6)]
            structures[" ".join(LETTERS[t] for t in types)] += 1
            active[str(sum(t != 0 for t in types))] += 1
    return structures, active


@pytest.fixture(scope="module")
def random_arms(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("card") / "arms.h5"
    generate_dataset(path, DhDatasetSpec(n_runs=40, seed=11, **SHORT), workers=1)
    return path


@pytest.fixture(scope="module")
def failing(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Random structures with a fixed joint table: every run with a prismatic module fails."""
    joints = np.zeros((8, 5))
    joints[:6] = [0.5, 0.2, 0.0, 1.0, 0.0]  # 0.2 m off a rail of d <= 0.3 m
    path = tmp_path_factory.mktemp("card") / "failing.h5"
    spec = DhDatasetSpec(n_runs=16, seed=2, vary=("structure", "base"), joint_table=joints, **SHORT)
    report = generate_dataset(path, spec, workers=1)
    assert report.failures and report.complete  # some of each
    return path


def test_counts_by_structure_equal_a_count_over_the_stored_tables(random_arms: Path) -> None:
    card = dataset_card(random_arms)
    structures, active = _independent_counts(random_arms)
    assert card.structures == dict(structures)
    assert card.active_modules == dict(active)
    assert sum(card.structures.values()) == card.complete == 40
    counts = list(card.structures.values())
    assert counts == sorted(counts, reverse=True)  # most frequent first
    text = card_text(card)
    for label, count in list(card.structures.items())[:MAX_LISTED_STRUCTURES]:
        assert f"  {label}: {count} run" in text


def test_counts_per_module_equal_a_count_over_the_stored_tables(random_arms: Path) -> None:
    with h5py.File(random_arms, "r") as handle:
        link_types = handle["senSenDH"][()][:, :6, 4]
    card = dataset_card(random_arms)
    for module, counts in enumerate(card.module_link_types):
        column = link_types[:, module].tolist()
        assert counts == {"0": column.count(0.0), "R": column.count(1.0), "P": column.count(2.0)}
    line = "; ".join(
        f"{m + 1}: {c['0']} / {c['R']} / {c['P']}" for m, c in enumerate(card.module_link_types)
    )
    assert f"by module, runs with 0 / R / P: {line}" in card_text(card)


def test_a_long_list_of_structures_is_cut_in_the_text(
    random_arms: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from aaria_pin.apps.dataset import card_text as card_module

    monkeypatch.setattr(card_module, "MAX_LISTED_STRUCTURES", 3)
    card = dataset_card(random_arms)
    rest = sum(list(card.structures.values())[3:])
    text = card_text(card)
    assert f"… {len(card.structures) - 3} more structures, {rest} runs" in text
    assert len(card.structures) > 3  # the card keeps them all


def test_counts_skip_runs_that_are_not_complete(random_arms: Path, tmp_path: Path) -> None:
    path = tmp_path / "partial.h5"
    shutil.copy(random_arms, path)
    with h5py.File(path, "r+") as handle:
        handle["complete"][[0, 5, 6]] = 0  # an interrupted job: no table stored there
    card = dataset_card(path)
    structures, _ = _independent_counts(path)
    assert card.structures == dict(structures)
    assert (card.complete, card.failed, card.not_done) == (37, 0, 3)


def test_failures_are_listed_and_grouped(failing: Path) -> None:
    with h5py.File(failing, "r") as handle:
        failures = json.loads(handle.attrs["failures_json"])
        flagged = np.flatnonzero(handle["failed"][()]).tolist()
    card = dataset_card(failing)
    listed = sorted(run for group in card.failures for run in group.runs)
    assert listed == sorted(int(k) for k in failures) == flagged
    assert card.failed == len(flagged) == sum(group.count for group in card.failures)
    assert len(card.failures) == 1  # one cause; only the numbers differ
    group = card.failures[0]
    assert group.message.startswith("joint oscillation table: row # (prismatic module #)")
    first = min(int(k) for k in failures)
    assert group.example.startswith(f"run {first}: joint oscillation table")
    assert "senSenDH=" in failures[str(first)] and "senSenDH=" not in group.example
    text = card_text(card)
    assert f"{len(flagged)} runs: joint oscillation table" in text
    assert "runs " + ", ".join(map(str, flagged)) in text


def test_failures_of_several_causes_largest_group_first(random_arms: Path, tmp_path: Path) -> None:
    path = tmp_path / "written.h5"
    shutil.copy(random_arms, path)
    messages = {
        "3": "a worker process died during this run",
        "7": "duration is 0.5; allowed: 1 to 2 (senSenDH=[[0.0]] senSenJ=[[1.0]])",
        "9": "duration is 0.25; allowed: 1 to 2 (inputs could not be drawn)",
        "12": "duration is 3; allowed: 1 to 2 (senSenDH=[[0.0]])",
    }
    with h5py.File(path, "r+") as handle:
        handle.attrs["failures_json"] = json.dumps(messages)
        for run in messages:
            handle["complete"][int(run)] = 0
            handle["failed"][int(run)] = 1
    card = dataset_card(path)
    assert [(g.message, g.count, g.runs) for g in card.failures] == [
        ("duration is #; allowed: # to #", 3, (7, 9, 12)),
        ("a worker process died during this run", 1, (3,)),
    ]
    assert card.failures[0].example == "run 7: duration is 0.5; allowed: 1 to 2"
    assert (card.complete, card.failed, card.not_done) == (36, 4, 0)


def test_every_column_has_its_stored_units_and_a_frame(random_arms: Path) -> None:
    card = dataset_card(random_arms)
    columns = {column.name: column for column in card.columns}
    with h5py.File(random_arms, "r") as handle:
        stored = [name for name in handle if name not in BOOKKEEPING]
        assert sorted(columns) == sorted(stored)
        for name in stored:
            column = columns[name]
            assert column.units == handle[name].attrs["units"] and column.units, name
            assert column.units_stored
            assert column.shape == handle[name].shape
            assert column.dtype == str(handle[name].dtype)
    assert columns["base_wrench"].frame == "world-aligned axes, about the base origin"
    assert columns["tool_pose"].frame.startswith("T_world_tool")
    assert columns["base_pose"].frame.startswith("T_world_base")
    assert columns["imu"].frame == "each IMU's own axes"
    assert columns["senSen"].role == "view" and columns["senSenDH"].role == "input"
    inertial = columns["inertial_parameters"]
    assert inertial.role == "input" and inertial.shape[1:] == (7, 10)
    assert inertial.units.startswith("m kg") and "the base body" in inertial.frame
    groups = {g.quantity: g for g in columns["senSen"].column_groups}
    assert [g.count for g in groups.values()] == [1, 6, 42, 42]  # 91 columns
    assert groups["angular velocity"].units == "rad/s"
    assert groups["specific force"].units == "m/s^2"
    assert groups["specific force"].frame == "each IMU's own axes"
    assert (groups["joint values"].first, groups["joint values"].last) == ("q1", "q6")


def test_settings_ranges_and_noise_come_from_the_attributes(failing: Path) -> None:
    with h5py.File(failing, "r") as handle:
        config = json.loads(handle.attrs["config_json"])
        fixed = json.loads(handle.attrs["fixed_tables_json"])
        noise = json.loads(handle.attrs["noise_parameters_json"])
        version = handle.attrs["version"]
        versions = handle.attrs.get("versions_json")
    card = dataset_card(failing)
    assert (card.n_runs, card.samples, card.seed, card.rate, card.duration) == (16, 6, 2, 50, 0.1)
    assert card.vary == ("structure", "base")
    assert set(card.ranges) == {"structure", "base"}  # the joints are fixed: no ranges
    assert card.ranges["structure"]["d"] == config["d"]
    assert card.ranges["base"]["base_frequency"] == config["base_frequency"]
    assert not any(key.startswith("revolute") for part in card.ranges.values() for key in part)
    assert card.fixed_tables["joint_table"] == fixed["joint_table"]
    recorded = {key: card.noise_parameters[key] for key in noise}  # and every term off, at 0
    assert card.noise and recorded == noise and card.noise_model == "ADIS16485"
    assert {v for k, v in card.noise_parameters.items() if k not in noise} <= {0.0, 1.0}
    assert card.written_by == version
    text = card_text(card)
    assert card.command is None  # made from Python, not by a command line
    assert f"command: not recorded (written by aaria_pin {version})" in text
    assert card.versions == (None if versions is None else json.loads(versions))


def test_the_command_and_versions_when_recorded(random_arms: Path, tmp_path: Path) -> None:
    path = tmp_path / "recorded.h5"
    shutil.copy(random_arms, path)
    with h5py.File(path, "r+") as handle:
        handle.attrs["command"] = "aaria dataset -n 40 --seed 11 -o arms.h5"
        handle.attrs["versions_json"] = json.dumps({"aaria_pin": "0.2.0", "pinocchio": "3.4.0"})
    card = dataset_card(path)
    assert card.command == "aaria dataset -n 40 --seed 11 -o arms.h5"
    assert card.versions == {"aaria_pin": "0.2.0", "pinocchio": "3.4.0"}
    text = card_text(card)
    assert "command: aaria dataset -n 40 --seed 11 -o arms.h5" in text
    assert "versions: aaria_pin 0.2.0, pinocchio 3.4.0" in text


def test_card_is_stored_and_read_back(random_arms: Path, tmp_path: Path) -> None:
    path = tmp_path / "stored.h5"
    shutil.copy(random_arms, path)
    with h5py.File(random_arms, "r") as handle:
        before = {name: handle[name][()] for name in ("imu", "senSenDH", "complete")}
    assert read_stored_card(path) is not None  # the engine stored one at the end of the job
    with h5py.File(path, "r+") as handle:
        del handle.attrs[CARD_ATTRIBUTE]
    assert read_stored_card(path) is None
    card = store_card(path)
    with h5py.File(path, "r") as handle:
        # the stored card names no path (a moved file's would be stale); read, it names the file
        assert json.loads(handle.attrs[CARD_ATTRIBUTE]) == {**card.to_dict(), "path": ""}
        for name, array in before.items():  # nothing else changes
            np.testing.assert_array_equal(handle[name][()], array)
    assert read_stored_card(path) == card
    assert DatasetCard.from_dict(json.loads(json.dumps(card.to_dict()))) == card
    with h5py.File(path, "r+") as handle:  # a continued job: the stored card is stale
        handle["complete"][4] = 0
    assert read_stored_card(path) is None
    assert current_card(path).complete == 39


def test_a_stored_card_is_what_the_card_shows(random_arms: Path, tmp_path: Path) -> None:
    path = tmp_path / "marked.h5"
    shutil.copy(random_arms, path)
    store_card(path)
    with h5py.File(path, "r+") as handle:  # a mark only a stored card carries
        data = json.loads(handle.attrs[CARD_ATTRIBUTE])
        data["robot_description"] = "from the stored card"
        handle.attrs[CARD_ATTRIBUTE] = json.dumps(data)
    assert current_card(path).robot_description == "from the stored card"
    moved = tmp_path / "moved.h5"
    path.rename(moved)
    assert current_card(moved).path == str(moved)  # the file as it is named now
    assert current_card(moved).robot_description == "from the stored card"


def test_a_card_is_computed_through_one_open_file(
    random_arms: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "once.h5"
    shutil.copy(random_arms, path)
    with h5py.File(path, "r+") as handle:  # no stored card: current_card computes one
        del handle.attrs[CARD_ATTRIBUTE]
        link_types = handle["senSenDH"][:, :6, 4][handle["complete"][()].astype(bool)]
    opened: list[str] = []
    real_file = h5py.File

    def counted(name: object, *args: object, **kwargs: object) -> h5py.File:
        opened.append(str(name))
        return real_file(name, *args, **kwargs)

    monkeypatch.setattr(h5py, "File", counted)
    card = current_card(path)
    assert opened == [str(path)]
    assert card.complete == len(link_types)
    assert sum(card.structures.values()) == len(link_types)


def test_format_1_fixtures_have_cards() -> None:
    card = dataset_card(FIXTURES / "dh_dataset.h5")
    structures, active = _independent_counts(FIXTURES / "dh_dataset.h5")
    assert (card.format_version, card.written_by, card.kind) == (1, "0.1.0", "dh")
    assert card.structures == dict(structures) and card.active_modules == dict(active)
    assert (card.n_runs, card.complete, card.seed, card.robot) == (3, 3, 5, "aaria-arm")
    columns = {column.name: column for column in card.columns}
    assert not columns["q"].units_stored and columns["q"].units == "rad or m"
    assert columns["senSen"].role == "table of columns"
    assert [g.count for g in columns["senSen"].column_groups] == [1, 6, 42, 42]
    assert "(not stored; the record's convention)" in card_text(card)

    urdf = dataset_card(FIXTURES / "ur5_dataset.h5")
    assert (urdf.kind, urdf.robot, urdf.n_runs, urdf.structures) == ("urdf", "ur5", 2, {})
    assert "structure" not in urdf.ranges
    assert "one robot: ur5" in card_text(urdf)


def test_one_arm_shows_its_fixed_table_and_one_structure(tmp_path: Path) -> None:
    preset = get_preset("aaria-fig2")
    path = tmp_path / "one.h5"
    spec = DhDatasetSpec(
        n_runs=3,
        seed=1,
        vary=("joints",),
        dh_table=preset.table,
        joint_table=preset.joint_table,  # given, but the joints vary: not used
        **SHORT,
    )
    generate_dataset(path, spec, workers=1)
    card = dataset_card(path)
    assert card.robot_description.startswith("one Aaria DH arm")
    assert set(card.fixed_tables) == {"dh_table"}  # the base table: the default, not stored
    np.testing.assert_array_equal(card.fixed_tables["dh_table"], preset.table)
    letters = " ".join(LETTERS[int(t)] for t in preset.table[:6, 4])
    assert card.structures == {letters: 3}
    assert set(card.ranges) == {"joints"}
