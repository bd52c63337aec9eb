"""The data card of a data set: what it is, computed from the file alone, printed and stored.

A card (:class:`DatasetCard`) says how a data set was made and what it holds: its format and
the aaria_pin that wrote it, the generating command and versions (attributes ``command`` and
``versions_json``; older files lack them), the robot (random Aaria DH arms, one DH arm, or a URDF
robot), the runs (complete, failed, not done), samples, rate, duration, dtype and seed, the ranges
the random parts were drawn from (``config_json``, for the parts in ``vary``) and the fixed
tables, the IMU noise model, every stored array and view with its shape, units and frame, the
counts of complete runs by structure (the link type of each module, from every run's stored
``senSenDH`` read as one array) and by number of active modules, and the failures grouped by
their message.

Example::

    from aaria_pin.apps.dataset.card import card_text, dataset_card, store_card

    card = dataset_card("ds.h5")        # computed; card.to_dict() is JSON-able
    print(card_text(card))              # what `aaria info --card ds.h5` prints
    store_card("ds.h5")                 # kept in the file as the attribute card_json

Data sets of both format versions (1: aaria_pin 0.1; 2) have cards. The units of an array are its
stored ``units`` attribute; a format 1 file stored none, so its card gives the record's
conventions and says so (``units_stored`` False).
"""

from __future__ import annotations

import json
import os
import re
import shlex
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.aaria.dh import LinkType
from aaria_pin.aaria.randomize import PARTS
from aaria_pin.aaria.sensen import N_MODULES
from aaria_pin.apps.dataset.spec import NOISE_STREAM
from aaria_pin.core.record import IMU_SIGNALS, SERIES, ColumnView
from aaria_pin.errors import InputFileError
from aaria_pin.files._stored import JSON_SUFFIX, units_of

__all__ = [
    "CARD_ATTRIBUTE",
    "CARD_VERSION",
    "CardColumn",
    "ColumnGroup",
    "DatasetCard",
    "FailureGroup",
    "card_text",
    "current_card",
    "dataset_card",
    "read_stored_card",
    "store_card",
]

CARD_ATTRIBUTE = "card_json"
"""The file attribute that holds the stored card (its :meth:`DatasetCard.to_dict` as JSON)."""
CARD_VERSION = 1
"""The card's own layout version: a stored card of another version is computed again."""
MAX_LISTED_RUNS = 100
"""Most run indices a failure group lists (its count is exact; ``failures_json`` has them all)."""
MAX_LISTED_STRUCTURES = 30
"""Most structures the text lists (the card holds them all: at most 3^6 - 1)."""

_LINK_LETTERS = {
    int(LinkType.EMPTY): "0",
    int(LinkType.REVOLUTE): "R",
    int(LinkType.PRISMATIC): "P",
}
"""How a structure is written: one letter per module (0 empty, R revolute, P prismatic)."""

_FRAMES = {
    "time": "",
    "q": "joint space (a column per joint of joint_names)",
    "qd": "joint space (a column per joint of joint_names)",
    "qdd": "joint space (a column per joint of joint_names)",
    "tau": "joint space (a column per joint of joint_names)",
    "base_pose": "T_world_base: the base frame in the world frame",
    "base_wrench": "world-aligned axes, about the base origin",
    "tool_pose": "T_world_tool: the tool frame in the world frame",
    "imu": "each IMU's own axes",
    "imu_mount": "T_parent_imu: each IMU in its parent frame",
}
"""The frame of each record array, as :mod:`aaria_pin.core.record` defines them."""

_SIGNAL_KINDS = {"w": ("angular velocity", "rad/s"), "f": ("specific force", "m/s^2")}
"""An IMU signal's kind and unit by the first letter of its name in :data:`IMU_SIGNALS`."""

_PART_OF_KEY = (("base_", "base"), ("revolute_", "joints"), ("prismatic_", "joints"))
"""Which random part a config key belongs to, by its prefix (``joint_*`` too; the rest:
structure)."""

_FIXED_PART = {"dh_table": "structure", "joint_table": "joints", "base_table": "base"}
"""The part each fixed table of ``fixed_tables_json`` keeps fixed."""

_INPUTS_SUFFIX = re.compile(r" \((?:\w+=\[.*|inputs could not be drawn)\)\s*$", re.DOTALL)
"""The run's inputs the engine appends to a failed run's message."""
_NUMBER = re.compile(r"(?<![\w.])[-+]?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?(?![\w])")
"""A number in a message (not a digit inside a name such as ``joint3``)."""


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
            over the series) or ``table of columns`` (a 0.1 flat table, stored)
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


