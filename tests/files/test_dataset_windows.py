"""The windows loader: a map-style dataset over a data set's runs, splits by run, statistics.

Every window is checked against a direct h5py slice of the file, the window index against nested
loops over the complete runs, the statistics against NumPy's ``mean``/``std`` of the split's
runs read with h5py; the loader is used from two processes at once and across pickling.
"""

from __future__ import annotations

import json
import multiprocessing
import os
import pickle
import shutil
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest

from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.apps.dataset.generate import generate_dataset
from aaria_pin.errors import InputFileError, OutputFileError, ParameterError
from aaria_pin.files.dataset.reader import DatasetReader
from aaria_pin.files.dataset.statistics import channel_statistics
from aaria_pin.files.dataset.windows import WindowDataset, split_runs

N_RUNS, SAMPLES, INCOMPLETE = 12, 51, 5
FIXTURES = Path(__file__).resolve().parent.parent / "fixtures" / "v0_1_0"


@pytest.fixture(scope="module")
def dataset(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A data set of random DH arms, 12 runs of 51 samples; run 5 marked incomplete."""
    path = tmp_path_factory.mktemp("windows") / "ds.h5"
    generate_dataset(path, DhDatasetSpec(n_runs=N_RUNS, seed=3, duration=0.5), workers=1)
    with h5py.File(path, "r+") as handle:
        handle["complete"][INCOMPLETE] = 0
    return path


def _complete_runs(path: Path) -> list[int]:
    with h5py.File(path, "r") as handle:
        return [k for k, flag in enumerate(handle["complete"][()]) if flag]


def _expected(path: Path, runs: list[int], length: int, stride: int) -> list[tuple[int, int]]:
    with h5py.File(path, "r") as handle:
        samples = handle["time"].shape[1] if "time" in handle else handle["q"].shape[1]
    return [(k, s) for k in runs for s in range(0, samples - length + 1, stride)]


@pytest.mark.parametrize(("length", "stride"), [(20, 10), (51, None), (1, 1), (10, 17)])
def test_windows_of_every_complete_run(dataset: Path, length: int, stride: int | None) -> None:
    expected = _expected(dataset, _complete_runs(dataset), length, stride or length)
    with DatasetReader(dataset) as reader:
        windows = reader.windows(length, stride, names=("senSen", "tau"))
    assert len(windows) == len(expected)
    assert [
        (int(w["run"]), int(w["start"])) for w in map(windows.__getitem__, range(len(windows)))
    ] == expected
    assert [(k, s) for k, s, _ in windows] == expected


def test_window_contents_equal_h5py_slices(dataset: Path) -> None:
    names = ("senSen", "signals", "imu", "tau", "base_pose", "senSenDH", "imu_mount")
    with DatasetReader(dataset) as reader:
        windows = reader.windows(20, 15, names=names)
    expected = _expected(dataset, _complete_runs(dataset), 20, 15)
    iterated = list(windows)
    with h5py.File(dataset, "r") as handle:
        for i, (k, s) in enumerate(expected):
            window = windows[i]
            assert set(window) == {*names, "run", "start"}
            for name in ("senSen", "signals", "imu", "tau", "base_pose"):  # along time
                np.testing.assert_array_equal(window[name], handle[name][k, s : s + 20])
                np.testing.assert_array_equal(iterated[i][2][name], window[name])
            for name in ("senSenDH", "imu_mount"):  # per-run constants, whole
                np.testing.assert_array_equal(window[name], handle[name][k])
        assert windows[-1]["tau"].shape == (20, 6) and int(windows[-1]["run"]) == N_RUNS - 1
        np.testing.assert_array_equal(windows[-1]["imu"], windows[len(windows) - 1]["imu"])
    with pytest.raises(IndexError):
        windows[len(windows)]
    with pytest.raises(IndexError):
        windows[-len(windows) - 1]


def test_default_name_and_bad_arguments(dataset: Path) -> None:
    with DatasetReader(dataset) as reader:
        assert reader.windows(10).names == ("senSen",)
        assert "senSenDH" not in reader.series_names and "senSen" in reader.series_names
        for kwargs, parameter in [
            ({"length": 0}, "length"),
            ({"length": SAMPLES + 1}, "length"),
            ({"length": 5, "stride": 0}, "stride"),
            ({"length": 5, "names": ("nope",)}, "names"),
            ({"length": 5, "split": "training"}, "split"),
            ({"length": 5, "split": "train", "seed": -1}, "seed"),
            ({"length": 5, "fractions": (0.8, 0.1)}, "fractions"),
            ({"length": 5, "fractions": (0.8, 0.3, -0.1)}, "fractions"),
        ]:
            with pytest.raises(ParameterError) as caught:
                reader.windows(**kwargs)
            assert caught.value.parameter == parameter


def test_splits_are_disjoint_and_cover_every_complete_run(dataset: Path) -> None:
    complete = set(_complete_runs(dataset))
    with DatasetReader(dataset) as reader:
        for seed in (0, 1, 7):
            parts = {
                s: reader.windows(51, split=s, seed=seed) for s in ("train", "validation", "test")
            }
            runs = {
                s: {int(w["run"]) for w in map(ds.__getitem__, range(len(ds)))}
                for s, ds in parts.items()
            }
            assert not runs["train"] & runs["validation"]
            assert not runs["train"] & runs["test"] and not runs["validation"] & runs["test"]
            assert runs["train"] | runs["validation"] | runs["test"] == complete
            assert INCOMPLETE not in set().union(*runs.values())
            for split in ("train", "validation", "test"):  # completeness moves no run
                every = split_runs(N_RUNS, split, seed=seed).tolist()
                assert sorted(runs[split]) == [k for k in every if k != INCOMPLETE]
        # the documented rule, written out: keys are PCG64(seed)'s raw outputs, runs by key
        order = np.argsort(np.random.PCG64(4).random_raw(N_RUNS), kind="stable")
        train = sorted(int(k) for k in order[: int(np.floor(0.8 * N_RUNS + 0.5))])
        assert list(reader.windows(51, split="train", seed=4).runs) == [
            k for k in train if k != INCOMPLETE
        ]


def test_split_sizes_and_dependence_on_seed_fractions_and_n_only() -> None:
    for n in (1, 7, 12, 100, 1001):
        parts = [split_runs(n, s, seed=2) for s in ("train", "validation", "test")]
        sizes = [len(p) for p in parts]
        # round half up of 0.8 N and 0.9 N, written out
        first, second = int(np.floor(0.8 * n + 0.5)), int(np.floor(0.9 * n + 0.5))
        assert sizes == [first, second - first, n - second]
        assert sorted(np.concatenate(parts).tolist()) == list(range(n))
        assert all(np.all(np.diff(p) > 0) for p in parts)
    assert len(split_runs(10, "validation", fractions=(0.5, 0.5, 0.0))) == 5
    assert len(split_runs(10, "test", fractions=(0.5, 0.5, 0.0))) == 0
    train = {seed: split_runs(1000, "train", seed=seed) for seed in (0, 1)}
    assert not np.array_equal(train[0], train[1])
    order = np.argsort(np.random.PCG64(0).random_raw(1000), kind="stable")  # the rule, by hand
    np.testing.assert_array_equal(train[0], np.sort(order[:800]))


def test_an_empty_split(dataset: Path) -> None:
    with DatasetReader(dataset) as reader:
        windows = reader.windows(10, split="test", fractions=(0.5, 0.5, 0.0))
        assert len(windows) == 0 and list(windows) == []
        with pytest.raises(IndexError):
            windows[0]


def test_pickling_round_trips(dataset: Path) -> None:
    with DatasetReader(dataset) as reader:
        windows = reader.windows(20, 10, names=("imu", "q"), split="train", seed=1)
    before = windows[7]  # the handle is open now; pickling leaves it behind
    copy = pickle.loads(pickle.dumps(windows))
    assert copy._handle is None and len(copy) == len(windows)
    for i in (0, 7, len(windows) - 1):
        for name, array in windows[i].items():
            np.testing.assert_array_equal(copy[i][name], array)
    np.testing.assert_array_equal(copy[7]["imu"], before["imu"])
    again = pickle.loads(pickle.dumps(copy))  # and after the copy has read
    np.testing.assert_array_equal(again[3]["q"], windows[3]["q"])
    copy.close()
    windows.close()
    np.testing.assert_array_equal(windows[3]["q"], again[3]["q"])  # reopened on demand


def _read_in_child(windows: WindowDataset, indices: list[int], barrier: Any, results: Any) -> None:
    barrier.wait(timeout=60)  # both processes read at the same time
    items = [windows[i] for i in indices for _ in range(3)]
    results.put((os.getpid(), windows._pid, indices, [item["imu"] for item in items[::3]]))


def test_two_processes_read_at_once(dataset: Path) -> None:
    with DatasetReader(dataset) as reader:
        windows = reader.windows(10, 5, names=("imu",), split="train")
    windows[0]  # the parent's handle is open before the fork: the children must not use it
    context = multiprocessing.get_context("fork")
    barrier, results = context.Barrier(2), context.Queue()
    halves = [list(range(0, len(windows), 2)), list(range(1, len(windows), 2))]
    children = [
        context.Process(target=_read_in_child, args=(windows, half, barrier, results))
        for half in halves
    ]
    for child in children:
        child.start()
    received = [results.get(timeout=120) for _ in children]
    for child in children:
        child.join(timeout=60)
        assert child.exitcode == 0
    with h5py.File(dataset, "r") as handle:
        for pid, opened_by, indices, arrays in received:
            assert opened_by == pid != os.getpid()
            for i, array in zip(indices, arrays, strict=True):
                k, s = windows.locate(i)
                np.testing.assert_array_equal(array, handle["imu"][k, s : s + 10])
    # a pickled copy (as a spawned DataLoader worker gets it) in a process of its own
    spawned = multiprocessing.get_context("spawn").Pool(1)
    try:
        first = spawned.apply(_first_imu, (pickle.dumps(windows),), {})
    finally:
        spawned.close()
        spawned.join()
    np.testing.assert_array_equal(first, windows[0]["imu"])


def _first_imu(pickled: bytes) -> np.ndarray:
    return pickle.loads(pickled)[0]["imu"]


def test_statistics_equal_numpy_over_the_training_runs(dataset: Path) -> None:
    names = ("senSen", "signals", "imu", "tau", "senSenDH")
    with DatasetReader(dataset) as reader:
        statistics = reader.statistics(names, split="train", seed=2)
        runs = reader.windows(SAMPLES, split="train", seed=2).runs
    assert INCOMPLETE not in runs
    with h5py.File(dataset, "r") as handle:
        for name in names:
            stored = np.stack([handle[name][k] for k in runs]).astype(np.float64)
            channel = stored.shape[1:] if name == "senSenDH" else stored.shape[2:]
            flat = stored.reshape(-1, *channel)
            mean, std = statistics[name]
            assert mean.shape == std.shape == channel and mean.dtype == np.float64
            np.testing.assert_allclose(mean, flat.mean(axis=0), rtol=1e-12, atol=1e-12)
            np.testing.assert_allclose(std, flat.std(axis=0), rtol=1e-10, atol=1e-12)
        one_run_blocks = channel_statistics(handle, ("imu",), (True,), runs, block_bytes=1)
    np.testing.assert_allclose(one_run_blocks["imu"][1], statistics["imu"][1], rtol=1e-12)
    assert one_run_blocks["imu"][2] == len(runs) * SAMPLES


def test_statistics_are_stable_far_from_zero(tmp_path: Path) -> None:
    rng = np.random.default_rng(0)
    noise = rng.normal(size=(40, 1000, 3))
    with h5py.File(tmp_path / "far.h5", "w") as handle:
        handle["x"] = 1e9 + noise  # E[x²] - E[x]² would lose every digit here
        result = channel_statistics(handle, ("x",), (True,), np.arange(40), block_bytes=48_000)
    flat = noise.reshape(-1, 3)
    np.testing.assert_allclose(result["x"][1], flat.std(axis=0), rtol=1e-6)
    np.testing.assert_allclose(result["x"][0] - 1e9, flat.mean(axis=0), atol=1e-6)


def test_statistics_stored_read_back_and_used_to_normalise(dataset: Path, tmp_path: Path) -> None:
    path = tmp_path / "ds.h5"
    shutil.copyfile(dataset, path)
    with h5py.File(path, "r") as handle:
        before = {name: handle[name][()] for name in ("imu", "senSen", "complete", "checksum")}
    with DatasetReader(path) as reader:
        with pytest.raises(InputFileError, match="no statistics"):
            reader.windows(10, names=("tau",), normalise=True)
        reader.statistics(("q",), store=True)
        computed = reader.statistics(("senSen", "tau"), store=True)  # replaces the first
        stored = reader.stored_statistics("train")
        assert set(stored) == {"senSen", "tau"}
        for name, (mean, std) in computed.items():
            np.testing.assert_array_equal(stored[name][0], mean)
            np.testing.assert_array_equal(stored[name][1], std)
        validation = reader.windows(10, names=("tau", "senSen"), split="validation", normalise=True)
        with pytest.raises(InputFileError, match="seed 0"):
            reader.windows(10, names=("tau",), seed=1, normalise=True)
        with pytest.raises(InputFileError, match="'imu'"):
            reader.windows(10, names=("imu",), normalise=True)
    with h5py.File(path, "r") as handle:
        for name, array in before.items():  # the data untouched
            np.testing.assert_array_equal(handle[name][()], array)
        group = handle["statistics/train"]
        assert group.attrs["seed"] == 0 and list(group.attrs["fractions"]) == [0.8, 0.1, 0.1]
        assert sorted(group) == ["senSen", "tau"]
        for i in range(len(validation)):
            k, s = validation.locate(i)
            tau = handle["tau"][k, s : s + 10].astype(np.float64)
            mean, std = computed["tau"]
            expected = ((tau - mean) / std).astype(np.float32)
            window = validation[i]
            assert window["tau"].dtype == np.float32
            np.testing.assert_allclose(window["tau"], expected, rtol=1e-6, atol=1e-6)
            assert np.isfinite(window["senSen"]).all()  # constant columns (std 0) only centred
    with DatasetReader(path) as reader:  # a fresh reader sees the same numbers
        np.testing.assert_array_equal(reader.stored_statistics()["tau"][1], computed["tau"][1])


def test_storing_refused_while_another_handle_is_open(dataset: Path, tmp_path: Path) -> None:
    path = tmp_path / "ds.h5"
    shutil.copyfile(dataset, path)
    with DatasetReader(path) as reader, h5py.File(path, "r"):
        with pytest.raises(OutputFileError, match="cannot store statistics"):
            reader.statistics(("tau",), store=True)
        assert len(reader.windows(10)) > 0  # the reader still reads


@pytest.mark.parametrize(
    ("fixture", "view"), [("dh_dataset.h5", "senSen"), ("ur5_dataset.h5", "signals")]
)
def test_version_1_data_sets(fixture: str, view: str, tmp_path: Path) -> None:
    path = tmp_path / fixture
    shutil.copyfile(FIXTURES / fixture, path)
    with DatasetReader(path) as reader:
        assert reader.version == 1
        windows = reader.windows(5, 3, names=(view, "tau", "imu_mount"))
        assert windows.names[0] == reader.windows(5).names[0] == view
        statistics = reader.statistics((view, "tau"), split=None, store=True)
        assert set(reader.stored_statistics(None)) == {view, "tau"}
    runs = _complete_runs(path)
    expected = _expected(path, runs, 5, 3)
    assert len(windows) == len(expected)
    with h5py.File(path, "r") as handle:
        for i, (k, s) in enumerate(expected):
            np.testing.assert_array_equal(windows[i][view], handle[view][k, s : s + 5])
            np.testing.assert_array_equal(windows[i]["imu_mount"], handle["imu_mount"][k])
        flat = handle["tau"][runs].astype(np.float64).reshape(-1, 6)
    np.testing.assert_allclose(statistics["tau"][0], flat.mean(axis=0), rtol=1e-12)
    np.testing.assert_allclose(statistics["tau"][1], flat.std(axis=0), rtol=1e-10)


def test_dataset_stats_command(dataset: Path, tmp_path: Path) -> None:
    from click.testing import CliRunner

    from aaria_pin.cli.stats_cmd import dataset_stats

    path = tmp_path / "ds.h5"
    shutil.copyfile(dataset, path)
    runner = CliRunner()
    result = runner.invoke(dataset_stats, [str(path), "--names", "tau,senSen", "--json"])
    assert result.exit_code == 0, result.output
    document = json.loads(result.output)
    with h5py.File(path, "r") as handle:
        runs = split_runs(N_RUNS, "train")
        runs = runs[handle["complete"][()][runs] == 1]
        tau = np.concatenate([handle["tau"][k] for k in runs]).astype(np.float64)
        assert "statistics" not in handle  # nothing stored without --store
    np.testing.assert_allclose(document["tau"]["mean"], tau.mean(axis=0), rtol=1e-12)
    np.testing.assert_allclose(document["tau"]["std"], tau.std(axis=0), rtol=1e-10)
    assert len(document["senSen"]["std"]) == 91
    result = runner.invoke(dataset_stats, [str(path), "--names", "q", "--split", "all", "--store"])
    assert result.exit_code == 0, result.output
    assert "q (6 channels)" in result.output and "statistics/all" in result.output
    with DatasetReader(path) as reader:
        assert set(reader.stored_statistics(None)) == {"q"}
    bad = runner.invoke(dataset_stats, [str(path), "--names", "nope"])
    assert isinstance(bad.exception, ParameterError) and bad.exception.parameter == "names"
    bad = runner.invoke(dataset_stats, [str(path), "--fractions", "a,b"])
    assert isinstance(bad.exception, ParameterError) and bad.exception.parameter == "fractions"


def test_arrays_in_shard_files_read_the_same(dataset: Path, tmp_path: Path) -> None:
    """A manifest whose ``imu`` and ``tau`` are virtual datasets over two shard files."""
    manifest = tmp_path / "manifest.h5"
    shutil.copyfile(dataset, manifest)
    with h5py.File(manifest, "r+") as handle:
        for name in ("imu", "tau"):
            array = handle[name][()]
            layout = h5py.VirtualLayout(shape=array.shape, dtype=array.dtype)
            for shard, runs in (("a", slice(0, 7)), ("b", slice(7, N_RUNS))):
                shard_path = tmp_path / f"shard_{shard}_{name}.h5"
                with h5py.File(shard_path, "w") as out:
                    out[name] = array[runs]
                layout[runs] = h5py.VirtualSource(str(shard_path), name, shape=array[runs].shape)
            del handle[name]
            handle.create_virtual_dataset(name, layout)
    with h5py.File(manifest, "r") as handle:
        assert handle["tau"].is_virtual and handle["imu"].is_virtual
    names = ("senSen", "imu", "tau")
    with DatasetReader(dataset) as plain, DatasetReader(manifest) as sharded:
        expected, got = plain.windows(20, 7, names=names), sharded.windows(20, 7, names=names)
        assert len(got) == len(expected)
        for i in range(0, len(got), 5):
            for name in names:
                np.testing.assert_array_equal(got[i][name], expected[i][name])
        reference = plain.statistics(names)
        for name, (mean, std) in sharded.statistics(names).items():
            np.testing.assert_array_equal(mean, reference[name][0])
            np.testing.assert_array_equal(std, reference[name][1])


def test_statistics_of_an_empty_split_are_refused_not_nan(dataset: Path) -> None:
    with DatasetReader(dataset) as reader:
        with pytest.raises(ParameterError) as error:
            reader.statistics(("tau",), split="test", fractions=(0.5, 0.5, 0.0))
    assert error.value.parameter == "split" and "holds none" in str(error.value)


def test_normalisation_per_field(dataset: Path, tmp_path: Path) -> None:
    path = tmp_path / "ds.h5"
    shutil.copyfile(dataset, path)
    names = ("imu", "senSenDH", "tau", "link_types")
    with DatasetReader(path) as reader:
        reader.statistics(("imu",), store=True)  # only imu's: enough to normalise imu alone
        train_runs = reader.split_runs("train")
        windows = reader.windows(10, 7, names=names, normalise=("imu",))
        assert windows.statistics is not None and set(windows.statistics) == {"imu"}
        as_string = reader.windows(10, 7, names=names, normalise="imu")
        everything = reader.windows(10, 7, names=("imu", "link_types"), normalise=True)
        raw = reader.windows(10, 7, names=names, normalise=False)
        with pytest.raises(InputFileError, match="'tau'") as missing:
            reader.windows(10, names=names, normalise=("imu", "tau"))
        assert "\n" not in str(missing.value)
        for bad in (("q",), ("link_types",), ("imu", "nope")):
            with pytest.raises(ParameterError) as caught:
                reader.windows(10, names=names, normalise=bad)
            assert caught.value.parameter == "normalise"
    with h5py.File(path, "r") as handle:
        imu = np.stack([handle["imu"][k] for k in train_runs]).astype(np.float64)
        mean, std = imu.reshape(-1, *imu.shape[2:]).mean(0), imu.reshape(-1, *imu.shape[2:]).std(0)
        for i in range(0, len(windows), 5):
            k, s = windows.locate(i)
            window, raw_window = windows[i], raw[i]
            stored = handle["imu"][k, s : s + 10].astype(np.float64)
            expected = (stored - mean) / np.where(std > 0, std, 1.0)
            np.testing.assert_allclose(window["imu"], expected, rtol=1e-5, atol=1e-5)
            np.testing.assert_array_equal(as_string[i]["imu"], window["imu"])
            np.testing.assert_array_equal(everything[i]["imu"], window["imu"])
            np.testing.assert_array_equal(window["tau"], handle["tau"][k, s : s + 10])  # raw
            np.testing.assert_array_equal(window["senSenDH"], handle["senSenDH"][k])
            np.testing.assert_array_equal(raw_window["imu"], handle["imu"][k, s : s + 10])
            assert window["link_types"].dtype == np.int64  # a label: never normalised
    assert "normalised=('imu',)" in repr(windows)


def test_read_cache_gives_the_stored_numbers(dataset: Path) -> None:
    with DatasetReader(dataset) as reader:
        cached = reader.windows(10, 3, names=("senSen", "tau", "imu_mount"))
        direct = reader.windows(10, 3, names=("senSen", "tau", "imu_mount"))
    direct.cache_runs = 0
    cached.cache_runs = 2
    order = np.random.default_rng(4).permutation(len(cached))
    for i in order[:60].tolist():
        window = cached[i]
        for name in ("senSen", "tau", "imu_mount"):
            np.testing.assert_array_equal(window[name], direct[i][name])
        window["tau"][:] = 1e9  # a window changed in place leaves the cached run as stored
        window["imu_mount"][:] = 1e9
        np.testing.assert_array_equal(cached[i]["tau"], direct[i]["tau"])
        np.testing.assert_array_equal(cached[i]["imu_mount"], direct[i]["imu_mount"])
    assert len(cached._cache) <= 2
    copy = pickle.loads(pickle.dumps(cached))
    assert len(copy._cache) == 0 and copy.cache_runs == 2
