"""matplotlib on a file-only backend, or a clear error where it is not installed."""

from __future__ import annotations

from typing import Any

from aaria_pin.errors import OutputFileError


def pyplot() -> Any:
    """``matplotlib.pyplot`` with the Agg backend (PNG files, no screen).

    Raises:
        OutputFileError: matplotlib is not installed, so no picture can be written
            (``parameter="path"``, the picture's).
    """
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise OutputFileError(
            "plots need matplotlib, which is not installed; allowed: pip install 'aaria-pin[plot]'",
            parameter="path",
        ) from None
    return plt
