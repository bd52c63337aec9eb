"""A driven run's progress on a terminal: one line that counts the samples integrated.

A torque-driven or closed-loop run integrates its whole motion before it writes anything
(:func:`~aaria_pin.core.forward.forward_simulate`, :func:`~aaria_pin.core.control.
closed_loop_simulate`); a long one (an hour of simulated time at 1 kHz control) takes minutes.
:func:`run_progress` is the callback those take (``progress``): on a terminal it writes
``aaria: integrating 42% (420,000/1,000,001 samples, 3.1 s)``, rewritten in place, once the
integration has lasted :data:`SHOW_AFTER` seconds (a short run shows nothing), and ends the line
when the integration ends (or, when it fails, :func:`end_progress_line` before the error); in a
log (stderr not a terminal) it writes nothing.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from typing import TextIO

__all__ = ["SHOW_AFTER", "end_progress_line", "run_progress"]

SHOW_AFTER = 0.5
"""Wall time an integration runs before its progress line appears [s]."""

_open: list[TextIO] = []
"""The stream whose progress line is not ended yet (at most one)."""


def end_progress_line() -> None:
    """End a progress line a failed integration left open (the error then starts a line)."""
    while _open:
        stream = _open.pop()
        stream.write("\n")
        stream.flush()


def run_progress(stream: TextIO | None = None) -> Callable[[int, int], None] | None:
    """The progress callback of a driven run on a terminal (None when ``stream`` is none).

    Args:
        stream: where the line goes (None: stderr)

    Returns:
        ``progress(done, samples)``, or None when the stream is not a terminal.
    """
    out = sys.stderr if stream is None else stream
    if not out.isatty():
        return None
    started = time.perf_counter()
    shown = [False]

    def progress(done: int, samples: int) -> None:
        seconds = time.perf_counter() - started
        if seconds < SHOW_AFTER and not shown[0]:
            return
        shown[0] = True
        out.write(
            f"\raaria: integrating {100 * done // samples}% ({done:,}/{samples:,} samples, "
            f"{seconds:.1f} s)"
        )
        if out not in _open:
            _open.append(out)
        if done >= samples:
            end_progress_line()
        out.flush()

    return progress
