"""Reading a numeric table and refusing a wrong shape or a non-finite entry, naming the cell."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.core.se3 import Array
from aaria_pin.errors import TableError


def finite_table(
    table: ArrayLike,
    columns: Sequence[str],
    what: str,
    rows: Sequence[int] | None = None,
    *,
    parameter: str = "table",
) -> Array:
    """The table as a new 2-D float array with ``len(columns)`` columns, all entries finite.

    Args:
        table: the table
        columns: column names, for messages
        what: the table's name, for messages
        rows: the allowed row counts (any when None)
        parameter: the caller's parameter the table came in by, for the error's ``parameter``

    Raises:
        TableError: not numeric, a wrong shape, or a NaN / inf (naming its row and column).
    """
    try:
        arr = np.array(table, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TableError(
            f"{what}: not a numeric table ({exc})",
            parameter=parameter,
            value=type(table).__name__,
            allowed="a numeric table",
        ) from None
    width = len(columns)
    if arr.ndim != 2 or arr.shape[1] != width or (rows is not None and arr.shape[0] not in rows):
        expected = (
            " or ".join(f"{r} × {width}" for r in rows) if rows else f"rows × {width} columns"
        )
        raise TableError(
            f"{what}: shape {arr.shape} is not allowed; expected {expected}",
            parameter=parameter,
            value=arr.shape,
            element="shape",
        )
    bad = np.argwhere(~np.isfinite(arr))
    if bad.size:
        row, col = bad[0]
        raise TableError(
            f"{what}: row {row + 1}, column {col + 1} ({columns[col]}) is {arr[row, col]};"
            " allowed: a finite number",
            parameter=parameter,
            value=float(arr[row, col]),
            element=f"row {row + 1}, column {col + 1} ({columns[col]})",
        )
    return arr
