"""A data set's card from its file: computed through one open reader, stored, read back.

The card's contents are described in :mod:`.card`. Everything is read through one
:class:`~aaria_pin.files.dataset.reader.DatasetReader`: its header, stored arrays'
shapes and units, and every run's ``senSenDH`` (read as one array for the structure counts).
"""

from __future__ import annotations

import json
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from aaria_pin.aaria.dh import LinkType
from aaria_pin.aaria.randomize import PARTS
from aaria_pin.aaria.sensen import N_MODULES
from aaria_pin.apps.dataset.card import (
    CARD_ATTRIBUTE,
    CARD_VERSION,
    MAX_LISTED_RUNS,
    CardColumn,
    ColumnGroup,
    DatasetCard,
    FailureGroup,
)
from aaria_pin.apps.dataset.spec import NOISE_STREAM
from aaria_pin.core.record import IMU_SIGNALS, SERIES, TIMED_HARDWARE, ColumnView
from aaria_pin.errors import InputFileError
from aaria_pin.files._stored import units_of
from aaria_pin.files.dataset.header import DatasetHeader
from aaria_pin.files.dataset.reader import DatasetReader

__all__ = ["current_card", "dataset_card", "read_stored_card", "reader_card", "store_card"]

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
    "inertial_parameters": "a row per joint of joint_names (the body it moves), then the base "
    "body; first moments and inertia in each joint's frame, about its origin",
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


def dataset_card(path: str | os.PathLike[str]) -> DatasetCard:
    """The card of a data set, computed from the file alone (opened once).

    Args:
        path: the data set (``.h5``, format version 1 or 2)

    Raises:
        InputFileError: missing, unreadable, or not a data set.
    """
    with DatasetReader(path) as reader:
        return reader_card(reader)


def reader_card(reader: DatasetReader) -> DatasetCard:
    """The card of a data set open in ``reader``: everything is read through its one handle.

    Args:
        reader: the data set, open (format version 1 or 2)
    """
    header = reader.header
    handle = reader.handle
    complete = reader.complete
    views = _views(reader)
    sensors = _sensor_groups(header.sensors)
    columns = tuple(
        _column(handle, name, name in views and reader.layout is not None, views.get(name))
        if name not in sensors
        else _sensor_column(handle, name, sensors[name])
        for name in reader.names
    )
    link_types = (
        np.asarray(handle["senSenDH"][:, :N_MODULES, 4])  # every run's at once
        if "senSenDH" in handle
        else None  # a URDF robot: one structure
    )
    kind = header.kind
    failures = header.failures
    n_complete = int(complete.sum())
    vary = tuple(header.vary or ())
    structures, active, per_module = _structure_counts(link_types, complete)
    parameters = header.noise_parameters
    return DatasetCard(
        path=str(reader.path),
        format_version=header.format_version,
        written_by=header.written_by or "unknown",
        command=header.command,
        versions=header.versions,
        kind=kind,
        robot=_robot_name(header),
        robot_description=_robot_description(header, vary),
        n_runs=header.n_runs,
        complete=n_complete,
        failed=len(failures),
        not_done=header.n_runs - n_complete - len(failures),
        samples=header.samples,
        rate=_number(header.rate),
        duration=_number(header.duration),
        dtype=str(header.dtype),
        seed=None if header.seed is None else int(header.seed),
        vary=vary,
        ranges=_ranges(header.config or {}, vary, kind),
        fixed_tables={
            name: table
            for name, table in header.fixed_tables.items()
            if _FIXED_PART.get(name) not in vary  # a preset's tables of a varied part: unused
        },
        noise=None if header.noise is None else bool(header.noise),
        noise_parameters=_every_noise_term(parameters),
        noise_model=_noise_model(parameters),
        noise_stream=NOISE_STREAM if header.noise_stream is None else header.noise_stream,
        columns=columns,
        structures=structures,
        active_modules=active,
        module_link_types=per_module,
        failures=_failure_groups(failures),
        hardware=dict(header.attributes.get("hardware") or {}),
        joint_hardware={
            name: dict(header.attributes[name])
            for name in ("encoder", "torque_sensor", "actuator", "current_sensor")
            if isinstance(header.attributes.get(name), Mapping)
        },
        drawn=tuple(header.attributes.get("hardware_names") or ()),
    )


def _number(value: Any) -> float | None:
    return None if value is None else float(value)