# --- computing a card ------------------------------------------------------------------------


def dataset_card(path: str | os.PathLike[str]) -> DatasetCard:
    """The card of a data set, computed from the file alone.

    Args:
        path: the data set (``.h5``, format version 1 or 2)

    Raises:
        InputFileError: missing, unreadable, or not a data set.
    """
    import h5py

    from aaria_pin.files.dataset_reader import DatasetReader, dataset_summary

    summary = dataset_summary(path)
    with DatasetReader(path) as reader, h5py.File(path, "r") as handle:
        attributes = reader.attributes
        complete = reader.complete
        views = _views(reader)
        columns = tuple(
            _column(handle, name, name in views and reader.layout is not None, views.get(name))
            for name in reader.names
        )
        link_types = (
            np.asarray(handle["senSenDH"][:, :N_MODULES, 4])  # every run's at once
            if "senSenDH" in handle
            else None  # a URDF robot: one structure
        )
    kind = str(summary["kind"])
    failures = {int(k): str(v) for k, v in (attributes.get("failures") or {}).items()}
    n_complete = int(complete.sum())
    vary = tuple(attributes.get("vary") or ())
    structures, active, per_module = _structure_counts(link_types, complete)
    parameters = dict(attributes.get("noise_parameters") or {})
    command = attributes.get("command") or None  # "": a job started from Python
    if isinstance(command, list):
        command = shlex.join(str(part) for part in command)
    versions = attributes.get("versions")
    return DatasetCard(
        path=str(Path(path)),
        format_version=int(summary["format_version"]),
        written_by=str(attributes.get("version", "unknown")),
        command=None if command is None else str(command),
        versions=versions if isinstance(versions, dict) or versions is None else {"": versions},
        kind=kind,
        robot=_robot_name(kind, attributes, summary),
        robot_description=_robot_description(kind, vary, attributes, summary),
        n_runs=int(summary["runs"]),
        complete=n_complete,
        failed=len(failures),
        not_done=int(summary["runs"]) - n_complete - len(failures),
        samples=int(summary["samples"]),
        rate=_number(summary.get("rate")),
        duration=_number(summary.get("duration")),
        dtype=str(summary.get("dtype")),
        seed=None if summary.get("seed") is None else int(summary["seed"]),
        vary=vary,
        ranges=_ranges(attributes.get("config") or {}, vary, kind),
        fixed_tables={
            name: table
            for name, table in (attributes.get("fixed_tables") or {}).items()
            if _FIXED_PART.get(name) not in vary  # a preset's tables of a varied part: unused
        },
        noise=None if attributes.get("noise") is None else bool(attributes["noise"]),
        noise_parameters={k: float(v) for k, v in parameters.items()},
        noise_model=_noise_model(parameters),
        noise_stream=_noise_stream(attributes),
        columns=columns,
        structures=structures,
        active_modules=active,
        module_link_types=per_module,
        failures=_failure_groups(failures),
    )


def _number(value: Any) -> float | None:
    return None if value is None else float(value)


def _robot_name(kind: str, attributes: Mapping[str, Any], summary: Mapping[str, Any]) -> str:
    """The robot's name: the ``robot`` attribute, a URDF robot's name, or the DH default."""
    robot = summary.get("robot")
    if isinstance(robot, Mapping) and robot.get("name"):
        return str(robot["name"])
    if isinstance(attributes.get("robot"), str) and attributes["robot"]:
        return str(attributes["robot"])
    if kind == "dh":
        from aaria_pin.aaria.arm_run import DH_ROBOT

        return DH_ROBOT  # 0.1 did not record it
    return "unknown"


def _robot_description(
    kind: str, vary: Sequence[str], attributes: Mapping[str, Any], summary: Mapping[str, Any]
) -> str:
    """The robot in words: random Aaria DH arms, one Aaria DH arm, or a URDF robot."""
    name = _robot_name(kind, attributes, summary)
    if kind == "dh":
        if "structure" in vary:
            return f"random Aaria DH arms ({name}), {N_MODULES} modules, one structure a run"
        return f"one Aaria DH arm ({name}), its table fixed"
    robot = summary.get("robot")
    if isinstance(robot, Mapping):
        base = "moving" if robot.get("moving_base", True) else "fixed"
        return (
            f"URDF robot {name} (source {robot.get('source') or 'unknown'}), "
            f"{len(robot.get('joint_names', []))} joints, {len(robot.get('imu_names', []))} IMUs,"
            f" tool {robot.get('tool_frame')}, {base} base"
        )
    return f"URDF robot {name}"


