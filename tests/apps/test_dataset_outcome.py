"""What a finished data-set job says (``apps/dataset/outcome``)."""

from __future__ import annotations

from pathlib import Path

from aaria_pin.apps.dataset.job import DatasetReport
from aaria_pin.apps.dataset.outcome import job_outcome


def test_a_job_with_a_remade_and_a_failed_run() -> None:
    report = DatasetReport(Path("ds.h5"), 3, 4, {2: "boom"}, 1.25, shards=2, remade=(1,))
    text, failures = job_outcome(report, 5, resume=True)
    assert text == (
        "run 1 was damaged; re-made\n"
        "wrote ds.h5: 4/5 runs complete (3 in this job, 2 shards, 1.2 s)"
    )
    assert failures == ["run 2 failed: boom", "failed runs: [2]"]


def test_a_resumed_complete_file_has_nothing_to_do() -> None:
    report = DatasetReport(Path("ds.h5"), 0, 5, {}, 0.1)
    assert job_outcome(report, 5, resume=True) == (
        "ds.h5: already complete (5/5 runs); nothing to do",
        [],
    )
    assert job_outcome(report, 5, resume=False)[0].startswith("wrote ds.h5: 5/5 runs complete")
