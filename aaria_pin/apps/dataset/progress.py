"""A data-set job's reports to a person: its estimate once, its progress as a bar or lines.

The callbacks :class:`~aaria_pin.apps.dataset.job.DatasetJob` takes (``progress``,
``estimate``), written to stderr; a Python caller gets the same reports as ``aaria dataset``.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import click

if TYPE_CHECKING:
    from aaria_pin.apps.dataset.job import DatasetEstimate


PROGRESS_EVERY = 10.0
"""Seconds between two progress lines of a batch job's log, by default [s]."""


def progress_report(
    quiet: bool, progress_every: float | None = None
) -> Callable[[int, int, float], None] | None:
    """The progress report: a bar on a terminal, else a plain line every ``progress_every`` s.

    A batch job's log (stderr not a terminal) gets lines ``aaria: 120/10000 runs, 35.2 runs/s,
    ETA 281 s`` at most every ``progress_every`` seconds, and the last one when the job ends; a
    terminal gets click's progress bar.

    Args:
        quiet: no report at all (returns ``None``)
        progress_every: seconds between two lines [s] (None: :data:`PROGRESS_EVERY`)

    Returns:
        The callback ``(done, total, seconds)``, or ``None`` when quiet.

    Raises:
        OptionConflictError: ``progress_every`` given with ``quiet`` (it would be ignored).
    """
    from aaria_pin.core.conflicts import OptionConflictError

    if quiet and progress_every is not None:
        raise OptionConflictError(parameter="progress_every", other="quiet", given_with=True)
    every = PROGRESS_EVERY if progress_every is None else progress_every
    if quiet:
        return None
    if sys.stderr.isatty():
        return _bar()
    last = [-float("inf")]

    def line(done: int, total: int, seconds: float) -> None:
        if seconds - last[0] >= every or done == total:
            last[0] = seconds
            rate = done / seconds if seconds > 0 else 0.0
            eta = (total - done) / rate if rate > 0 else float("nan")
            click.echo(f"aaria: {done}/{total} runs, {rate:.1f} runs/s, ETA {eta:.0f} s", err=True)

    return line


def _bar() -> Callable[[int, int, float], None]:
    """A progress bar (click's) on stderr, made at the first report (when the total is known)."""
    bars: list[Any] = []

    def show(done: int, total: int, seconds: float) -> None:
        if not bars:
            bar = click.progressbar(
                length=total, label="runs", show_pos=True, item_show_func=_shown, file=sys.stderr
            )
            bars.append(bar.__enter__())
        bars[0].update(done - bars[0].pos, f"{done / seconds if seconds > 0 else 0:.1f} runs/s")
        if done >= total:
            bars[0].__exit__(None, None, None)

    return show


def _shown(rate: str | None) -> str | None:
    """The bar's text after the count: the rate (none before the first run)."""
    return rate


def estimate_report(quiet: bool) -> Callable[[DatasetEstimate], None] | None:
    """The estimate report: a job's estimated size and time, printed once (to stderr).

    Args:
        quiet: no report (returns ``None``)

    Returns:
        The callback taking the :class:`~aaria_pin.apps.dataset.job.DatasetEstimate`, or ``None``.
    """
    if quiet:
        return None

    def show(estimate: DatasetEstimate) -> None:
        seconds = "under 1 s" if estimate.seconds < 1 else f"about {estimate.seconds:.0f} s"
        click.echo(
            f"aaria: estimate for {estimate.runs} runs: {_size(estimate.bytes)}, {seconds} "
            f"(the runs, not start-up) on {estimate.workers} workers "
            f"({estimate.run_seconds * 1e3:.0f} ms a run)",
            err=True,
        )

    return show


def _size(count: float) -> str:
    """A byte count as a person reads it (``12.3 MB``)."""
    for unit in ("B", "kB", "MB", "GB"):
        if count < 1000:
            return f"{count:.0f} {unit}" if unit == "B" else f"{count:.1f} {unit}"
        count /= 1000
    return f"{count:.1f} TB"