def _ranges(config: Mapping[str, Any], vary: Sequence[str], kind: str) -> dict[str, dict[str, Any]]:
    """The configuration of each part that varies, by part, in the config's key order.

    A URDF robot's structure never varies (its structure keys are not used).
    """
    ranges: dict[str, dict[str, Any]] = {part: {} for part in PARTS if part in vary}
    for key, value in config.items():
        part = next((p for prefix, p in _PART_OF_KEY if key.startswith(prefix)), None)
        if part is None:
            part = "joints" if key.startswith("joint_") else "structure"
        if part in ranges and not (part == "structure" and kind != "dh"):
            ranges[part][key] = value
    return ranges


def _noise_model(parameters: Mapping[str, Any]) -> str:
    """``"ADIS16485"`` when the parameters are that model's (the one the engine uses)."""
    from aaria_pin.core.imu_noise import ADIS16485, noise_attributes

    known = noise_attributes(ADIS16485)
    if parameters and set(parameters) == set(known):
        if all(np.isclose(float(parameters[k]), v, rtol=1e-12) for k, v in known.items()):
            return "ADIS16485"
    return ""


def _noise_stream(attributes: Mapping[str, Any]) -> int | None:
    """The noise stream (0.1 did not record it: it used stream 3, as the reader assumes)."""
    if attributes.get("noise_stream") is not None:
        return int(attributes["noise_stream"])
    return NOISE_STREAM


def _views(reader: Any) -> dict[str, ColumnView]:
    """The column views (version 2), or a 0.1 file's flat tables as views of its first run."""
    if reader.layout is not None:
        return dict(reader.layout.views)
    complete = np.flatnonzero(reader.complete)
    if not complete.size:
        return {}
    return dict(reader.record(int(complete[0])).views)  # 0.1: senSen or signals, stored


def _column(handle: Any, name: str, virtual: bool, view: ColumnView | None) -> CardColumn:
    """The card's entry of one stored array or view."""
    dataset = handle[name]
    stored = dataset.attrs.get("units")
    if isinstance(stored, bytes):
        stored = stored.decode("utf-8", errors="replace")
    if view is not None:
        role = "view" if virtual else "table of columns"
        fallback = view.units or "see columns"
    else:
        role = "series" if name in SERIES else "input"
        fallback = units_of(name)
    return CardColumn(
        name=name,
        shape=tuple(int(n) for n in dataset.shape),
        dtype=str(dataset.dtype),
        role=role,
        units=str(stored) if stored is not None else fallback,
        units_stored=stored is not None,
        frame="" if view is not None else _FRAMES.get(name, ""),
        column_groups=_column_groups(view) if view is not None else (),
    )


def _column_groups(view: ColumnView) -> tuple[ColumnGroup, ...]:
    """A view's columns grouped by quantity, in the order each quantity first appears."""
    groups: dict[str, list[Any]] = {}
    for column, source in zip(view.columns, view.sources, strict=True):
        if source.array == "imu":
            quantity, units = _SIGNAL_KINDS[IMU_SIGNALS[source.index[-1]][0]]
        elif source.array == "q":
            quantity, units = "joint values", units_of("q")
        else:
            quantity, units = source.array, units_of(source.array)
        group = groups.setdefault(quantity, [0, column, column, units, _FRAMES[source.array]])
        group[0] += 1
        group[2] = column
    return tuple(ColumnGroup(quantity, *values) for quantity, values in groups.items())


def _structure_counts(
    link_types: np.ndarray | None, complete: np.ndarray
) -> tuple[dict[str, int], dict[str, int], tuple[dict[str, int], ...]]:
    """Complete runs by structure, by number of active modules, and per module by link type.

    Args:
        link_types: each run's link type per module, N × 6 (None: a URDF robot)
        complete: which runs are complete (N booleans); the others store no table
    """
    if link_types is None:
        return {}, {}, ()
    types = np.rint(link_types[np.asarray(complete, dtype=bool)]).astype(np.int64)
    if not types.size:
        return {}, {}, ()
    unique, counts = np.unique(types, axis=0, return_counts=True)
    order = sorted(range(len(counts)), key=lambda i: (-counts[i], unique[i].tolist()))
    structures = {
        " ".join(_LINK_LETTERS.get(int(t), str(t)) for t in unique[i]): int(counts[i])
        for i in order
    }
    active = np.bincount((types != LinkType.EMPTY).sum(axis=1), minlength=N_MODULES + 1)
    by_count = {str(n): int(active[n]) for n in range(len(active)) if active[n]}
    per_module = tuple(
        {letter: int(np.count_nonzero(column == code)) for code, letter in _LINK_LETTERS.items()}
        for column in types.T
    )
    return structures, by_count, per_module


