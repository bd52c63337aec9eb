"""DatasetJob: how a data set is made, checked before anything is touched (apps/dataset/job.py)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.apps.dataset.generate import generate_dataset
from aaria_pin.apps.dataset.job import DatasetJob, DatasetReport
from aaria_pin.errors import ParameterError


@pytest.mark.parametrize(
    ("fields", "parameter", "pattern"),
    [
        ({"scheduler": "  "}, "scheduler", "scheduler is '  '; allowed: a Dask"),
        ({"shards": "folder"}, "shards", "--shards needs --scheduler"),
        ({"workers": 0}, "workers", "workers is 0; allowed: >= 1"),
        ({"workers": 2, "scheduler": "tcp://h:8786"}, "workers", "not both"),
    ],
)
def test_a_job_no_data_set_can_run_is_refused(
    fields: dict[str, object], parameter: str, pattern: str
) -> None:
    with pytest.raises(ParameterError, match=pattern) as refused:
        DatasetJob(**fields)  # type: ignore[arg-type]
    assert refused.value.parameter == parameter


def test_local_workers_are_the_cores_unless_given() -> None:
    assert DatasetJob(workers=3).local_workers == 3
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    assert DatasetJob().local_workers == cores


def test_keywords_replace_the_fields_of_a_job(tmp_path: Path) -> None:
    spec = DhDatasetSpec(n_runs=2, duration=0.1, seed=1)
    seen: list[tuple[int, int]] = []
    job = DatasetJob(workers=1, command="first")
    report = generate_dataset(
        tmp_path / "ds.h5", spec, job, progress=lambda done, total, _: seen.append((done, total))
    )
    assert isinstance(report, DatasetReport) and (report.written, report.complete) == (2, 2)
    assert seen == [(1, 2), (2, 2)]
    with pytest.raises(ParameterError, match="workers is 0"):  # checked before the file
        generate_dataset(tmp_path / "other.h5", spec, job, workers=0)
    assert not (tmp_path / "other.h5").exists()
