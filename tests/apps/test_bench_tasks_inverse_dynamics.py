"""The ``inverse-dynamics`` task on measured inputs, and its rigid-body baselines.

A shrunk task (6 arms of 0.5 s): its inputs hold no truth; the ceiling (the model along the
hidden true motion) scores at the float32 storage; the classical baseline (the table's model on
differentiated encoder readings) lies between the ceiling and ``zero``; the filter's window is
chosen from the training runs alone; a folder of the older definition is refused.
"""

from __future__ import annotations

import json
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from aaria_pin.apps.bench_tasks import rigid_body as rb
from aaria_pin.apps.bench_tasks.baselines import run_baseline
from aaria_pin.apps.bench_tasks.card import CARD_NAME, DATASET_NAME
from aaria_pin.apps.bench_tasks.inverse_dynamics import ENCODER
from aaria_pin.apps.bench_tasks.make import make_task
from aaria_pin.apps.bench_tasks.metrics import relative_rms
from aaria_pin.apps.bench_tasks.registry import get_task
from aaria_pin.apps.bench_tasks.scoring import score_task
from aaria_pin.errors import InputFileError
from aaria_pin.files.dataset.reader import DatasetReader

_TRUTH = {"q", "qd", "qdd", "tau", "encoder_offset"}
"""What the simulator knows and a real arm does not measure."""


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("id") / "torques"
    make_task("inverse-dynamics", path, n_runs=6, duration=0.5, workers=1)
    return path


def _card(folder: Path) -> dict[str, Any]:
    card: dict[str, Any] = json.loads((folder / CARD_NAME).read_text())
    return card


def test_the_inputs_are_measurements_not_the_truth(folder: Path) -> None:
    task = get_task("inverse-dynamics")
    assert not _TRUTH & set(task.inputs)
    assert {"q_measured", "imu", "senSenDH"} <= set(task.inputs)
    card = _card(folder)
    assert card["inputs"] == list(task.inputs)
    assert card["spec"]["encoder"] == {
        "counts_per_revolution": 131072.0, "counts_per_metre": 1e5, "noise": 1e-5,
        "offset": 1e-3,
    }  # fmt: skip
    with DatasetReader(folder / DATASET_NAME) as reader:
        assert reader.attributes["encoder"] == asdict(ENCODER)
        run = reader.run(0, ["q", "q_measured", "encoder_offset"])
    moving = np.flatnonzero(np.abs(run["q"]).max(axis=0) > 0)
    error = run["q_measured"][:, moving] - run["q"][:, moving]
    assert (error != 0).any(axis=0).all()  # every moving joint's reading differs from q
    assert np.abs(error - run["encoder_offset"][:, moving]).max() < 1e-4  # ~ counts and noise


def test_the_ceiling_reads_the_truth_and_scores_the_storage(folder: Path, tmp_path: Path) -> None:
    path = run_baseline("inverse-dynamics", folder, tmp_path / "c.npz", "rigid-body-truth")
    score = score_task("inverse-dynamics", folder, path)
    assert score["relative_rms_max"] < 1e-6  # the stored float32 torques


def test_the_table_model_on_the_true_motion_gives_the_stored_torques(folder: Path) -> None:
    """The classical model has the data set's inertias: its error comes from the motion only."""
    from aaria_pin.aaria.dh_robot import build_dh_robot
    from aaria_pin.core.dynamics import inverse_dynamics
    from aaria_pin.core.oscillation import base_motion
    from aaria_pin.core.trajectory import JointTrajectory

    with DatasetReader(folder / DATASET_NAME) as reader:
        names = list(reader.layout.joint_names)
        run = reader.run(1, ["time", "q", "qd", "qdd", "tau", "senSenB", "senSenDH"])
    robot = build_dh_robot(run["senSenDH"].astype(float)).model(moving_base=True)
    columns = [names.index(name) for name in robot.joint_names]
    motion = [run[name][:, columns].astype(float) for name in ("q", "qd", "qdd")]
    time = run["time"].astype(float)
    base = base_motion(run["senSenB"].astype(float), time)
    torques = inverse_dynamics(robot, base, JointTrajectory(time, *motion))[0]
    assert relative_rms(run["tau"][:, columns], torques) < 1e-6


def test_the_classical_baseline_lies_between_the_ceiling_and_zero(
    folder: Path, tmp_path: Path
) -> None:
    scores = {
        name: score_task(
            "inverse-dynamics",
            folder,
            run_baseline("inverse-dynamics", folder, tmp_path / f"{name}.npz", name),
        )["relative_rms_max"]
        for name in ("rigid-body", "rigid-body-truth", "zero")
    }
    assert scores["zero"] == 1.0
    assert 1e-4 < scores["rigid-body"] < 0.1
    assert scores["rigid-body"] > 100 * scores["rigid-body-truth"]