def _failure_groups(failures: Mapping[int, str]) -> tuple[FailureGroup, ...]:
    """Failed runs grouped by message (numbers as ``#``, inputs left out), largest first."""
    groups: dict[str, list[int]] = {}
    examples: dict[str, str] = {}
    for run in sorted(failures):
        reason = _INPUTS_SUFFIX.sub("", failures[run]).strip()
        key = _NUMBER.sub("#", reason)
        groups.setdefault(key, []).append(run)
        examples.setdefault(key, f"run {run}: {reason}")
    ordered = sorted(groups.items(), key=lambda item: (-len(item[1]), item[1][0]))
    return tuple(
        FailureGroup(key, len(runs), tuple(runs[:MAX_LISTED_RUNS]), examples[key])
        for key, runs in ordered
    )


# --- storing and reading it back -------------------------------------------------------------


def store_card(path: str | os.PathLike[str]) -> DatasetCard:
    """Compute a data set's card and store it in the file (attribute :data:`CARD_ATTRIBUTE`).

    Args:
        path: the data set (opened ``r+``: nothing else in it changes)

    Raises:
        InputFileError: as :func:`dataset_card`, or the file cannot be opened for writing.
    """
    import h5py

    card = dataset_card(path)
    try:
        with h5py.File(path, "r+") as handle:
            # The stored card names no path (a file moved or copied would carry a stale one,
            # and a resumed file would differ from an uninterrupted one): read, it takes the
            # path it is read from (current_card).
            stored = {**card.to_dict(), "path": ""}
            handle.attrs[CARD_ATTRIBUTE] = json.dumps(stored, ensure_ascii=False)
    except OSError as exc:
        raise InputFileError(f"{path}: cannot store its card ({exc})") from None
    return card


def read_stored_card(path: str | os.PathLike[str]) -> DatasetCard | None:
    """The card stored in a data set, if there is one and it is current, naming ``path``.

    Current: of this :data:`CARD_VERSION`, and the file's N, complete runs and failed runs are
    still those the card counted (a resumed or continued job changes them).

    Raises:
        InputFileError: missing, unreadable, or not a data set.
    """
    from aaria_pin.files.dataset_reader import DatasetReader

    with DatasetReader(path) as reader:
        attributes = reader.attributes
        text = attributes.get(CARD_ATTRIBUTE.removesuffix(JSON_SUFFIX))
        if text is None:
            return None
        try:
            if text.get("card_version") != CARD_VERSION:
                return None
            card = DatasetCard.from_dict(text)
        except (AttributeError, TypeError, KeyError):
            return None  # of an unknown layout: computed again
        failed = len(attributes.get("failures") or {})
        current = (card.n_runs, card.complete, card.failed) == (
            len(reader),
            int(reader.complete.sum()),
            failed,
        )
    return replace(card, path=str(Path(path))) if current else None


def current_card(path: str | os.PathLike[str]) -> DatasetCard:
    """The stored card when current (:func:`read_stored_card`), else one computed now.

    A stored card names the file as it is now (it may have been renamed or moved since).
    """
    stored = read_stored_card(path)
    return stored if stored else dataset_card(path)


# --- the card as text ------------------------------------------------------------------------


def _shape(shape: Sequence[int]) -> str:
    return " × ".join(map(str, shape)) if len(shape) else "scalar"


