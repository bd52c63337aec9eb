"""The data-set job's reports: its estimate once, its progress as lines in a log."""

from __future__ import annotations

import pytest

from aaria_pin.apps.dataset.job import DatasetEstimate
from aaria_pin.apps.dataset.progress import estimate_report, progress_report


def test_quiet_gives_no_reports() -> None:
    assert progress_report(True) is None and estimate_report(True) is None


def test_a_progress_interval_with_quiet_is_refused_naming_both() -> None:
    from aaria_pin.core.conflicts import OptionConflictError

    with pytest.raises(OptionConflictError) as error:
        progress_report(True, 1.0)
    assert error.value.parameter == "progress_every" and "quiet" in str(error.value)


def test_progress_lines_come_every_so_often_and_at_the_end(
    capsys: pytest.CaptureFixture[str],
) -> None:
    report = progress_report(False, 10.0)  # stderr is captured: not a terminal, so lines
    assert report is not None
    for done, seconds in [(1, 1.0), (2, 5.0), (30, 11.0), (31, 12.0), (40, 16.0)]:
        report(done, 40, seconds)
    lines = capsys.readouterr().err.splitlines()
    # a line at 1 s, none at 5 s or 12 s (under 10 s since the last), one at 11 s, the last one
    assert lines == [
        "aaria: 1/40 runs, 1.0 runs/s, ETA 39 s",
        "aaria: 30/40 runs, 2.7 runs/s, ETA 4 s",  # 30 / 11 s; 10 left / (30 / 11) = 3.7 s
        "aaria: 40/40 runs, 2.5 runs/s, ETA 0 s",
    ]


def test_the_estimate_is_one_line_in_readable_units(capsys: pytest.CaptureFixture[str]) -> None:
    show = estimate_report(False)
    assert show is not None
    show(DatasetEstimate(runs=1000, bytes=2_345_678, seconds=42.4, workers=4, run_seconds=0.0124))
    assert capsys.readouterr().err == (
        "aaria: estimate for 1000 runs: 2.3 MB, about 42 s (the runs, not start-up) on 4 "
        "workers (12 ms a run)\n"
    )
