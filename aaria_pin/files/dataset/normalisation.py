"""Normalisation per field of a window dataset: which names, with which statistics.

Each name to normalise (:func:`normalised_names`: every name but the labels, none, or some
names) is centred on its per-channel mean and divided by its std (:func:`normalised`), the
statistics stored in the file for the training split
(:func:`~.statistics.training_statistics`) or held in memory (:func:`given_statistics`: another
data set's, runs simulated on demand); labels are never normalised.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping, Sequence
from typing import Any

import numpy as np

from aaria_pin.errors import ParameterError
from aaria_pin.files.dataset.labels import LABELS

__all__ = ["GivenStatistics", "Statistics", "given_statistics", "normalised", "normalised_names"]

Statistics = Mapping[str, tuple[np.ndarray, np.ndarray]]
"""Per-channel statistics by array name: ``(mean, std)``, each of the channel shape."""
GivenStatistics = Mapping[str, Sequence[Any]]
"""Statistics held in memory, by name: ``(mean, std)`` or ``(mean, std, count)``."""


def normalised(array: np.ndarray, mean: np.ndarray, std: np.ndarray) -> np.ndarray:
    """``(array - mean) / std`` in the array's floating type; a channel of zero std is only centred.

    A constant channel (the last row of a pose, an empty module's joint) has std 0: dividing by 1
    there, as scikit-learn's ``StandardScaler`` does, keeps it finite (zero).
    """
    dtype = array.dtype if np.issubdtype(array.dtype, np.floating) else np.dtype(np.float64)
    scale = np.where(std > 0.0, std, 1.0)
    return ((array - mean) / scale).astype(dtype, copy=False)


def normalised_names(normalise: bool | Collection[str], names: Sequence[str]) -> tuple[str, ...]:
    """The names of some windows to normalise, in their order.

    Args:
        normalise: True: every name but the labels (:mod:`.labels`, never normalised); False:
            none; a collection of names (a single name as a string): those
        names: the windows' names

    Raises:
        ParameterError: a name to normalise that is not among the names, or is a label.
    """
    if isinstance(normalise, bool):
        return tuple(name for name in names if name not in LABELS) if normalise else ()
    wanted = (normalise,) if isinstance(normalise, str) else tuple(normalise)
    bad = [name for name in wanted if name not in names or name in LABELS]
    if bad:
        allowed = [name for name in names if name not in LABELS]
        raise ParameterError(
            parameter="normalise",
            value=bad[0],
            allowed=f"True, False or names of the windows, labels apart ({', '.join(allowed)})",
        )
    return tuple(name for name in names if name in wanted)


def given_statistics(
    names: Sequence[str], statistics: GivenStatistics
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """The ``(mean, std)`` of some names from statistics held in memory.

    Args:
        names: the names to normalise
        statistics: by name, ``(mean, std)`` or ``(mean, std, count)`` (what
            :meth:`DatasetReader.statistics
            <aaria_pin.files.dataset.reader.DatasetReader.statistics>`,
            :func:`~.statistics.names_statistics`, ``OnlineRuns.statistics`` or a window
            dataset's ``statistics`` attribute give), of another data set as well

    Raises:
        ParameterError: no statistics of a name to normalise (named).
    """
    missing = [name for name in names if name not in statistics]
    if missing:
        raise ParameterError(
            f"statistics has none of {missing[0]!r}; allowed: (mean, std) of every name to"
            f" normalise ({', '.join(names)})",
            parameter="statistics",
            value=missing[0],
        )
    return {
        name: (
            np.asarray(statistics[name][0], dtype=np.float64),
            np.asarray(statistics[name][1], dtype=np.float64),
        )
        for name in names
    }
