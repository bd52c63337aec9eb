"""Random Aaria runs (the paper's MODE 1): structures, joint and base oscillations.

Every range and probability lives in one :class:`RandomConfig`, read from a TOML file with the
layout of :func:`default_config_toml` (unknown keys and empty ranges are refused). Each draw takes
its generator: run k of a data set with seed S draws each part from its own stream,
``RunSeeds(S, k).generator(part)`` (:class:`~aaria_pin.core.seeds.RunSeeds`), so its inputs and
noise depend only on (S, k), and keeping one part fixed (``vary``) leaves the draws of the
others unchanged.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin.core.se3 import Array
from aaria_pin.core.seeds import DATASET_STREAMS
from aaria_pin.errors import InputFileError, ParameterError

if TYPE_CHECKING:
    from aaria_pin.core.urdf_tree import UrdfJoint

__all__ = [
    "PARTS",
    "RandomConfig",
    "default_config_toml",
    "load_config",
    "random_base_table",
    "random_dh_table",
    "random_joint_table",
    "random_urdf_joint_table",
    "read_config_file",
    "refuse_unknown_keys",
]

PARTS = DATASET_STREAMS[:3]
"""What a data set can vary: ``structure``, ``joints``, ``base`` (the streams but the noise)."""

_HALF_PI = math.pi / 2


@dataclass(frozen=True)
class RandomConfig:
    """Ranges ``(low, high)`` and choices of the random runs; defaults follow the paper.

    Attributes:
        link_type_probabilities: probabilities of empty, revolute, prismatic per module
        a: link length range [m]
        alpha_choices: twist angles to choose from [rad]
        theta_choices: joint angle offsets to choose from (prismatic modules) [rad]
        d: joint offset / rail length range [m]
        tool_a: tool length range [m]
        revolute_amplitude: revolute amplitude range [rad]
        revolute_bias: revolute bias range [rad]
        prismatic_amplitude_fraction: prismatic amplitude as a fraction of the rail length
        prismatic_bias_fraction: prismatic bias as a fraction of the room the amplitude leaves
            on the rail, ``(d/2 - A)``
        joint_frequency: joint frequency range [rad/s]
        joint_phase: joint phase range [rad]
        base_translation_amplitude: base translation amplitude range [m]
        base_translation_bias: base translation bias range [m]
        base_rotation_amplitude: base gimbal amplitude range [rad]
        base_rotation_bias: base gimbal bias range [rad]
        base_frequency: base frequency range [rad/s]
        base_phase: base phase range [rad]
        base_per_axis: draw a 6 × 4 base table (each axis its own sine) instead of 2 × 4
    """

    link_type_probabilities: tuple[float, float, float] = (1 / 3, 1 / 3, 1 / 3)
    a: tuple[float, float] = (0.8, 0.9)
    alpha_choices: tuple[float, ...] = (-_HALF_PI, 0.0, _HALF_PI)
    theta_choices: tuple[float, ...] = (-_HALF_PI, 0.0, _HALF_PI)
    d: tuple[float, float] = (0.1, 0.3)
    tool_a: tuple[float, float] = (0.8, 0.9)
    revolute_amplitude: tuple[float, float] = (0.1, 1.0)
    revolute_bias: tuple[float, float] = (-0.5, 0.5)
    prismatic_amplitude_fraction: tuple[float, float] = (0.05, 0.45)
    prismatic_bias_fraction: tuple[float, float] = (-1.0, 1.0)
    joint_frequency: tuple[float, float] = (0.5, 3.0)
    joint_phase: tuple[float, float] = (0.0, 2 * math.pi)
    base_translation_amplitude: tuple[float, float] = (0.0, 0.1)
    base_translation_bias: tuple[float, float] = (-0.1, 0.1)
    base_rotation_amplitude: tuple[float, float] = (0.0, 0.1)
    base_rotation_bias: tuple[float, float] = (-0.1, 0.1)
    base_frequency: tuple[float, float] = (0.2, 2.0)
    base_phase: tuple[float, float] = (0.0, 2 * math.pi)
    base_per_axis: bool = True

    def __post_init__(self) -> None:
        for item in fields(self):
            value = getattr(self, item.name)
            if item.name == "base_per_axis":
                if not isinstance(value, bool):
                    raise _config_error(item.name, value, "true or false")
                continue
            numbers = tuple(float(v) for v in value)
            if not all(math.isfinite(v) for v in numbers):
                raise _config_error(item.name, value, "finite numbers")
            if item.name.endswith("_choices"):
                if not numbers:
                    raise _config_error(item.name, value, "one or more", shown="empty")
            elif item.name == "link_type_probabilities":
                if len(numbers) != 3 or min(numbers) < 0 or numbers[1] + numbers[2] <= 0:
                    raise _config_error(
                        item.name,
                        value,
                        "3 probabilities >= 0 (empty, revolute, prismatic), revolute + prismatic"
                        " > 0",
                    )
            elif len(numbers) != 2 or numbers[0] > numbers[1]:
                raise _config_error(item.name, value, "a range [low, high], low <= high")
        if self.a[0] < 0 or self.d[0] < 0 or self.tool_a[0] < 0:
            raise ParameterError(
                "config lengths a, d, tool_a must be >= 0",
                parameter="config",
                value=(self.a[0], self.d[0], self.tool_a[0]),
                element="a, d, tool_a",
            )
        if self.prismatic_amplitude_fraction[1] > 0.5 or self.prismatic_amplitude_fraction[0] < 0:
            raise _config_error(
                "prismatic_amplitude_fraction",
                self.prismatic_amplitude_fraction,
                "within [0, 0.5] (the rail is d long)",
            )
        if abs(self.prismatic_bias_fraction[0]) > 1 or abs(self.prismatic_bias_fraction[1]) > 1:
            raise _config_error(
                "prismatic_bias_fraction", self.prismatic_bias_fraction, "within [-1, 1]"
            )
        worst = max(abs(v) for v in self.revolute_bias) + self.revolute_amplitude[1]
        if worst > 2 * math.pi:
            raise ParameterError(
                f"config revolute bias and amplitude reach {worst:.4g} rad; allowed: <= 2π",
                parameter="config",
                value=worst,
                element="revolute_bias, revolute_amplitude",
            )
        if self.joint_frequency[0] < 0 or self.base_frequency[0] < 0:
            raise ParameterError(
                "config frequencies must be >= 0 rad/s",
                parameter="config",
                value=(self.joint_frequency[0], self.base_frequency[0]),
                element="joint_frequency, base_frequency",
            )

    def as_dict(self) -> dict[str, Any]:
        """The configuration as plain values (lists for ranges), for files and attributes."""
        return {
            item.name: (
                list(getattr(self, item.name))
                if isinstance(getattr(self, item.name), tuple)
                else getattr(self, item.name)
            )
            for item in fields(self)
        }


def _config_error(name: str, value: Any, allowed: str, shown: str = "") -> ParameterError:
    """``config NAME is VALUE; allowed: ALLOWED``, of ``parameter`` ``config``, ``element`` NAME.

    The message is given whole (not composed from the fields): a key's name may also be a flag's
    parameter (``base_frequency``), which the CLI must not name instead of the config key.
    """
    return ParameterError(
        f"config {name} is {shown or repr(value)}; allowed: {allowed}",
        parameter="config",
        value=value,
        element=name,
    )


_DESCRIPTIONS = {
    "link_type_probabilities": "probabilities of empty, revolute, prismatic for each module",
    "a": "link length a [m]",
    "alpha_choices": "twist alpha, one of these [rad]",
    "theta_choices": "offset theta of a prismatic module, one of these [rad]",
    "d": "offset d of a revolute module, rail length of a prismatic one [m]",
    "tool_a": "tool length [m]",
    "revolute_amplitude": "revolute joint amplitude [rad]",
    "revolute_bias": "revolute joint bias [rad]",
    "prismatic_amplitude_fraction": "prismatic amplitude as a fraction of the rail length, <= 0.5",
    "prismatic_bias_fraction": "prismatic bias, a fraction in [-1, 1] of the rail left, d/2 - A",
    "joint_frequency": "joint frequency [rad/s]",
    "joint_phase": "joint phase [rad]",
    "base_translation_amplitude": "base translation amplitude, each of x, y, z [m]",
    "base_translation_bias": "base translation bias [m]",
    "base_rotation_amplitude": "base gimbal amplitude, each of ax, ay, az [rad]",
    "base_rotation_bias": "base gimbal bias [rad]",
    "base_frequency": "base frequency [rad/s]",
    "base_phase": "base phase [rad]",
    "base_per_axis": "true: one sine per base axis (6 x 4 table); false: 2 x 4",
}


def default_config_toml() -> str:
    """The default configuration as TOML text (what ``aaria dataset --print-config`` prints)."""
    lines = [
        "# aaria dataset --config: ranges are [low, high] (uniform), choices are drawn uniformly;",
        "# any key may be left out (its default stays); unknown keys are refused.",
    ]
    for key, value in RandomConfig().as_dict().items():
        lines.append(f"# {_DESCRIPTIONS[key]}")
        if isinstance(value, bool):
            lines.append(f"{key} = {'true' if value else 'false'}")
        else:
            lines.append(f"{key} = [{', '.join(repr(float(v)) for v in value)}]")
    return "\n".join(lines) + "\n"


def load_config(path: str | Path | None) -> RandomConfig:
    """Read a TOML configuration (keys of :class:`RandomConfig`; missing keys keep defaults).

    Raises:
        InputFileError: the file is missing, unreadable, not UTF-8 or not TOML.
        ParameterError: an unknown key, or a value out of its allowed set.
    """
    if path is None:
        return RandomConfig()
    return config_from_mapping(read_config_file(path), str(path))


def read_config_file(path: str | Path) -> dict[str, Any]:
    """The tables of a TOML configuration file, as plain values (not checked).

    Raises:
        InputFileError: the file is missing, unreadable, not UTF-8 or not TOML (one line).
    """
    file = Path(path)
    try:
        raw = file.read_bytes()
    except OSError as exc:
        raise InputFileError(
            f"{file}: cannot be read ({exc.strerror})", parameter="file", value=str(file)
        ) from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputFileError(
            f"{file}: byte {exc.start} is not UTF-8 text; allowed: a TOML file in UTF-8",
            parameter="file",
            value=str(file),
        ) from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputFileError(
            f"{file}: not valid TOML ({exc})", parameter="file", value=str(file)
        ) from None


def refuse_unknown_keys(data: Mapping[str, Any], known: Sequence[str], where: str) -> None:
    """Refuse a config table with a key not in ``known`` (the first such key, sorted).

    Args:
        data: the table as read
        known: its allowed keys, in the order the message lists them
        where: the table's place, as the message names it (``config``, ``config: noise``)

    Raises:
        ParameterError: ``WHERE: unknown key KEY; allowed: KNOWN`` (``parameter`` ``config``).
    """
    unknown = sorted(set(data) - set(known))
    if unknown:
        raise ParameterError(
            f"{where}: unknown key {unknown[0]!r}; allowed: {', '.join(known)}",
            parameter="config",
            value=unknown[0],
            element=where,
        )


def config_from_mapping(data: Mapping[str, Any], where: str = "config") -> RandomConfig:
    """A configuration from plain values (a parsed TOML file, or a data set's attribute)."""
    refuse_unknown_keys(data, sorted(item.name for item in fields(RandomConfig)), where)
    values: dict[str, Any] = {
        key: (tuple(v) if isinstance(v, list) else v) for key, v in data.items()
    }
    try:
        return RandomConfig(**values)
    except (TypeError, ValueError) as exc:
        raise ParameterError(
            f"{where}: {exc}", parameter="config", value=dict(data), element=where
        ) from None


def _uniform(rng: np.random.Generator, bounds: Iterable[float]) -> float:
    low, high = bounds
    return float(rng.uniform(low, high)) if high > low else float(low)


def random_dh_table(config: RandomConfig, rng: np.random.Generator) -> Array:
    """A random 8 × 5 Aaria table: link types, lengths and angles in the configured sets.

    At least one module is non-empty (an all-empty draw is drawn again).
    """
    p = np.asarray(config.link_type_probabilities, dtype=float)
    p = p / p.sum()
    table = np.zeros((8, 5))
    while True:
        types = rng.choice(3, size=6, p=p)
        if types.any():
            break
    for row, link_type in enumerate(types):
        alpha = float(rng.choice(config.alpha_choices))
        theta = float(rng.choice(config.theta_choices))
        a, d = _uniform(rng, config.a), _uniform(rng, config.d)
        if link_type:
            table[row] = [alpha, a, theta, d, link_type]
    table[6] = [0.0, _uniform(rng, config.tool_a), 0.0, 0.0, 1]
    return table


def _joint_draws(config: RandomConfig, rng: np.random.Generator) -> list[float]:
    """One joint's six draws: revolute amplitude, bias; prismatic fractions; frequency, phase."""
    return [
        _uniform(rng, config.revolute_amplitude),
        _uniform(rng, config.revolute_bias),
        _uniform(rng, config.prismatic_amplitude_fraction),
        _uniform(rng, config.prismatic_bias_fraction),
        _uniform(rng, config.joint_frequency),
        _uniform(rng, config.joint_phase),
    ]


def random_joint_table(config: RandomConfig, dh_table: Array, rng: np.random.Generator) -> Array:
    """A random 8 × 5 joint oscillation table that keeps every joint within its range."""
    table = np.zeros((8, 5))
    for row in range(6):
        link_type = int(dh_table[row, 4])
        draws = _joint_draws(config, rng)
        if link_type == 1:
            table[row] = [draws[0], 0.0, draws[1], draws[4], draws[5]]
        elif link_type == 2:
            rail = dh_table[row, 3]
            amplitude = draws[2] * rail
            room = rail / 2 - amplitude
            table[row] = [0.0, amplitude, draws[3] * room * (1 - 1e-9), draws[4], draws[5]]
    return table


def random_urdf_joint_table(
    config: RandomConfig, joints: Sequence[UrdfJoint], rng: np.random.Generator
) -> Array:
    """A random n × 5 joint oscillation table for a URDF robot, within its limits.

    Each joint draws the same six numbers as an Aaria module, in the same order, over the part
    of its range that motions use (:func:`~aaria_pin.core.urdf_robot.usable_range`: at most 0.5 m of
    a prismatic range, 2π of a revolute one, about the middle; a continuous joint's is
    centred on 0). A revolute joint swings by a revolute amplitude, at most 45 % of that range,
    about its middle moved by a revolute bias cut to the room left; a prismatic joint swings by
    a fraction of the range about the middle moved by a fraction of the room left. The
    frequency is cut so that |amplitude| × frequency stays
    within the joint's velocity limit. Mimic joints get zero rows (they follow their leader).
    """
    from aaria_pin.core.urdf_robot import usable_range

    table = np.zeros((len(joints), 5))
    for row, joint in enumerate(joints):
        draws = _joint_draws(config, rng)
        if joint.mimic is not None:
            continue
        middle, span = usable_range(joint)
        if joint.kind == "prismatic":
            amplitude = draws[2] * span
            bias = middle + draws[3] * (span / 2 - amplitude) * (1 - 1e-9)
        else:
            amplitude = min(draws[0], 0.45 * span)
            room = span / 2 - amplitude
            bias = middle + min(max(draws[1], -room), room) * (1 - 1e-9)
        frequency = draws[4]
        if amplitude > 0 and math.isfinite(joint.velocity):
            frequency = min(frequency, joint.velocity / amplitude * (1 - 1e-9))
        column = 1 if joint.kind == "prismatic" else 0
        table[row, column] = amplitude
        table[row, 2:] = [bias, frequency, draws[5]]
    return table


def random_base_table(config: RandomConfig, rng: np.random.Generator) -> Array:
    """A random base oscillation table: 6 × 4 (one sine per axis) or 2 × 4."""
    rows = 6 if config.base_per_axis else 2
    table = np.zeros((rows, 4))
    for row in range(rows):
        rotation = row >= rows // 2
        table[row] = [
            _uniform(
                rng,
                config.base_rotation_amplitude if rotation else config.base_translation_amplitude,
            ),
            _uniform(rng, config.base_rotation_bias if rotation else config.base_translation_bias),
            _uniform(rng, config.base_frequency),
            _uniform(rng, config.base_phase),
        ]
    return table
