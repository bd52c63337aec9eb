"""The data card of a data set: what it is, computed from the file alone, printed and stored.

A card (:class:`DatasetCard`) says how a data set was made and what it holds: its format and
the aaria_pin that wrote it, the generating command and versions (attributes ``command`` and
``versions_json``; older files lack them), the robot (random Aaria DH arms, one DH arm, or a URDF
robot), the runs (complete, failed, not done), samples, rate, duration, dtype and seed, the ranges
the random parts were drawn from (``config_json``, for the parts in ``vary``) and the fixed
tables, the IMU noise model and the joint hardware (values, ranges, the tables they add), every
stored array and view with its shape, units and frame, the
counts of complete runs by structure (the link type of each module, from every run's stored
``senSenDH`` read as one array) and by number of active modules, and the failures grouped by
their message.

This module holds the card's value and its JSON form; :mod:`.card_file` computes it from a
data set through one open file, stores it and reads it back; :mod:`.card_text` prints it.

Example::

    from aaria_pin.apps.dataset.card_file import dataset_card, store_card
    from aaria_pin.apps.dataset.card_text import card_text

    card = dataset_card("ds.h5")        # computed; card.to_dict() is JSON-able
    print(card_text(card))              # what `aaria info --card ds.h5` prints
    store_card("ds.h5")                 # kept in the file as the attribute card_json

Data sets of both format versions (1: aaria_pin 0.1; 2) have cards. The units of an array are its
stored ``units`` attribute; a format 1 file stored none, so its card gives the record's
conventions and says so (``units_stored`` False).
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field
from typing import Any

from aaria_pin.core.joint_sensors import JOINT_MODELS
from aaria_pin.core.record import HARDWARE_UNITS
from aaria_pin.core.run.measured import JOINT_TABLES

__all__ = [
    "CARD_ATTRIBUTE",
    "CARD_VERSION",
    "HARDWARE_TABLE_UNITS",
    "MAX_LISTED_RUNS",
    "MAX_LISTED_STRUCTURES",
    "CardColumn",
    "ColumnGroup",
    "DatasetCard",
    "FailureGroup",
]

CARD_ATTRIBUTE = "card_json"
"""The file attribute that holds the stored card (its :meth:`DatasetCard.to_dict` as JSON)."""
CARD_VERSION = 1
"""The card's own layout version: a stored card of another version is computed again."""
MAX_LISTED_RUNS = 100
"""Most run indices a failure group lists (its count is exact; ``failures_json`` has them all)."""
MAX_LISTED_STRUCTURES = 30
"""Most structures the text lists (the card holds them all: at most 3^6 - 1)."""
HARDWARE_TABLE_UNITS = {
    model: {
        name: HARDWARE_UNITS[name] for name in (*JOINT_TABLES[model][1], *JOINT_TABLES[model][0])
    }
    for model in JOINT_MODELS
}
"""The tables a run records of each joint model, with their units (and shapes)."""


@dataclass(frozen=True)
class ColumnGroup:
    """Columns of a view (or a 0.1 flat table) that hold one kind of quantity.

    Attributes:
        quantity: what they hold (``time``, ``joint values``, ``angular velocity``, ...)
        count: how many columns
        first: the first column's name
        last: the last column's name
        units: their units
        frame: their frame (``""``: none)
    """

    quantity: str
    count: int
    first: str
    last: str
    units: str
    frame: str


@dataclass(frozen=True)
class CardColumn:
    """One stored array (or view) of the data set.

    Attributes:
        name: the HDF5 dataset's name
        shape: its shape (runs first)
        dtype: its dtype
        role: ``series``, ``input`` (mounts and tables), ``view`` (an HDF5 virtual dataset
            over the series), ``sensor`` (an extra sensor's signals, ``sensor_<name>``: its
            columns as the column groups) or ``table of columns`` (a 0.1 flat table, stored)
        units: its ``units`` attribute (or the record's convention when not stored)
        units_stored: whether the file stores the units
        frame: its frame (``""``: none, or see the column groups)
        column_groups: for a view or a flat table, its columns by quantity
    """

    name: str
    shape: tuple[int, ...]
    dtype: str
    role: str
    units: str
    units_stored: bool
    frame: str
    column_groups: tuple[ColumnGroup, ...] = ()