def _value(value: Any) -> str:
    """A config or noise value, short: numbers with 4 significant digits."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return f"{value:.4g}"
    if isinstance(value, list):
        return "[" + ", ".join(_value(v) for v in value) + "]"
    return str(value)


def _count(count: int, what: str = "run") -> str:
    """``1 run``, ``12 runs``."""
    return f"{count} {what}" + ("" if count == 1 else "s")


def _runs(runs: Sequence[int], count: int) -> str:
    shown = ", ".join(map(str, runs[:20]))
    return shown + (f", … ({count - 20} more)" if count > 20 else "")


def card_text(card: DatasetCard) -> str:
    """The card as plain text (Markdown-like) for the terminal."""
    lines = [f"# Data card: {card.path}", ""]
    lines.append(
        f"aaria_pin data set, format version {card.format_version}, "
        f"written by aaria_pin {card.written_by}"
    )
    not_recorded = f"not recorded (written by aaria_pin {card.written_by})"
    lines.append(f"command: {card.command if card.command is not None else not_recorded}")
    if card.versions is None:
        lines.append(f"versions: {not_recorded}")
    else:
        lines.append("versions: " + ", ".join(f"{k} {v}".strip() for k, v in card.versions.items()))
    lines.append(f"robot: {card.robot_description}")
    lines.append(
        f"runs: {card.n_runs} ({card.complete} complete, {card.failed} failed, "
        f"{card.not_done} not done)"
    )
    rate = "?" if card.rate is None else f"{card.rate:g}"
    duration = "?" if card.duration is None else f"{card.duration:g}"
    lines.append(
        f"samples: {card.samples} a run at {rate} Hz ({duration} s), series in {card.dtype}; "
        f"seed {card.seed}"
    )

    lines += ["", "## Drawn from"]
    fixed = [part for part in PARTS if part not in card.vary]
    lines.append(
        f"vary: {', '.join(card.vary) or 'nothing'}"
        + (f" (fixed: {', '.join(fixed)})" if fixed else "")
    )
    for part, keys in card.ranges.items():
        lines.append(f"{part}:")
        lines += [f"  {key} = {_value(value)}" for key, value in keys.items()]
    for name, table in card.fixed_tables.items():
        lines.append(f"fixed {name} = {_value(table)}")

    lines += ["", "## Noise"]
    if card.noise is None:
        lines.append("not recorded")
    elif not card.noise:
        lines.append("off: the IMU signals are exact")
    else:
        model = f" ({card.noise_model} parameters)" if card.noise_model else ""
        lines.append(
            f"on{model}: run k's noise from SeedSequence(seed, spawn_key=(k, {card.noise_stream}))"
        )
        lines += [f"  {key} = {_value(value)}" for key, value in card.noise_parameters.items()]

    lines += ["", "## Columns"]
    width = max((len(column.name) for column in card.columns), default=0) + 2
    for column in card.columns:
        convention = "" if column.units_stored else " (not stored; the record's convention)"
        lines.append(
            f"  {column.name:<{width}} {_shape(column.shape)} {column.dtype} {column.role}"
            f" [{column.units}]{convention}"
        )
        if column.frame and column.frame not in column.units:  # stored units may say it already
            lines.append(f"  {'':<{width}} frame: {column.frame}")
        for group in column.column_groups:
            span = group.first if group.count == 1 else f"{group.first} … {group.last}"
            frame = f", {group.frame}" if group.frame and group.frame not in group.units else ""
            lines.append(
                f"  {'':<{width}} {group.quantity}: {_count(group.count, 'column')} ({span})"
                f" [{group.units}]{frame}"
            )

    lines += ["", "## Structures"]
    if card.kind != "dh":
        lines.append(f"one robot: {card.robot}")
    elif not card.structures:
        lines.append("no complete run")
    else:
        lines.append(
            "complete runs by link type of modules 1 to 6 (0 empty, R revolute, P prismatic):"
        )
        shown = list(card.structures.items())[:MAX_LISTED_STRUCTURES]
        lines += [f"  {label}: {_count(count)}" for label, count in shown]
        if len(card.structures) > len(shown):
            rest = sum(card.structures.values()) - sum(count for _, count in shown)
            lines.append(
                f"  … {len(card.structures) - len(shown)} more structures, {_count(rest)}"
                " (all of them in --json)"
            )
        lines.append(
            "by module, runs with 0 / R / P: "
            + "; ".join(
                f"{module}: " + " / ".join(str(n) for n in counts.values())
                for module, counts in enumerate(card.module_link_types, start=1)
            )
        )
        lines.append(
            "by active modules: "
            + ", ".join(f"{n}: {_count(count)}" for n, count in card.active_modules.items())
        )

    lines += ["", "## Failures"]
    if not card.failures:
        lines.append("none")
    for failure in card.failures:
        lines.append(f"{_count(failure.count)}: {failure.message}")
        lines.append(f"  runs {_runs(failure.runs, failure.count)}")
        lines.append(f"  e.g. {failure.example}")
    return "\n".join(lines) + "\n"
