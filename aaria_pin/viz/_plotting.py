"""matplotlib on a file-only backend, or a clear error where it is not installed."""

from __future__ import annotations

from typing import Any

from aaria_pin.errors import ParameterError


def pyplot() -> Any:
    """``matplotlib.pyplot`` with the Agg backend (PNG files, no screen)."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise ParameterError(
            "plots need matplotlib, which is not installed; allowed: pip install 'aaria-pin[plot]'"
        ) from None
    return plt
