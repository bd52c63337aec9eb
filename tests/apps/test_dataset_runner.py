"""Local workers of a data-set job (apps/dataset/runner.py): tasks of whole runs."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

from aaria_pin.apps.dataset import runner
from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.apps.dataset.generate import generate_dataset
from aaria_pin.apps.dataset.runner import task_runs

SHORT = {"duration": 0.5, "rate": 100.0}


def _assert_same(a: Path, b: Path) -> None:
    """Every stored array of two data set files, equal bit for bit."""
    with h5py.File(a, "r") as left, h5py.File(b, "r") as right:
        assert sorted(left) == sorted(right)
        for name in left:
            np.testing.assert_array_equal(right[name][()], left[name][()], err_msg=name)


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("ref") / "ref.h5"
    generate_dataset(path, DhDatasetSpec(n_runs=24, seed=7, **SHORT), workers=1)
    return path


def test_runs_per_task_do_not_change_the_arrays(
    reference: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    assert task_runs(51) == 8  # the reference: eight runs of 0.5 s a task
    monkeypatch.setattr(runner, "TASK_SAMPLES", 1)  # one run a task
    assert task_runs(51) == 1
    path = tmp_path / "single.h5"
    generate_dataset(path, DhDatasetSpec(n_runs=24, seed=7, **SHORT), workers=2)
    _assert_same(reference, path)


def test_runs_per_task_follow_the_run_length() -> None:
    assert [task_runs(n) for n in (1, 100, 1000, 1500, 4000, 10**6)] == [8, 8, 4, 2, 1, 1]
