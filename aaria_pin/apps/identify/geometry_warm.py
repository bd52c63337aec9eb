"""A warm start of the kinematic identification: a given table (a prediction, a prior estimate).

:func:`~aaria_pin.apps.identify.geometry.identify_kinematics` takes an optional start table
(8 × 5, the layout of ``senSenDH``: rows 1-6 the modules, 7 the tool, 8 the base; the link type
in column 5), checked here (:func:`checked_start`). What it does with it:

1. the link types: the detection from the gyroscopes
   (:func:`~aaria_pin.apps.identify.geometry_start.detect_kind`) stays where it is sure; where
   its statistic is within :data:`UNSURE` of its threshold 0.5 and the table's type differs
   (:func:`start_kinds`), the closed-form start is built under both sets of types and the
   smaller residual decides (:func:`closed_form_choice`): the data, never the table alone.
   Which modules move is the encoders' (an empty row of the table for a moving module is not
   obeyed);
2. the table's angles and lengths, with the IMU mounts fitted to them
   (:func:`~aaria_pin.apps.identify.geometry_start.table_start`), are the first start: walked
   and fitted as the closed-form start is. A fit that ends at the noise floor is the result:
   the closed-form start (unless item 1 built it) and the other starts are not computed;
3. else the usual starts follow (the closed-form one, then the others), the smallest residual
   kept: a wrong table costs one fit, never the result.

What a warm start can change against the cold one: the fit's prior (the faint pull towards the
start, :class:`~aaria_pin.apps.identify.geometry_fit.WeightedFit`) is anchored at the table,
so the combinations the signals hardly determine follow the start table, not the data, and
along the exact null directions (the equivalent tables,
:func:`~aaria_pin.apps.identify.geometry_fit.deficiencies`) the entries follow it too.

Measured (the standard ``structure`` task's 20 test arms, 10 s at 100 Hz with noise;
``docs/guide/bench-tasks.md``): a far table pulls run 71's tool tip from 12.9 mm (cold) to
0.32 m (the earlier model's ``big2`` table) at the same residual. Anchoring the prior at the
closed-form start instead was tried: run 71 from ``big2`` then gave 12.89 mm, the cold figure,
and today's learned tables gave the cold figure on run 9 too (13.7 mm against 25 mm; median
4.583 mm), but it was not kept: the closed-form start costs about 70 s of CPU on those 20 arms
(a grid of candidates module by module; 0.1 to 25 s an arm, measured with the fit stopped
after it), so the warm run took 265 s of CPU against the cold 161 s; and on a noise-free run
(``aaria-fig3``) the closed-form start lies on another branch of equivalent tables, whose pull
keeps the true table's fit off the exact noise floor. The link types are the detection's
wherever it is sure: it is right on every module of those arms, the learned tables on 82 % to
97.5 %; the tool tip's error is the noise's (the truth as the start gives the cold median,
4.6 mm).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.apps.identify.geometry_model import ArmLayout, KinematicData, predict_signals
from aaria_pin.apps.identify.geometry_start import start_parameters
from aaria_pin.apps.identify.geometry_structure import length_indices
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = ["UNSURE", "checked_start", "closed_form_choice", "start_kinds"]

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


def closed_form_choice(
    layouts: list[ArmLayout], data: KinematicData, measured: Array, weights: Array
) -> tuple[int, Array]:
    """The closed-form start under each layout (link types), the smallest residual's.

    With a start table the layouts are the detection's and, where the table's link types
    differ from the detection's on unsure modules (:func:`start_kinds`), the table's: the data
    decide between them, not the table. The start found anchors the fits' prior.

    Args:
        layouts: the arm's modules and IMUs, one per candidate set of link types
        data: the base motion and joint motions (a subsample of the run)
        measured: the measured signals of :attr:`ArmLayout.imus`, T × S × 6
        weights: the weight of each signal, 6

    Returns:
        The index of the layout kept (the first on a tie) and its closed-form start.
    """
    starts = [
        start_parameters(lay, data, measured, weights, length_indices(lay)) for lay in layouts
    ]
    costs = [
        float(np.sum(((predict_signals(x, lay, data)[0] - measured) * weights) ** 2))
        for x, lay in zip(starts, layouts, strict=True)
    ]
    chosen = int(np.argmin(costs))
    return chosen, starts[chosen]
