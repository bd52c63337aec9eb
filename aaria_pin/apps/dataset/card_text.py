"""A data set's card as plain text for the terminal (what ``aaria info --card`` prints)."""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from typing import Any

from aaria_pin.aaria.randomize import PARTS
from aaria_pin.apps.dataset.card import HARDWARE_TABLE_UNITS, MAX_LISTED_STRUCTURES, DatasetCard

__all__ = ["card_text"]


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


def _drawn(card: DatasetCard, path: str) -> str:
    """`` (drawn per run from RANGE; here its middle)`` for a value each run draws, else ``""``."""
    if not any(name == path or name.startswith(f"{path}/") for name in card.drawn):
        return ""
    given = _given(card.hardware, path)
    return f" (drawn per run from {_value(given)}; here its middle)"


def _given(tables: Mapping[str, Any], path: str) -> Any:
    """The config's value (a range) of a recorded attribute path (``noise_parameters/KEY``)."""
    section, key = path.split("/")[:2]
    if section != "noise_parameters":
        return tables.get(section, {}).get(key)
    imu = tables.get("imu", tables.get("noise", {}))
    for sensor in ("gyro", "accel"):
        for field, value in imu.get(sensor, {}).items():
            if key.startswith(f"{sensor}_{field}_"):
                return value
    return next((v for f, v in imu.items() if key == f or key.startswith(f"{f}_")), None)


def _hardware_lines(card: DatasetCard) -> list[str]:
    """The joint hardware: each model's values and units, the tables it adds; the config."""
    from aaria_pin.aaria.hardware_templates import field_notes
    from aaria_pin.core.joint_sensors import JOINT_MODELS

    lines = ["", "## Joint hardware"]
    for name, cls in JOINT_MODELS.items():
        model = card.joint_hardware.get(name)
        if model is None:
            lines.append(f"{name}: off (no {', '.join(HARDWARE_TABLE_UNITS[name])})")
            continue
        lines.append(f"{name}: on")
        units = {k: re.findall(r"\[([^]]+)\]", note) for k, note in field_notes(cls).items()}
        for key, value in model.items():
            unit = f" [{units[key][-1]}]" if units.get(key) else ""
            lines.append(f"  {key} = {_value(value)}{unit}{_drawn(card, f'{name}/{key}')}")
        tables = HARDWARE_TABLE_UNITS[name]
        lines.append("  tables: " + ", ".join(f"{t} [{u}]" for t, u in tables.items()))
    if card.hardware:
        lines.append(f"config tables as given (a [low, high] drawn per run): {card.hardware}")
    if card.drawn:
        lines.append(f"drawn per run ({len(card.drawn)} values, hardware_values): "
                     + ", ".join(card.drawn))  # fmt: skip
    return lines


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
        lines += [
            f"  {key} = {_value(value)}{_drawn(card, f'noise_parameters/{key}')}"
            for key, value in card.noise_parameters.items()
        ]
    lines += _hardware_lines(card)

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