def _robot_name(header: DatasetHeader) -> str:
    """The robot's name: a URDF robot's name, the ``robot`` attribute, or the DH default."""
    robot = header.robot_info
    if isinstance(robot, Mapping) and robot.get("name"):
        return str(robot["name"])
    if header.robot:
        return header.robot
    if header.kind == "dh":
        from aaria_pin.aaria.arm_run import DH_ROBOT

        return DH_ROBOT  # 0.1 did not record it
    return "unknown"


def _robot_description(header: DatasetHeader, vary: Sequence[str]) -> str:
    """The robot in words: random Aaria DH arms, one Aaria DH arm, or a URDF robot."""
    name = _robot_name(header)
    if header.kind == "dh":
        if "structure" in vary:
            return f"random Aaria DH arms ({name}), {N_MODULES} modules, one structure a run"
        return f"one Aaria DH arm ({name}), its table fixed"
    robot = header.robot_info
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


def _every_noise_term(parameters: Mapping[str, Any]) -> dict[str, float]:
    """Every IMU term of the recorded model, those off (not recorded) at their off value."""
    from aaria_pin.core.imu_attributes import noise_model_from_attributes
    from aaria_pin.core.imu_noise import noise_attributes

    if not parameters:
        return {}
    every = noise_attributes(noise_model_from_attributes(parameters), every=True)
    return {key: float(value) for key, value in every.items() if np.ndim(value) == 0}


def _noise_model(parameters: Mapping[str, Any]) -> str:
    """The preset the parameters are (``"ADIS16485"``, the default, ...; ``""``: none)."""
    from aaria_pin.core.imu_noise import noise_attributes
    from aaria_pin.core.imu_presets import IMU_PRESETS

    for name, model in IMU_PRESETS.items():
        known = noise_attributes(model)
        if parameters and set(parameters) == set(known):
            if all(np.isclose(float(parameters[k]), v, rtol=1e-12) for k, v in known.items()):
                return name.upper()
    return ""


def _views(reader: DatasetReader) -> dict[str, ColumnView]:
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
        role = "series" if name in SERIES or name in TIMED_HARDWARE else "input"
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


def _sensor_groups(described: Mapping[str, Any]) -> dict[str, tuple[ColumnGroup, ...]]:
    """Each extra sensor's table (``sensor_<name>``) → its columns, a group each with units.

    From the file's attribute ``sensors`` (:func:`~aaria_pin.core.run.sensor.sensor_attributes`).
    """
    return {
        str(entry["table"]): tuple(
            ColumnGroup(f"{name} {column}", 1, str(column), str(column), str(entry["units"]), "")
            for column in entry["columns"]
        )
        for name, entry in described.items()
    }


def _sensor_column(handle: Any, name: str, groups: tuple[ColumnGroup, ...]) -> CardColumn:
    """The card's entry of an extra sensor's table: role ``sensor``, its columns and units."""
    dataset = handle[name]
    return CardColumn(
        name=name,
        shape=tuple(int(n) for n in dataset.shape),
        dtype=str(dataset.dtype),
        role="sensor",
        units=groups[0].units if groups else "",
        units_stored=True,
        frame="",
        column_groups=groups,
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
        raise InputFileError(f"{path}: cannot store its card ({exc})", parameter="path") from None
    return card


def read_stored_card(path: str | os.PathLike[str]) -> DatasetCard | None:
    """The card stored in a data set, if there is one and it is current, naming ``path``.

    Current: of this :data:`CARD_VERSION`, and the file's N, complete runs and failed runs are
    still those the card counted (a resumed or continued job changes them).

    Raises:
        InputFileError: missing, unreadable, or not a data set.
    """
    with DatasetReader(path) as reader:
        return _stored_card(reader)


def _stored_card(reader: DatasetReader) -> DatasetCard | None:
    """:func:`read_stored_card` of an open data set."""
    text = reader.header.stored_card
    if text is None:
        return None
    try:
        if text.get("card_version") != CARD_VERSION:
            return None
        card = DatasetCard.from_dict(text)
    except (AttributeError, TypeError, KeyError):
        return None  # of an unknown layout: computed again
    failed = len(reader.header.failures)
    current = (card.n_runs, card.complete, card.failed) == (
        len(reader),
        int(reader.complete.sum()),
        failed,
    )
    return replace(card, path=str(reader.path)) if current else None


def current_card(path: str | os.PathLike[str]) -> DatasetCard:
    """The stored card when current (:func:`read_stored_card`), else one computed now.

    A stored card names the file as it is now (it may have been renamed or moved since). The
    file is opened once, for both.
    """
    with DatasetReader(path) as reader:
        stored = _stored_card(reader)
        return stored if stored else reader_card(reader)
