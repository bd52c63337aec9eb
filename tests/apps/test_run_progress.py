"""A driven run's progress line: on a terminal after half a second, never in a log."""

from __future__ import annotations

import io

import pytest

from aaria_pin.apps import run_progress as module
from aaria_pin.apps.run_progress import SHOW_AFTER, run_progress


class Terminal(io.StringIO):
    """A stream that says it is a terminal."""

    def isatty(self) -> bool:
        return True


def test_a_log_gets_no_progress() -> None:
    assert run_progress(io.StringIO()) is None


def test_a_short_integration_shows_nothing_a_long_one_counts_to_the_end(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    clock = [100.0]
    monkeypatch.setattr(module.time, "perf_counter", lambda: clock[0])
    screen = Terminal()
    progress = run_progress(screen)
    assert progress is not None
    progress(10, 1000)
    assert screen.getvalue() == ""  # under SHOW_AFTER: silent
    clock[0] += SHOW_AFTER + 0.1
    progress(420, 1000)
    assert screen.getvalue() == "\raaria: integrating 42% (420/1,000 samples, 0.6 s)"
    progress(1000, 1000)
    assert screen.getvalue().endswith("100% (1,000/1,000 samples, 0.6 s)\n")


def test_a_failed_integration_ends_its_line(monkeypatch: pytest.MonkeyPatch) -> None:
    clock = [0.0]
    monkeypatch.setattr(module.time, "perf_counter", lambda: clock[0])
    screen = Terminal()
    progress = run_progress(screen)
    assert progress is not None
    clock[0] = SHOW_AFTER + 1
    progress(5, 100)
    module.end_progress_line()  # what the CLI does before it prints the error
    module.end_progress_line()  # once only
    assert screen.getvalue().endswith("samples, 1.5 s)\n")
