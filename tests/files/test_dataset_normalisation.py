"""Normalisation with statistics held in memory, and whole runs as windows: each window against
the run's arrays read with h5py and normalised here with NumPy."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.apps.dataset.generate import generate_dataset
from aaria_pin.errors import ParameterError
from aaria_pin.files.dataset.normalisation import given_statistics
from aaria_pin.files.dataset.reader import DatasetReader
from aaria_pin.files.dataset.statistics import names_statistics
from aaria_pin.files.dataset.windows import WindowCut


@pytest.fixture(scope="module")
def files(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """Two data sets of random DH arms (5 and 3 runs of 0.2 s), no statistics stored."""
    root = tmp_path_factory.mktemp("normalisation")
    generate_dataset(root / "a.h5", DhDatasetSpec(n_runs=5, seed=3, duration=0.2), workers=1)
    generate_dataset(root / "b.h5", DhDatasetSpec(n_runs=3, seed=4, duration=0.2), workers=1)
    return root / "a.h5", root / "b.h5"


def _numpy_statistics(path: Path, name: str, runs: list[int]) -> tuple[np.ndarray, np.ndarray]:
    with h5py.File(path, "r") as handle:
        values = np.stack([handle[name][k] for k in runs]).astype(np.float64)
    flat = values.reshape(-1, *values.shape[2:])
    return flat.mean(axis=0), flat.std(axis=0)


def test_windows_normalised_with_another_data_sets_statistics(files: tuple[Path, Path]) -> None:
    first, second = files
    mean, std = _numpy_statistics(first, "imu", list(range(5)))
    with DatasetReader(first) as reader:
        statistics = reader.statistics(("imu", "tau"), split=None)  # computed, not stored
    with DatasetReader(second) as reader:
        assert "statistics" not in reader.handle  # no stored statistics needed
        windows = reader.windows(7, names=("imu", "tau"), normalise=("imu",), statistics=statistics)
        assert windows.statistics is not None and set(windows.statistics) == {"imu"}
        every = reader.windows(7, names=("imu", "tau"), normalise=True, statistics=statistics)
        with pytest.raises(ParameterError) as caught:
            reader.windows(7, names=("imu", "q"), normalise=True, statistics=statistics)
        assert caught.value.parameter == "statistics" and "'q'" in str(caught.value)
        assert "\n" not in str(caught.value)
    with h5py.File(second, "r") as handle:
        for i in range(len(windows)):
            k, s = windows.locate(i)
            stored = handle["imu"][k, s : s + 7].astype(np.float64)
            expected = (stored - mean) / np.where(std > 0, std, 1.0)
            np.testing.assert_allclose(windows[i]["imu"], expected, rtol=1e-5, atol=1e-5)
            np.testing.assert_array_equal(windows[i]["tau"], handle["tau"][k, s : s + 7])
            np.testing.assert_array_equal(every[i]["imu"], windows[i]["imu"])
            assert not np.array_equal(every[i]["tau"], windows[i]["tau"])


def test_statistics_with_their_counts_are_taken_too(files: tuple[Path, Path]) -> None:
    first, _ = files
    with DatasetReader(first) as reader:
        cut = WindowCut(1, 1, ("imu",), {}, frozenset(), 1)
        triples = names_statistics(reader.handle, cut, np.arange(5))
        pairs = reader.statistics(("imu",), split=None)
        a = reader.windows(7, names=("imu",), normalise=True, statistics=triples)
        b = reader.windows(7, names=("imu",), normalise=True, statistics=pairs)
        np.testing.assert_array_equal(a[3]["imu"], b[3]["imu"])
    chosen = given_statistics(("imu",), triples)
    assert set(chosen) == {"imu"} and len(chosen["imu"]) == 2
    assert given_statistics((), {}) == {}


def test_whole_runs_are_one_window_each(files: tuple[Path, Path]) -> None:
    first, _ = files
    mean, std = _numpy_statistics(first, "imu", [0, 1])
    statistics = {"imu": (mean, std)}
    names = ("imu", "senSen", "link_types", "inertial_parameters")
    with DatasetReader(first) as reader:
        runs = reader.windows(None, names=names, normalise=("imu",), statistics=statistics)
        train = reader.windows(None, names=("q",), split="train")
        assert len(train) == len(reader.split_runs("train"))
        assert runs.length == reader.samples and runs.windows_per_run == 1
        with pytest.raises(ParameterError) as caught:
            reader.windows(reader.samples + 1)
        assert caught.value.parameter == "length" and "None" in str(caught.value)
        iterated = list(runs)
    assert len(runs) == 5 and [k for k, _, _ in iterated] == list(range(5))
    with h5py.File(first, "r") as handle:
        for k in range(5):
            window = runs[k]
            assert int(window["run"]) == k and int(window["start"]) == 0
            expected = (handle["imu"][k].astype(np.float64) - mean) / np.where(std > 0, std, 1)
            np.testing.assert_allclose(window["imu"], expected, rtol=1e-5, atol=1e-5)
            np.testing.assert_array_equal(window["senSen"][:, 0], handle["time"][k])
            np.testing.assert_array_equal(
                window["inertial_parameters"], handle["inertial_parameters"][k]
            )
            np.testing.assert_array_equal(iterated[k][2]["imu"], window["imu"])
