"""Learning targets per run derived from what a data set file stores (no new data written).

A label is a name :meth:`DatasetReader.windows
<aaria_pin.files.dataset.reader.DatasetReader.windows>` and :meth:`DatasetReader.labels
<aaria_pin.files.dataset.reader.DatasetReader.labels>` accept beside the stored arrays and views:
its per-run value is computed from one stored per-run array (its ``source``) when the run is read,
and comes whole with every window, as a per-run constant does. A label exists in a file only when
its source is stored there (:func:`available_labels`); labels are never normalised.

================  ==============  =======  =========================================================
label             source          dtype    value (per run)
================  ==============  =======  =========================================================
``link_types``    ``senSenDH``    int64    ``(6,)``: the link type of modules 1–6, the DH table's
                                           fifth column: 0 empty, 1 revolute, 2 prismatic
                                           (:class:`aaria_pin.aaria.dh.LinkType`'s codes)
``empty_mask``    ``senSenDH``    bool     ``(6,)``: True where module 1–6 is empty (link type 0);
                                           its record columns (``q``, ``tau``…) are zeros
================  ==============  =======  =========================================================

The other targets are stored arrays already, read by their names: the extended DH table
``senSenDH`` (``8 × 5`` float64, ``[alpha [rad], a [m], theta [rad], d [m], link type]``, rows
1–6 modules, 7 the tool, 8 the base), the IMU mounts ``imu_mount`` (``S × 4 × 4`` float64, each
IMU's pose in its parent link's frame [m]), the joint torques ``tau`` (a series, ``length × n``
a window, N·m or N for a prismatic joint) and the standard inertial parameters
``inertial_parameters`` (``(n + 1) × 10`` float64, ``7 × 10`` for an Aaria arm: a row per joint
column, the body it moves, zeros for an empty module, then the base body; each row
``[m [kg], m·c [kg·m], I [kg·m²]]`` in Pinocchio's ``Inertia.toDynamicParameters`` order, about
the joint's origin; the tool is in the last joint's row), which data sets made after
aaria_pin 0.3.0 store (:mod:`aaria_pin.apps.dataset.inertial_table`; an older file does not have
it: its :attr:`DatasetReader.names <aaria_pin.files.dataset.reader.DatasetReader.names>` lack
it).

No label gives the inertial *base* parameters, as no fixed-shape vector of them means the same
from one run to the next: they are the combinations of the standard ones that the measurements
determine, and their number and coefficients depend on the arm (which modules are empty,
prismatic or revolute, the angles between their axes), on what is measured (the joint torques
alone, or the base wrench too) and on the motion (a base at rest, a run that does not excite
every direction); the set is found numerically, by a pivoted QR of the run's regressor
(:func:`aaria_pin.apps.identify.inertial_base.base_parameters`). They are
``basis.combination @ pi`` of the standard parameters ``pi`` (the guide's page "Reading data
sets and training" has the example).
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["LABELS", "MODULES", "Label", "available_labels", "derive_labels", "label_sources"]

MODULES = 6
"""Modules of an Aaria arm: the rows of the extended DH table holding a link type (1–6)."""


def _link_types(table: np.ndarray) -> np.ndarray:
    """Link types of modules 1–6 of an extended DH table (8 × 5), int64."""
    return np.rint(np.asarray(table)[:MODULES, 4]).astype(np.int64)


def _empty_mask(table: np.ndarray) -> np.ndarray:
    """Whether modules 1–6 of an extended DH table (8 × 5) are empty (link type 0)."""
    return _link_types(table) == 0


@dataclass(frozen=True)
class Label:
    """A per-run target computed from a stored per-run array.

    Attributes:
        source: the stored per-run array it is computed from
        derive: the computation, from the run's source array to the label
    """

    source: str
    derive: Callable[[np.ndarray], np.ndarray]


LABELS: Mapping[str, Label] = {
    "link_types": Label("senSenDH", _link_types),
    "empty_mask": Label("senSenDH", _empty_mask),
}
"""The labels by name (see the module docstring for their shapes, types and units)."""


def available_labels(stored: Collection[str]) -> tuple[str, ...]:
    """The labels whose source is among some stored arrays.

    Args:
        stored: the names of a file's stored per-run arrays
    """
    return tuple(name for name, label in LABELS.items() if label.source in stored)


def label_sources(names: Sequence[str]) -> tuple[str, ...]:
    """The names with each label replaced by its source (first occurrence kept, order kept)."""
    return tuple(dict.fromkeys(LABELS[n].source if n in LABELS else n for n in names))


def derive_labels(names: Sequence[str], stored: Mapping[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The labels among some names, from a run's stored arrays.

    Args:
        names: names, labels among them (the others are ignored)
        stored: the run's arrays by name, the labels' sources among them
    """
    return {
        name: LABELS[name].derive(stored[LABELS[name].source]) for name in names if name in LABELS
    }
