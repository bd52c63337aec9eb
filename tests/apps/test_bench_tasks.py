"""The benchmark tasks end to end on shrunk specs: make, then score the truth and perturbations.

Each task's folder is made with 3 runs of 0.2 s (the test split: one run); scoring its true
targets gives perfect scores, a known perturbation of them the numbers worked out by hand.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from aaria_pin.aaria.presets import get_preset
from aaria_pin.apps.bench_tasks.baselines import run_baseline
from aaria_pin.apps.bench_tasks.card import CARD_NAME, DATASET_NAME, read_card, split_arguments
from aaria_pin.apps.bench_tasks.make import make_task
from aaria_pin.apps.bench_tasks.predictions import write_predictions
from aaria_pin.apps.bench_tasks.registry import TASKS, get_task
from aaria_pin.apps.bench_tasks.scoring import score_lines, score_task
from aaria_pin.apps.identify import identify_kinematics
from aaria_pin.errors import InputFileError, ParameterError
from aaria_pin.files.dataset.reader import DatasetReader
from aaria_pin.files.dataset.windows import split_runs


@pytest.fixture(scope="module")
def folders(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    root = tmp_path_factory.mktemp("bench")
    for name in TASKS:
        make_task(name, root / name, n_runs=3, duration=0.2, workers=1)
    return {name: root / name for name in TASKS}


def _truth(folder: Path, target: str) -> dict[int, np.ndarray]:
    card = json.loads((folder / CARD_NAME).read_text())
    with DatasetReader(folder / DATASET_NAME) as reader:
        return {k: reader.run(k, [target])[target].astype(float) for k in card["splits"]["test"]}


def test_the_card_names_the_splits_and_the_shrunk_spec(folders: dict[str, Path]) -> None:
    card = json.loads((folders["structure"] / CARD_NAME).read_text())
    assert card["task"] == "structure"
    assert card["standard"] is False
    assert card["spec"] == {
        "n_runs": 3, "seed": 2701, "duration": 0.2, "rate": 100.0, "noise": True,
        "dtype": "float32",
    }  # fmt: skip
    assert card["target"] == "senSenDH" and card["target_shape"] == [8, 5]
    assert card["inputs"] == ["q", "imu"]
    for split in ("train", "validation", "test"):
        assert card["splits"][split] == split_runs(3, split, 0, (0.6, 0.2, 0.2)).tolist()
    runs = [k for s in ("train", "validation", "test") for k in card["splits"][s]]
    assert sorted(runs) == [0, 1, 2]
    with DatasetReader(folders["structure"] / DATASET_NAME) as reader:
        assert len(reader) == 3 and reader.samples == 21
        assert reader.attributes["seed"] == 2701


def test_split_arguments_give_the_cards_runs_of_every_split(folders: dict[str, Path]) -> None:
    for folder in folders.values():
        card = read_card(folder)
        split = split_arguments(card)
        assert split == {"seed": 0, "fractions": (0.6, 0.2, 0.2)}
        with DatasetReader(folder / DATASET_NAME) as reader:
            for name in ("train", "validation", "test"):
                assert reader.split_runs(name, **split).tolist() == card["splits"][name]
                windows = reader.windows(None, names=("q",), split=name, **split)
                assert [int(windows[i]["run"]) for i in range(len(windows))] == card["splits"][name]


def test_structure_truth_scores_perfectly_and_a_longer_tool_by_its_length(
    folders: dict[str, Path], tmp_path: Path
) -> None:
    truth = _truth(folders["structure"], "senSenDH")
    write_predictions(tmp_path / "true.npz", truth)
    score = score_task("structure", folders["structure"], tmp_path / "true.npz")
    assert score["link_type_accuracy"] == 1.0 and score["link_types_arm_accuracy"] == 1.0
    assert score["tool_tip_rms_max_m"] == pytest.approx(0.0, abs=1e-9)
    assert score["within_1mm_share"] == 1.0
    longer = {}
    for run, table in truth.items():
        changed = table.copy()
        changed[6, 1] += 0.01  # the tool's length a: the tip moves 1 cm, whatever the joints
        moving = np.flatnonzero(changed[:6, 4] > 0)[0]
        changed[moving, 4] = 3 - changed[moving, 4]  # one revolute ↔ prismatic swap
        longer[run] = changed
    write_predictions(tmp_path / "longer.npz", longer)
    score = score_task("structure", folders["structure"], tmp_path / "longer.npz")
    assert score["link_type_accuracy"] == pytest.approx(5 / 6)
    assert score["link_types_arm_accuracy"] == 0.0
    assert score["runs"] == len(truth)


def test_structure_tool_tip_error_of_a_longer_tool(
    folders: dict[str, Path], tmp_path: Path
) -> None:
    truth = _truth(folders["structure"], "senSenDH")
    longer = {
        run: table + np.where(np.arange(40).reshape(8, 5) == 31, 0.01, 0.0)
        for run, table in truth.items()
    }  # fmt: skip  (row 7 = index 6, column a = 1)
    write_predictions(tmp_path / "longer.npz", longer)
    score = score_task("structure", folders["structure"], tmp_path / "longer.npz")
    assert score["tool_tip_rms_median_m"] == pytest.approx(0.01, rel=1e-6)
    assert score["within_1mm_share"] == 0.0 and score["within_1cm_share"] == 1.0
    assert score["link_type_accuracy"] == 1.0


def test_inverse_dynamics_truth_and_ten_percent_more(
    folders: dict[str, Path], tmp_path: Path
) -> None:
    truth = _truth(folders["inverse-dynamics"], "tau")
    write_predictions(tmp_path / "true.npz", truth)
    score = score_task("inverse-dynamics", folders["inverse-dynamics"], tmp_path / "true.npz")
    assert score["relative_rms_median"] == 0.0 and score["relative_rms_max"] == 0.0
    write_predictions(tmp_path / "more.npz", {k: 1.1 * v for k, v in truth.items()})
    score = score_task("inverse-dynamics", folders["inverse-dynamics"], tmp_path / "more.npz")
    assert score["relative_rms_median"] == pytest.approx(0.1)
    assert score["relative_rms_mean"] == pytest.approx(0.1)
    assert list(score["per_run"]) == [f"run_{k}" for k in truth]


def test_sensor_to_state_truth_and_an_offset(folders: dict[str, Path], tmp_path: Path) -> None:
    folder = folders["sensor-to-state"]
    truth = _truth(folder, "q")
    write_predictions(tmp_path / "true.npz", truth)
    score = score_task("sensor-to-state", folder, tmp_path / "true.npz")
    for key in ("rms_per_joint_revolute_rad", "rms_per_joint_prismatic_m"):
        assert all(v is None or v == 0.0 for v in score[key])
    write_predictions(tmp_path / "off.npz", {k: v + 0.01 for k, v in truth.items()})
    score = score_task("sensor-to-state", folder, tmp_path / "off.npz")
    with DatasetReader(folder / DATASET_NAME) as reader:
        types = np.array([reader.labels(k, ["link_types"])["link_types"] for k in truth])
    for code, key in ((1, "revolute_rad"), (2, "prismatic_m")):
        expected = [0.01 if (types[:, j] == code).any() else None for j in range(6)]
        assert score[f"rms_per_joint_{key}"] == pytest.approx(expected)


def test_baselines_give_the_floors(folders: dict[str, Path], tmp_path: Path) -> None:
    zero = run_baseline("inverse-dynamics", folders["inverse-dynamics"], tmp_path / "z.npz", "zero")
    assert score_task("inverse-dynamics", folders["inverse-dynamics"], zero)[
        "relative_rms_median"
    ] == pytest.approx(1.0)
    physics = run_baseline(
        "inverse-dynamics", folders["inverse-dynamics"], tmp_path / "r.npz", "rigid-body-truth"
    )  # the stored torques are the model's RNEA torques, to float32 storage
    score = score_task("inverse-dynamics", folders["inverse-dynamics"], physics)
    assert score["relative_rms_max"] < 1e-6
    folder = folders["sensor-to-state"]
    card = json.loads((folder / CARD_NAME).read_text())
    with DatasetReader(folder / DATASET_NAME) as reader:
        train = np.concatenate([reader.run(k, ["q"])["q"] for k in card["splits"]["train"]])
    mean = run_baseline("sensor-to-state", folder, tmp_path / "m.npz")
    with np.load(mean) as archive:
        predicted = archive[f"run_{card['splits']['test'][0]}"]
    np.testing.assert_allclose(predicted[5], train.astype(float).mean(axis=0))
    nominal = run_baseline("structure", folders["structure"], tmp_path / "n.npz", "nominal")
    score = score_task("structure", folders["structure"], nominal)
    preset = get_preset("aaria-fig2").table[:6, 4]
    truth = _truth(folders["structure"], "senSenDH")
    expected = np.mean([table[:6, 4] == preset for table in truth.values()])
    assert score["link_type_accuracy"] == pytest.approx(expected)
    assert f"link_type_accuracy: {score['link_type_accuracy']}" in score_lines(score)


def test_refusals(folders: dict[str, Path], tmp_path: Path) -> None:
    with pytest.raises(ParameterError, match="allowed: structure, inverse-dynamics"):
        get_task("segmentation")
    with pytest.raises(ParameterError, match="allowed: 'structure'"):
        score_task("inverse-dynamics", folders["structure"], tmp_path / "p.npz")
    with pytest.raises(InputFileError, match="no such file"):
        score_task("structure", tmp_path, tmp_path / "p.npz")
    with pytest.raises(ParameterError, match="baseline is 'oracle'"):
        run_baseline("structure", folders["structure"], tmp_path / "p.npz", "oracle")
    with pytest.raises(ParameterError, match="test split"):
        make_task("structure", tmp_path / "two", n_runs=2, duration=0.2)
    assert not (tmp_path / "two").exists()


def test_the_identify_baseline_starts_from_a_predictions_file(
    folders: dict[str, Path], tmp_path: Path
) -> None:
    folder = folders["structure"]
    truth = _truth(folder, "senSenDH")
    start = tmp_path / "truth.npz"
    write_predictions(start, truth)
    warm = run_baseline("structure", folder, tmp_path / "w.npz", "identify", start=start)
    with np.load(warm) as archive, DatasetReader(folder / DATASET_NAME) as reader:
        for run, table in truth.items():  # each run's fit started from its own table
            direct = identify_kinematics(reader.record(run), with_truth=False, start=table)
            np.testing.assert_array_equal(archive[f"run_{run}"], direct.table)
    bad = {run: np.where(np.arange(5) == 4, 3.0, table) for run, table in truth.items()}
    write_predictions(tmp_path / "bad.npz", bad)
    run = next(iter(truth))
    with pytest.raises(InputFileError, match=f"run_{run}'s row 1, column 5 .link type. is 3") as e:
        run_baseline("structure", folder, tmp_path / "p.npz", start=tmp_path / "bad.npz")
    assert e.value.parameter == "start"
    write_predictions(tmp_path / "other.npz", {999: truth[run]})
    with pytest.raises(InputFileError, match=f"^start .*has no array run_{run}"):
        run_baseline("structure", folder, tmp_path / "p.npz", start=tmp_path / "other.npz")
    with pytest.raises(ParameterError, match="allowed: with the identify baseline") as e:
        run_baseline("structure", folder, tmp_path / "p.npz", "nominal", start=start)
    assert e.value.parameter == "start" and not (tmp_path / "p.npz").exists()


def test_arms_identify_refuses_are_counted_and_given_the_nominal_table(
    folders: dict[str, Path], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import aaria_pin.apps.identify.geometry as geometry

    def refuse(*_: object, **__: object) -> None:
        raise ParameterError("record is refused; allowed: a test's", parameter="record")

    monkeypatch.setattr(geometry, "identify_kinematics", refuse)  # one process: workers=1
    card = json.loads((folders["structure"] / CARD_NAME).read_text())
    test_runs = card["splits"]["test"]
    with pytest.warns(UserWarning, match=f"refused {len(test_runs)} of {len(test_runs)} test"):
        path = run_baseline("structure", folders["structure"], tmp_path / "p.npz", "identify")
    nominal = np.asarray(get_preset("aaria-fig2").table, dtype=float)
    with np.load(path) as archive:
        for run in test_runs:
            np.testing.assert_array_equal(archive[f"run_{run}"], nominal)
