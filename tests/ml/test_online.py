"""Online runs and windows against the file ``aaria dataset`` makes with the same settings.

Each expectation is the file: run k's stored arrays read with h5py, the file-backed windows
and statistics of :class:`~aaria_pin.files.dataset.reader.DatasetReader`; the workers' shares
against the runs of the split, counted as they are simulated.
"""

from __future__ import annotations

import pickle
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from aaria_pin.apps.dataset.spec_sources import DatasetSources
from aaria_pin.errors import ParameterError
from aaria_pin.files.dataset.reader import DatasetReader
from aaria_pin.ml import OnlineRuns, OnlineWindows, worker_info
from tests.conftest import run_cli

N_RUNS, SEED = 3, 5
SETTINGS = {"n_runs": N_RUNS, "seed": SEED, "duration": 0.2, "rate": 100.0}
ROBOTS = {"dh": {}, "ur5": {"robot": "ur5"}}
NAMES = ("imu", "senSen", "tau", "senSenDH", "link_types", "empty_mask")


@pytest.fixture(scope="module", params=sorted(ROBOTS))
def made(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> tuple:
    """A data set made by ``aaria dataset`` (3 runs, 0.2 s at 100 Hz) and its online runs."""
    robot = ROBOTS[request.param]
    path = tmp_path_factory.mktemp("online") / f"{request.param}.h5"
    flags = ["--robot", robot["robot"]] if robot else []
    code, _, err = run_cli(
        "dataset", "-n", str(N_RUNS), "--seed", str(SEED), "--duration", "0.2", "--rate", "100",
        "--workers", "1", "--quiet", *flags, "-o", str(path),
    )  # fmt: skip
    assert code == 0, err
    return path, OnlineRuns(DatasetSources(**SETTINGS, **robot))


@pytest.fixture(scope="module")
def dh_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A data set of random DH arms made by ``aaria dataset``, its training statistics stored."""
    path = tmp_path_factory.mktemp("online_dh") / "ds.h5"
    code, _, err = run_cli(
        "dataset", "-n", str(N_RUNS), "--seed", str(SEED), "--duration", "0.2", "--rate", "100",
        "--workers", "1", "--quiet", "-o", str(path),
    )  # fmt: skip
    assert code == 0, err
    with DatasetReader(path) as reader:
        reader.statistics(("imu", "senSen"), split="train", store=True)
    return path


def test_run_k_equals_run_k_of_the_file(made: tuple) -> None:
    path, runs = made
    assert len(runs) == N_RUNS
    with h5py.File(path, "r") as handle:
        stored = [name for name in runs.layout.names if name in handle]
        assert stored == list(runs.layout.names)  # every array the file stores per run
        for k in range(N_RUNS):
            arrays = runs[k]
            assert list(arrays) == stored
            for name in stored:
                expected = handle[name][k]
                assert arrays[name].dtype == expected.dtype, name
                np.testing.assert_array_equal(arrays[name], expected, err_msg=f"{name} run {k}")
    np.testing.assert_array_equal(runs[-1]["imu"], runs[N_RUNS - 1]["imu"])
    with pytest.raises(IndexError):
        runs[N_RUNS]


def _windows_equal(online: list[dict], file_backed: list[dict]) -> None:
    assert len(online) == len(file_backed)
    for mine, theirs in zip(online, file_backed, strict=True):
        assert list(mine) == list(theirs)
        for name in theirs:
            assert mine[name].dtype == theirs[name].dtype, name
            np.testing.assert_array_equal(mine[name], theirs[name], err_msg=name)


def test_windows_and_labels_equal_the_file_backed_ones(dh_file: Path) -> None:
    runs = OnlineRuns.defaults(N_RUNS, seed=SEED, duration=0.2, rate=100.0)
    online = list(runs.windows(7, 4, names=NAMES))
    with DatasetReader(dh_file) as reader:
        windows = reader.windows(7, 4, names=NAMES)
        _windows_equal(online, [windows[i] for i in range(len(windows))])
        assert len(online) == N_RUNS * 4  # (21 - 7) // 4 + 1 windows a run
        labels = [reader.labels(k) for k in range(N_RUNS)]
    for window in online:  # the labels: the stored table's fifth column
        assert window["link_types"].tolist() == labels[int(window["run"])]["link_types"].tolist()
        np.testing.assert_array_equal(window["empty_mask"], window["senSenDH"][:6, 4] == 0)


def test_statistics_and_normalised_windows_equal_the_file_backed_ones(dh_file: Path) -> None:
    runs = OnlineRuns.defaults(N_RUNS, seed=SEED, duration=0.2, rate=100.0)
    statistics = runs.statistics(("imu", "senSen"))  # the training split of seed 0
    names = ("imu", "senSen", "link_types")
    with DatasetReader(dh_file) as reader:
        stored = reader.statistics(("imu", "senSen"), split="train")
        windows = reader.windows(10, names=names, split="train", normalise=True)
        expected = [windows[i] for i in range(len(windows))]
    for name, (mean, std) in stored.items():
        np.testing.assert_array_equal(statistics[name][0], mean)
        np.testing.assert_array_equal(statistics[name][1], std)
    online = runs.windows(10, names=names, split="train", normalise=True, statistics=statistics)
    assert online.statistics is not None and set(online.statistics) == {"imu", "senSen"}
    _windows_equal(list(online), expected)


def test_whole_runs_normalised_with_a_files_statistics_equal_the_file_backed_ones(
    dh_file: Path,
) -> None:
    runs = OnlineRuns.defaults(N_RUNS, seed=SEED, duration=0.2, rate=100.0)
    names = ("imu", "tau", "inertial_parameters", "empty_mask")
    with DatasetReader(dh_file) as reader:
        statistics = reader.statistics(("imu", "tau"), split=None)
        windows = reader.windows(None, names=names, normalise=("imu", "tau"), statistics=statistics)
        expected = [windows[i] for i in range(len(windows))]
    online = runs.windows(None, names=names, normalise=("imu", "tau"), statistics=statistics)
    assert len(online) == N_RUNS and online.length == 21
    _windows_equal(list(online), expected)
    again = runs.windows(None, names=names, normalise=("imu", "tau"), statistics=online.statistics)
    _windows_equal(list(again), expected)  # a window dataset's statistics, passed on


def test_two_workers_share_the_runs_each_simulated_once() -> None:
    runs = OnlineRuns.defaults(5, seed=SEED, duration=0.2, rate=100.0)
    windows = runs.windows(10, names=("q",))
    simulated: list[int] = []
    original = runs.simulate

    def counted(run: int) -> dict[str, np.ndarray]:
        simulated.append(run)
        return original(run)

    runs.simulate = counted  # type: ignore[method-assign]
    shares = [windows.worker_runs(w, 2).tolist() for w in range(2)]
    assert shares == [[0, 2, 4], [1, 3]]
    seen = [(int(w["run"]), int(w["start"])) for k in range(2) for w in windows.iterate(k, 2)]
    assert sorted(simulated) == list(range(5))  # each run once over both workers
    assert sorted(seen) == [(run, start) for run in range(5) for start in (0, 10)]
    assert len(seen) == len(windows)
    assert worker_info() == (0, 1)  # the main process
    assert [int(w["run"]) for w in windows] == [0, 0, 1, 1, 2, 2, 3, 3, 4, 4]


def test_fresh_epochs_are_the_runs_of_a_larger_data_set() -> None:
    runs = OnlineRuns.defaults(2, seed=SEED, duration=0.2, rate=100.0)
    windows = runs.windows(21, names=("imu", "senSenDH"))
    windows.set_epoch(1)
    assert windows.epoch_runs().tolist() == [2, 3]
    larger = OnlineRuns.defaults(4, seed=SEED, duration=0.2, rate=100.0)
    for window in windows:
        run = int(window["run"])
        np.testing.assert_array_equal(window["imu"], larger[run]["imu"])
        np.testing.assert_array_equal(window["senSenDH"], larger[run]["senSenDH"])
    with pytest.raises(ParameterError, match="epoch"):
        windows.set_epoch(-1)


def test_pickled_windows_give_the_same_windows() -> None:
    runs = OnlineRuns.defaults(2, seed=SEED, duration=0.2, rate=100.0, robot="ur5")
    windows = runs.windows(10, names=("signals", "q"), split=None)
    assert "link_types" not in runs.names  # a URDF robot's structure is fixed: no labels
    copy = pickle.loads(pickle.dumps(windows))
    assert isinstance(copy, OnlineWindows)
    _windows_equal(list(copy), list(windows))


def test_bad_arguments_are_refused_naming_the_parameter() -> None:
    runs = OnlineRuns.defaults(N_RUNS, seed=SEED, duration=0.2, rate=100.0)
    with pytest.raises(ParameterError, match="names") as caught:
        runs.windows(5, names=("nope",))
    assert caught.value.parameter == "names"
    with pytest.raises(ParameterError) as caught:
        runs.windows(5, names=("imu",), normalise=True)
    assert caught.value.parameter == "statistics"
    with pytest.raises(ParameterError) as caught:
        runs.windows(50)
    assert caught.value.parameter == "length"
    with pytest.raises(ParameterError) as caught:
        runs.statistics(("link_types",))
    assert caught.value.parameter == "names"
    with pytest.raises(ParameterError) as caught:
        runs.windows(5).worker_runs(2, 2)
    assert caught.value.parameter == "worker"
    assert runs.windows(5).names == ("senSen",)  # the first view, as the reader's default


def test_importing_the_package_does_not_import_torch() -> None:
    code = (
        "import sys, aaria_pin.ml; from aaria_pin.ml import OnlineRuns; "
        "print('torch' in sys.modules)"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.stdout.strip() == "False", result.stderr


def test_a_torch_data_loader_with_two_workers_reads_each_window_once() -> None:
    torch = pytest.importorskip("torch")
    runs = OnlineRuns.defaults(4, seed=SEED, duration=0.2, rate=100.0)
    windows = runs.windows(10, names=("imu", "link_types"))
    loader = torch.utils.data.DataLoader(windows.torch(), batch_size=3, num_workers=2)
    seen = []
    for batch in loader:
        assert batch["imu"].shape[1:] == (10, 14, 6)
        seen += list(zip(batch["run"].tolist(), batch["start"].tolist(), strict=True))
    assert sorted(seen) == [(run, start) for run in range(4) for start in (0, 10)]
    assert len(loader.dataset) == len(windows) == 8


def test_persistent_workers_take_fresh_arms_each_epoch() -> None:
    torch = pytest.importorskip("torch")
    runs = OnlineRuns.defaults(4, seed=SEED, duration=0.2, rate=100.0)
    windows = runs.windows(20, names=("link_types",))
    loader = torch.utils.data.DataLoader(
        windows.torch(advance_epochs=True), batch_size=2, num_workers=2, persistent_workers=True
    )
    for epoch in range(3):
        seen = sorted(run for batch in loader for run in batch["run"].tolist())
        assert seen == [k + 4 * epoch for k in range(4)], epoch  # run k + e·N in epoch e
    assert windows.epoch == 0  # the workers moved their own copies
    plain = torch.utils.data.DataLoader(windows.torch(), batch_size=2, num_workers=0)
    for _ in range(2):  # without advance_epochs: the same runs again
        assert sorted(run for batch in plain for run in batch["run"].tolist()) == [0, 1, 2, 3]
    here = torch.utils.data.DataLoader(windows.torch(advance_epochs=True), batch_size=2)
    for epoch in range(3):  # no workers: set_epoch moves it, each epoch once, none skipped
        windows.set_epoch(epoch)
        seen = sorted(run for batch in here for run in batch["run"].tolist())
        assert seen == [k + 4 * epoch for k in range(4)], epoch
    assert windows.epoch == 2
