"""What native (C and C++) code prints to the process's standard error, captured.

Some libraries under the toolkit print their complaints straight to file descriptor 2, past
Python's ``sys.stderr``: urdfdom, the URDF reader inside Pinocchio, writes
``Error:   material 'm' is not unique.`` and ``at line 159 in .../model.cpp`` before its caller
sees an exception. :func:`captured_stderr` points descriptor 2 at a temporary file for the
length of a block and always points it back (``finally``); the caller then folds the text into
its own one-line error (:meth:`CapturedText.folded`), so a command prints one line only.

Descriptor 2 belongs to the whole process: whatever any thread writes to it during the block
is captured too. Keep the block to the one native call. Blocks of different threads take turns
(a lock), so each restores the descriptor it found; nested blocks of one thread each capture
their own part.
"""

from __future__ import annotations

import os
import re
import sys
import tempfile
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass

__all__ = ["CapturedText", "captured_stderr"]

_SOURCE_LINE = re.compile(r"^at line \d+ in \S+$")
"""urdfdom's second line of each message: where in its C++ source it was raised."""

_TURN = threading.RLock()
"""Held while descriptor 2 is redirected (re-entrant: a block may nest in another)."""


@dataclass
class CapturedText:
    """The text native code wrote to standard error within a :func:`captured_stderr` block.

    Attributes:
        text: everything written, as UTF-8 (undecodable bytes replaced); set when the block
            ends
    """

    text: str = ""

    def folded(self) -> str:
        """The text as one line: its messages joined by ``"; "``, without source locations.

        Each message's leading ``Error:`` and the lines that give a place in the library's own
        source (``at line 103 in .../model.cpp``) are dropped; runs of white space become one
        space.

        Returns:
            The line ("" when nothing was written).
        """
        messages = []
        for raw in self.text.splitlines():
            line = " ".join(raw.split())
            if not line or _SOURCE_LINE.match(line):
                continue
            line = re.sub(r"^(?:Error|Warning):\s*", "", line)
            if line:
                messages.append(line.rstrip("."))
        return "; ".join(messages)


@contextmanager
def captured_stderr() -> Iterator[CapturedText]:
    """Capture what is written to file descriptor 2 within the block.

    Python's ``sys.stderr`` is flushed first, so nothing written before the block is taken.
    When descriptor 2 cannot be duplicated (closed) or no temporary file can be made, nothing
    is captured and the block runs as it is.

    Yields:
        The captured text, filled in when the block ends (also when it raises).
    """
    captured = CapturedText()
    try:
        sys.stderr.flush()
    except (AttributeError, OSError, ValueError):  # no or a closed sys.stderr
        pass
    try:
        sink = tempfile.TemporaryFile()
    except OSError:  # no temporary folder: the block runs uncaptured
        yield captured
        return
    with sink, _TURN:
        try:
            saved = os.dup(2)
        except OSError:
            yield captured
            return
        try:
            os.dup2(sink.fileno(), 2)
            yield captured
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            sink.seek(0)
            captured.text = sink.read().decode("utf-8", errors="replace")