@dataclass(frozen=True)
class FailureGroup:
    """Failed runs whose messages differ only in their numbers.

    Attributes:
        message: the message with each number written ``#`` and the run's inputs left out
        count: how many runs
        runs: the first :data:`MAX_LISTED_RUNS` of them, in order
        example: the first run's message (without its inputs)
    """

    message: str
    count: int
    runs: tuple[int, ...]
    example: str


@dataclass(frozen=True)
class DatasetCard:
    """What a data set is (module docstring); :meth:`to_dict` is its JSON form.

    Attributes:
        path: the file the card was computed from
        format_version: the data set format version (1: aaria_pin 0.1, 2)
        written_by: the aaria_pin version that wrote the file (its ``version`` attribute)
        command: the generating command line (None: not recorded, or a job started from
            Python, whose ``command`` attribute is empty)
        versions: the versions of the software that made it, by package (None: not recorded)
        kind: ``"dh"`` or ``"urdf"``
        robot: the robot's name
        robot_description: the robot in words (random Aaria DH arms, one DH arm, a URDF robot)
        n_runs: runs N
        complete: complete runs
        failed: failed runs
        not_done: runs neither complete nor failed (an interrupted job)
        samples: samples per run T
        rate: sample rate [Hz]
        duration: run length [s]
        dtype: dtype of the stored series
        seed: the data set's seed
        vary: the random parts
        ranges: the configuration of the random parts that vary, by part (key → value)
        fixed_tables: the tables of the parts that do not vary, by name (their values)
        noise: whether the IMU signals carry noise
        noise_parameters: the noise model's parameters (SI units in the keys)
        noise_model: the named model the parameters equal (``""``: none known)
        noise_stream: run k's noise is ``SeedSequence(seed, spawn_key=(k, noise_stream))``
        hardware: the hardware tables of the config as given (``[imu]``, ``[encoder]``, ...;
            a range ``[low, high]`` drawn per run), empty: none given
        joint_hardware: the joint models the file records (``encoder``, ``torque_sensor``,
            ``actuator``; a ranged value at its middle), each field with its value
        drawn: the attribute paths of the values each run draws (its ``hardware_values``)
        columns: every stored array and view
        structures: complete runs by structure (link type per module, e.g. ``"R R P 0 R R"``),
            most frequent first; empty for a URDF robot
        active_modules: complete runs by number of non-empty modules (keys ``"1"`` …)
        module_link_types: per module 1 to 6, its complete runs by link type
            ``{"0": empty, "R": revolute, "P": prismatic}``; empty for a URDF robot
        failures: failed runs, grouped by message, largest group first
        card_version: :data:`CARD_VERSION`
    """

    path: str
    format_version: int
    written_by: str
    command: str | None
    versions: dict[str, Any] | None
    kind: str
    robot: str
    robot_description: str
    n_runs: int
    complete: int
    failed: int
    not_done: int
    samples: int
    rate: float | None
    duration: float | None
    dtype: str
    seed: int | None
    vary: tuple[str, ...]
    ranges: dict[str, dict[str, Any]]
    fixed_tables: dict[str, Any]
    noise: bool | None
    noise_parameters: dict[str, float]
    noise_model: str
    noise_stream: int | None
    columns: tuple[CardColumn, ...]
    structures: dict[str, int] = field(default_factory=dict)
    active_modules: dict[str, int] = field(default_factory=dict)
    module_link_types: tuple[dict[str, int], ...] = ()
    failures: tuple[FailureGroup, ...] = ()
    hardware: dict[str, Any] = field(default_factory=dict)
    joint_hardware: dict[str, dict[str, Any]] = field(default_factory=dict)
    drawn: tuple[str, ...] = ()
    card_version: int = CARD_VERSION

    def to_dict(self) -> dict[str, Any]:
        """The card as plain JSON-able values (tuples as lists)."""
        return json.loads(json.dumps(asdict(self)))

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> DatasetCard:
        """A card from its :meth:`to_dict` form (as stored in ``card_json``)."""
        values = dict(data)
        values["vary"] = tuple(values["vary"])
        values["module_link_types"] = tuple(values["module_link_types"])
        values["drawn"] = tuple(values.get("drawn", ()))
        values["columns"] = tuple(
            CardColumn(
                **{
                    **column,
                    "shape": tuple(column["shape"]),
                    "column_groups": tuple(ColumnGroup(**g) for g in column["column_groups"]),
                }
            )
            for column in values["columns"]
        )
        values["failures"] = tuple(
            FailureGroup(**{**group, "runs": tuple(group["runs"])}) for group in values["failures"]
        )
        return cls(**values)
