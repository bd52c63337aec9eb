"""A warm start of the kinematic identification: a given table (a prediction, a prior estimate).

:func:`~aaria_pin.apps.identify.geometry.identify_kinematics` takes an optional start table
(8 × 5, the layout of ``senSenDH``: rows 1-6 the modules, 7 the tool, 8 the base; the link type
in column 5), checked here (:func:`checked_start`). What it does with it:

1. the link types: the detection from the gyroscopes
   (:func:`~aaria_pin.apps.identify.geometry_start.detect_kind`) stays, except where its
   statistic is within :data:`UNSURE` of its threshold 0.5: there the table's type decides
   (:func:`start_kinds`). Which modules move is the encoders' (an empty row of the table for a
   moving module is not obeyed);
2. the table's angles and lengths, with the IMU mounts fitted to them
   (:func:`~aaria_pin.apps.identify.geometry_start.table_start`), are the first start: walked
   and fitted as the closed-form start is. A fit that ends at the noise floor is the result:
   the closed-form start and the other starts are not computed;
3. else the usual starts follow (the closed-form one, then the others), the smallest residual
   kept: a wrong table costs one fit, never the result.

Why this order (measured on the standard ``structure`` task's 20 test arms, 10 s at 100 Hz
with noise; ``docs/guide/bench-tasks.md``): the table's fit is tried first because a near table
(the truth) ends at the floor from it (7 arms looked at one by one), and the closed-form
start, a grid of candidates module by module, is then never built; the usual starts stay
behind it because a far table must not decide the result. The link types are the detection's
wherever it is sure: it is right on every module of those arms, the learned tables on 82 % to
97.5 %. What it buys is little there: the time is the final fit's (its bias splines on every
sample) and the other starts' on arms that end just above the floor from any start (run 98:
1.12 floors from the truth too), which a warm start does not shorten, and the tool tip's error
is the noise's (the truth as the start gives the cold median, 4.6 mm, in 55 s for the 20 arms
against the cold 80 s). Tables far off (the learned ones: 4.4 m off at the tool tip) mostly
still walk to the floor, in more iterations than the closed-form start needs (and pulled
towards the far table by the fit's prior): 158 s and 259 s (two models' tables), the same
link types, and on one arm whose fit hardly determines some lengths, the tool tip pulled
towards the far table (run 71: 12.9 mm cold, 48 mm and 0.32 m warm) at the same residual.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = ["UNSURE", "checked_start", "start_kinds"]

UNSURE = 0.25
"""A link-type statistic (about 1 revolute, 0 prismatic) within this of 0.5 is unsure."""

_KINDS = {1: "revolute", 2: "prismatic"}


def checked_start(table: ArrayLike) -> Array:
    """A start table checked: 8 × 5 real numbers, finite, link types (column 5) 0, 1 or 2.

    Args:
        table: the start table (``senSenDH`` layout; rows 1-6 modules, 7 tool, 8 base)

    Returns:
        The table as an 8 × 5 float array (a copy).

    Raises:
        ParameterError: another shape, a value that is not a finite real number, a link type
            (rows 1-6) other than 0, 1 or 2.
    """
    try:
        array = np.array(table, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(
            f"start is {type(table).__name__}; allowed: an 8 × 5 table of real numbers",
            parameter="start",
            value=type(table).__name__,
        ) from None
    if array.shape != (8, 5):
        raise ParameterError(
            f"start is a table of shape {array.shape}; allowed: 8 × 5 (senSenDH: rows 1-6 "
            "modules, 7 tool, 8 base)",
            parameter="start",
            value=array.shape,
        )
    if not np.isfinite(array).all():
        row, column = (int(i) for i in np.argwhere(~np.isfinite(array))[0])
        raise ParameterError(
            f"start row {row + 1}, column {column + 1} is {array[row, column]}; allowed: "
            "finite numbers",
            parameter="start",
            value=float(array[row, column]),
        )
    types = array[:6, 4]
    if not np.isin(types, (0.0, 1.0, 2.0)).all():
        row = int(np.argmin(np.isin(types, (0.0, 1.0, 2.0))))
        raise ParameterError(
            f"start row {row + 1}, column 5 (link type) is {types[row]:g}; allowed: 0, 1 or 2 "
            "(empty, revolute, prismatic)",
            parameter="start",
            value=float(types[row]),
        )
    return array


def start_kinds(
    modules: tuple[int, ...], detected: tuple[tuple[str, float], ...], table: Array
) -> tuple[tuple[str, ...], tuple[int, ...]]:
    """The joint kinds with a start table: the detection's, the table's where it is unsure.

    Args:
        modules: the moving modules (1-based rows)
        detected: per module the detected kind and its statistic (``detect_kind``)
        table: the checked start table

    Returns:
        The kinds, and the modules whose kind the table decided against the detection.
    """
    kinds: list[str] = []
    decided: list[int] = []
    for module, (kind, statistic) in zip(modules, detected, strict=True):
        given = _KINDS.get(int(table[module - 1, 4]))
        if given is not None and given != kind and abs(statistic - 0.5) < UNSURE:
            kind = given
            decided.append(module)
        kinds.append(kind)
    return tuple(kinds), tuple(decided)