def test_the_filter_differentiates_a_cubic_exactly() -> None:
    t = np.arange(50) / 100.0
    q = np.stack([1 + 2 * t - 3 * t**2 + 4 * t**3, -(t**3)], axis=1)
    value, rate, acceleration = rb.encoder_motion(q, 100.0, 9)
    np.testing.assert_allclose(value, q, atol=1e-12)
    np.testing.assert_allclose(rate, np.stack([2 - 6 * t + 12 * t**2, -3 * t**2], 1), atol=1e-9)
    np.testing.assert_allclose(acceleration, np.stack([-6 + 24 * t, -6 * t], 1), atol=1e-7)


class _Spy:
    """Records the (run, names) each ``DatasetReader.run`` call asks for."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch) -> None:
        self.calls: list[tuple[int, tuple[str, ...]]] = []
        original = DatasetReader.run

        def run(reader: DatasetReader, index: int, names: Any = None) -> Any:
            self.calls.append((int(index), tuple(names or ())))
            return original(reader, index, names)

        monkeypatch.setattr(DatasetReader, "run", run)


@settings(
    max_examples=5, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(train=st.lists(st.integers(0, 5), min_size=1, max_size=3, unique=True))
def test_the_window_is_chosen_from_the_training_runs_alone(
    folder: Path, monkeypatch: pytest.MonkeyPatch, train: list[int]
) -> None:
    spy = _Spy(monkeypatch)
    window = rb.choose_window(folder / DATASET_NAME, train, 100.0, 1)
    assert {run for run, _ in spy.calls} == set(train)
    with DatasetReader(folder / DATASET_NAME) as reader:  # the window of least median error
        arrays = [reader.run(k, [*rb._INPUTS, "tau"]) for k in train]
        names = reader.layout.joint_names
    windows = [w for w in rb.WINDOWS if w <= 51]
    errors = [
        [relative_rms(a["tau"], t) for t in rb.table_torques(a, names, 100.0, windows)]
        for a in arrays
    ]
    assert window == windows[int(np.argmin(np.median(errors, axis=0)))]


def test_the_baseline_reads_no_test_target(
    folder: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    card = _card(folder)
    spy = _Spy(monkeypatch)
    run_baseline("inverse-dynamics", folder, tmp_path / "rb.npz", "rigid-body")
    train = set(card["splits"]["train"])
    read_truth = {run for run, names in spy.calls if _TRUTH & set(names)}
    assert read_truth == train
    tested = {run for run, _ in spy.calls} - train
    assert tested == set(card["splits"]["test"])


def test_a_folder_of_the_older_definition_is_refused(folder: Path, tmp_path: Path) -> None:
    old = tmp_path / "old"
    old.mkdir()
    card = _card(folder)
    card["inputs"] = ["q", "qd", "qdd", "base_pose", "senSenDH"]  # the card before measurements
    del card["spec"]["encoder"]
    (old / CARD_NAME).write_text(json.dumps(card))
    (old / DATASET_NAME).symlink_to(folder / DATASET_NAME)
    for call in (
        lambda: score_task("inverse-dynamics", old, tmp_path / "p.npz"),
        lambda: run_baseline("inverse-dynamics", old, tmp_path / "p.npz", "zero"),
    ):
        with pytest.raises(InputFileError, match=r"older definition of the task: make it again"):
            call()
    assert not (tmp_path / "p.npz").exists()


def test_the_data_set_is_aaria_dataset_with_the_encoder_table(folder: Path, tmp_path: Path) -> None:
    """The card's equivalence: ``aaria dataset`` with a config of the ``[encoder]`` table."""
    from aaria_pin.apps.dataset.generate import generate_dataset
    from aaria_pin.apps.dataset.job import DatasetJob
    from aaria_pin.apps.dataset.spec_sources import DatasetSources

    config = tmp_path / "encoder.toml"
    fields = "\n".join(f"{key} = {value!r}" for key, value in asdict(ENCODER).items())
    config.write_text(f"[encoder]\n{fields}\n")
    sources = DatasetSources(n_runs=6, seed=2702, duration=0.5, rate=100.0, config_file=config)
    generate_dataset(tmp_path / "d.h5", sources.spec(), DatasetJob(workers=1))
    with DatasetReader(tmp_path / "d.h5") as made, DatasetReader(folder / DATASET_NAME) as task:
        for name in ("q_measured", "imu", "tau", "senSenDH"):
            np.testing.assert_array_equal(made.run(4, [name])[name], task.run(4, [name])[name])


def test_runs_shorter_than_a_window_are_refused(tmp_path: Path) -> None:
    folder = tmp_path / "short"
    make_task("inverse-dynamics", folder, n_runs=3, duration=0.03, workers=1)
    with pytest.raises(InputFileError, match="runs of 4 samples; allowed: at least 5"):
        run_baseline("inverse-dynamics", folder, tmp_path / "p.npz", "rigid-body")
    assert not (tmp_path / "p.npz").exists()
