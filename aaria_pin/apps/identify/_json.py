"""Numbers for JSON reports (JSON has no NaN)."""

from __future__ import annotations

import numpy as np

__all__ = ["json_number"]


def json_number(value: float) -> float | None:
    """A finite number as a float, anything else (NaN, ±inf) as None."""
    return float(value) if np.isfinite(value) else None
