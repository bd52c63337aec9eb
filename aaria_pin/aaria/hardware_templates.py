"""The hardware templates: ``aaria template imu-model`` and ``aaria template hardware``.

Written from the models themselves: every field of :class:`~aaria_pin.core.imu_noise.ImuNoiseModel`,
:class:`~aaria_pin.core.imu_noise.SensorNoise` and the joint models, with its value (a preset's,
or the default) written by ``repr`` so it reads back bit for bit, and with the meaning and unit
its class documents (the ``Attributes:`` of its docstring).
"""

from __future__ import annotations

import dataclasses
import json
from typing import Any

from aaria_pin.core.imu_presets import DEFAULT_IMU_MODEL, imu_model_toml
from aaria_pin.core.joint_sensors import JOINT_MODELS

__all__ = ["CLOSED_LOOP_TABLE", "hardware_template", "imu_model_template"]

CLOSED_LOOP_TABLE = "controller"
"""The table only a closed-loop run takes: written commented out in the template."""


def field_notes(cls: type) -> dict[str, str]:
    """Each field's line of a class's ``Attributes:`` docstring section (continuations joined)."""
    notes: dict[str, str] = {}
    inside, current = False, ""
    for line in (cls.__doc__ or "").splitlines():
        text = line.strip()
        if text == "Attributes:":
            inside = True
            continue
        if not inside or not text:
            inside = inside and bool(text)
            continue
        name, colon, rest = text.partition(": ")
        if colon and name.isidentifier() and line.startswith("        ") and not line[8] == " ":
            current = name
            notes[name] = rest
        elif current:
            notes[current] += " " + text
    return notes


def _toml(value: Any) -> str:
    """A TOML value that reads back as ``value``: numbers by ``repr``, text as JSON strings."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int | float):
        return repr(float(value))
    if isinstance(value, str):
        return json.dumps(value)
    return "[" + ", ".join(_toml(v) for v in value) + "]"


def _lines(model: Any, skip: tuple[str, ...] = ()) -> list[str]:
    """``key = value  # meaning`` for each field of a model (None values as a comment)."""
    notes = field_notes(type(model))
    lines = []
    for item in dataclasses.fields(model):
        if item.name in skip:
            continue
        value = getattr(model, item.name)
        note = " ".join(notes.get(item.name, "").split())
        if value is None:
            lines.append(f"# {item.name} = ...  # {note} (not set)")
        else:
            lines.append(f"{item.name} = {_toml(value)}  # {note}".rstrip(" #"))
    return lines


def imu_model_template(name: str = DEFAULT_IMU_MODEL) -> str:
    """``aaria template imu-model [--imu-model NAME]``: a preset's IMU model, every field.

    The preset's TOML (:func:`~aaria_pin.core.imu_presets.imu_model_toml`: each value with its
    unit and data-sheet source), read by ``--imu-model FILE.toml`` back to the preset.

    Raises:
        ParameterError: an unknown preset (parameter ``imu_model``).
    """
    return f"""\
# aaria simulate|dataset --imu-model FILE.toml reads this file; it is also the [imu] table of a
# hardware file (aaria template hardware).
{imu_model_toml(name)}"""


def hardware_template() -> str:
    """``aaria template hardware``: the hardware tables, every key with its unit and default."""
    joints = []
    for name, cls in JOINT_MODELS.items():
        doc = (cls.__doc__ or "").strip().splitlines()[0]
        lines = [f"[{name}]", *_lines(cls())]
        if name == CLOSED_LOOP_TABLE:  # a run of another drive refuses it: off until wanted
            doc += " Uncomment it for --drive pd|computed-torque."
            lines = [f"# {line}" for line in lines]
        joints.append("\n".join([f"# {doc}", *lines]))
    imu = imu_model_toml(DEFAULT_IMU_MODEL)
    joint_tables = "\n\n".join(joints)
    return f"""\
# Hardware of a run (aaria simulate --hardware FILE; the same tables in a data set's config,
# aaria dataset --config FILE). Every value in SI units; 0 turns a term off. A table left out:
# that hardware is off (no such table in the run) or, for [imu], the --imu-model preset (default
# {DEFAULT_IMU_MODEL}); a key left out keeps the default written here. With aaria simulate --from,
# the tables given replace the run's stored ones, the others stay as stored.
#
# Joint values: a number for every joint, or a list of one per joint in the record's joint
# order (rad, N*m, kg*m^2 for a revolute joint; m, N, kg for a prismatic one).
#
# Ranges (a data set's config only): any number may be a range [low, high] (low <= high), drawn
# uniformly for each run from its own seed stream (one draw per joint for a joint value), e.g.
#   noise = [0.0, 1.0e-4]
# The data set records the ranges (its attribute hardware) and each run's drawn values (the
# table hardware_values, named by the attribute hardware_names). There a list of two numbers
# is a range: per-joint values of a two-joint robot are written [[v1, v1], [v2, v2]].

# The IMU model (aaria template imu-model writes any preset's values).
{imu}
{joint_tables}
"""
