"""Named DH tables: the paper's example arms and the spherical wrist.

The Aaria presets also carry default joint and base oscillation tables, so a run needs nothing
else: each revolute module swings ±0.6 rad and each prismatic module over 80 % of its rail, at
``0.8 + 0.3·i`` rad/s with phase ``0.5·i`` rad (module i); the base moves ±5 cm along each world
axis at 1 rad/s and turns ±0.05 rad about each gimbal axis at 0.7 rad/s.

- ``aaria-fig2``: Table 3 of the Aaria paper (two prismatic and four revolute modules).
- ``aaria-fig3``: Table 4 of the Aaria paper (module 2 empty; three prismatic, two revolute).
- ``spherical-wrist``: Table 1 of the spherical-wrist report, a standard DH table
  (a = 0; alpha = -90°, +90°, 0; d3 = 132 mm).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from aaria_pin._se3 import Array
from aaria_pin.dh import Convention
from aaria_pin.errors import ParameterError
from aaria_pin.oscillation import default_base_table

__all__ = ["PRESETS", "Preset", "get_preset", "preset_names"]

_HALF_PI = np.pi / 2


@dataclass(frozen=True)
class Preset:
    """A named table.

    Attributes:
        name: preset name
        table: the DH table (8 × 5 for Aaria, n × 5 otherwise)
        convention: the table's convention
        description: one line saying where the table comes from
        joint_table: default joint oscillation table ``senSenJ`` (Aaria presets)
        base_table: default base oscillation table ``senSenB`` (Aaria presets)
    """

    name: str
    table: Array
    convention: Convention
    description: str
    joint_table: Array | None = None
    base_table: Array | None = None


PRESETS: dict[str, Preset] = {
    preset.name: preset
    for preset in (
        Preset(
            "aaria-fig2",
            np.array(
                [
                    [_HALF_PI, 0.89, 0.0, 0.14, 2],
                    [_HALF_PI, 0.83, _HALF_PI, 0.29, 1],
                    [_HALF_PI, 0.88, 0.0, 0.22, 1],
                    [_HALF_PI, 0.85, _HALF_PI, 0.24, 1],
                    [0.0, 0.86, _HALF_PI, 0.13, 2],
                    [0.0, 0.89, 0.0, 0.23, 1],
                    [_HALF_PI, 0.89, _HALF_PI, 0.12, 1],
                    [-_HALF_PI, 0.86, 0.0, 0.29, 1],
                ]
            ),
            "aaria",
            "Aaria paper, Table 3 (Figure 2): 2 prismatic and 4 revolute modules",
            np.array(
                [
                    [0.0, 0.056, 0.0, 1.1, 0.5],
                    [0.6, 0.0, 0.0, 1.4, 1.0],
                    [0.6, 0.0, 0.0, 1.7, 1.5],
                    [0.6, 0.0, 0.0, 2.0, 2.0],
                    [0.0, 0.052, 0.0, 2.3, 2.5],
                    [0.6, 0.0, 0.0, 2.6, 3.0],
                    [0.0, 0.0, 0.0, 0.0, 0.0],
                    [0.0, 0.0, 0.0, 0.0, 0.0],
                ]
            ),
            default_base_table(),
        ),
        Preset(
            "aaria-fig3",
            np.array(
                [
                    [0.0, 0.84, 0.0, 0.17, 2],
                    [0.0, 0.82, _HALF_PI, 0.26, 0],
                    [_HALF_PI, 0.82, _HALF_PI, 0.21, 2],
                    [0.0, 0.85, -_HALF_PI, 0.23, 2],
                    [_HALF_PI, 0.83, -_HALF_PI, 0.26, 1],
                    [0.0, 0.87, 0.0, 0.12, 1],
                    [_HALF_PI, 0.88, _HALF_PI, 0.27, 1],
                    [-_HALF_PI, 0.85, _HALF_PI, 0.20, 1],
                ]
            ),
            "aaria",
            "Aaria paper, Table 4 (Figure 3): module 2 empty, 3 prismatic and 2 revolute",
            np.array(
                [
                    [0.0, 0.068, 0.0, 1.1, 0.5],
                    [0.0, 0.0, 0.0, 0.0, 0.0],
                    [0.0, 0.084, 0.0, 1.7, 1.5],
                    [0.0, 0.092, 0.0, 2.0, 2.0],
                    [0.6, 0.0, 0.0, 2.3, 2.5],
                    [0.6, 0.0, 0.0, 2.6, 3.0],
                    [0.0, 0.0, 0.0, 0.0, 0.0],
                    [0.0, 0.0, 0.0, 0.0, 0.0],
                ]
            ),
            default_base_table(),
        ),
        Preset(
            "spherical-wrist",
            np.array(
                [
                    [-_HALF_PI, 0.0, 0.0, 0.0, 1],
                    [_HALF_PI, 0.0, 0.0, 0.0, 1],
                    [0.0, 0.0, 0.0, 0.132, 1],
                ]
            ),
            "standard",
            "spherical-wrist report, Table 1: standard DH, d3 = 132 mm",
        ),
    )
}


def preset_names() -> tuple[str, ...]:
    """Names of the built-in presets, sorted."""
    return tuple(sorted(PRESETS))


def get_preset(name: str) -> Preset:
    """Look a preset up by name.

    Raises:
        ParameterError: the name is not a preset.
    """
    try:
        return PRESETS[name]
    except KeyError:
        raise ParameterError(
            f"preset {name!r} is not known; allowed: {', '.join(preset_names())}"
        ) from None
