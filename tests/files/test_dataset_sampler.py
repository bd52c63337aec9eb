"""The run-block sampler: every window once an epoch, seeded, blocks of runs, one read a run."""

from __future__ import annotations

import pickle
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.apps.dataset.generate import generate_dataset
from aaria_pin.errors import ParameterError
from aaria_pin.files.dataset.reader import DatasetReader
from aaria_pin.files.dataset.sampler import RunBlockSampler


@pytest.mark.parametrize(("runs", "per_run", "block"), [(7, 5, 3), (4, 1, 8), (1, 9, 1), (0, 4, 2)])
def test_every_window_once_an_epoch_in_blocks_of_runs(runs: int, per_run: int, block: int) -> None:
    sampler = RunBlockSampler(runs, per_run, block, seed=3)
    for epoch in range(3):
        sampler.set_epoch(epoch)
        order = list(sampler)
        assert len(order) == len(sampler) == runs * per_run
        assert sorted(order) == list(range(runs * per_run))
        run_of = [i // per_run for i in order]
        for first in range(0, len(order), block * per_run):  # a block: `block` whole runs
            part = run_of[first : first + block * per_run]
            assert len(set(part)) == min(block, runs - first // per_run)
            assert all(part.count(k) == per_run for k in set(part))


def test_order_is_reproducible_from_seed_and_epoch_and_differs_otherwise() -> None:
    orders = {
        (seed, epoch): RunBlockSampler(20, 10, 4, seed=seed).order(epoch)
        for seed in (0, 1)
        for epoch in (0, 1)
    }
    again = RunBlockSampler(20, 10, 4, seed=0)
    np.testing.assert_array_equal(list(again), orders[0, 0])
    again.set_epoch(1)
    np.testing.assert_array_equal(list(again), orders[0, 1])
    np.testing.assert_array_equal(pickle.loads(pickle.dumps(again)).order(), orders[0, 1])
    values = [tuple(order.tolist()) for order in orders.values()]
    assert len(set(values)) == 4
    assert orders[0, 0].tolist() != sorted(orders[0, 0].tolist())  # shuffled within blocks


def test_consecutive_windows_share_a_run_about_once_a_block() -> None:
    runs, per_run, block = 40, 37, 8
    sampler = RunBlockSampler(runs, per_run, block, seed=0)
    same = [np.mean(np.diff(sampler.order(e) // per_run) == 0) for e in range(20)]
    expected = (per_run - 1) / (block * per_run - 1)  # the docstring's figure (1/G)
    assert abs(float(np.mean(same)) - expected) < 0.02


def test_bad_arguments() -> None:
    cases: list[tuple[dict[str, Any], str]] = [
        ({"n_runs": -1, "windows_per_run": 3}, "n_runs"),
        ({"n_runs": 3, "windows_per_run": 3, "runs_per_block": 0}, "runs_per_block"),
        ({"n_runs": 3, "windows_per_run": 3, "seed": -2}, "seed"),
        ({"n_runs": 3, "windows_per_run": 2.5}, "windows_per_run"),
    ]
    for kwargs, parameter in cases:
        with pytest.raises(ParameterError) as caught:
            RunBlockSampler(**kwargs)
        assert caught.value.parameter == parameter
    with pytest.raises(ParameterError) as caught:
        RunBlockSampler(3, 3).set_epoch(-1)
    assert caught.value.parameter == "epoch"


def test_a_shuffled_epoch_reads_each_run_once(tmp_path: Path) -> None:
    path = tmp_path / "ds.h5"
    generate_dataset(path, DhDatasetSpec(n_runs=3, seed=1, duration=0.2), workers=1)
    with DatasetReader(path) as reader:
        windows = reader.windows(4, 2, names=("senSen", "tau"))
    windows.cache_runs = 2
    sampler = RunBlockSampler.for_windows(windows, seed=7)
    assert sampler.runs_per_block == 2 and len(sampler) == len(windows)
    expected = sorted((k, s) for k, s, _ in windows)
    windows.close()  # an empty cache
    reads: list[tuple[str, int]] = []
    stored = windows._stored

    def counted(dataset: Any, name: str, run: int, samples: slice) -> np.ndarray:
        reads.append((name, run))
        return stored(dataset, name, run, samples)

    windows._stored = counted  # type: ignore[method-assign]
    seen = [(int(w["run"]), int(w["start"])) for w in map(windows.__getitem__, sampler)]
    assert sorted(seen) == expected
    per_source = {name for name, _ in reads}
    assert len(reads) == 3 * len(per_source)  # each run's arrays read once in the epoch


def test_batches_handed_to_two_workers_in_turn_cover_the_epoch(tmp_path: Path) -> None:
    path = tmp_path / "ds.h5"
    generate_dataset(path, DhDatasetSpec(n_runs=3, seed=2, duration=0.2), workers=1)
    with DatasetReader(path) as reader:
        windows = reader.windows(5, 3, names=("imu", "link_types"))
    expected = sorted((k, s) for k, s, _ in windows)
    sampler = RunBlockSampler.for_windows(windows, runs_per_block=2, seed=4)
    order = list(sampler)
    batches = [order[i : i + 4] for i in range(0, len(order), 4)]  # as a DataLoader batches
    workers = [pickle.loads(pickle.dumps(windows)) for _ in range(2)]  # each its own copy
    seen = [
        (int(w["run"]), int(w["start"]))
        for b, batch in enumerate(batches)
        for w in map(workers[b % 2].__getitem__, batch)  # batches to the workers in turn
    ]
    assert sorted(seen) == expected and len(seen) == len(set(seen))
