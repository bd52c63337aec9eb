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

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from aaria_pin.aaria.dh import Convention
from aaria_pin.aaria.sine_tables import default_base_table
from aaria_pin.core.arguments import checked
from aaria_pin.core.inertia import Inertia
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = ["APPENDIX_B_PARTS", "PRESETS", "Preset", "get_preset", "preset_names"]

WRIST_D3 = 0.132
"""The wrist report's d3: wrist centre to tool point [m] (Table 1)."""

_HALF_PI = np.pi / 2

APPENDIX_B_PARTS = {
    # link: (part, material, mass [kg], centre of mass [mm], principal moments [kg·mm²])
    "base": ("part 1", "1060 aluminium alloy", 0.05987, (0.0, 15.34, 0.0), (26.55, 46.97, 26.55)),
    "link1": ("part 2", "Delrin 2700 NC010", 0.03481, (7.14, 0.0, 36.0), (20.23, 17.90, 5.90)),
    "link2": (
        "part 3",
        "1060 aluminium alloy",
        0.29058,
        (82.77, 20.0, 0.0),
        (175.09, 425.71, 310.43),
    ),
    "link3": (
        "part 4",
        "ABS plastic",
        0.16480,
        (-0.00039, 28.38, -0.00035),
        (103.45, 88.05, 99.66),
    ),
}
"""Appendix B of the wrist report, by the link each part is mounted on: part 2 on link 1, part 3
on link 2, part 4 (the gripper) on link 3; the report gives no placement of the parts' CAD
frames, so each is taken as its link's frame."""


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
        mass_properties: measured mass properties by link name, replacing those computed from
            the bodies' solids (the wrist's Appendix B parts)
    """

    name: str
    table: Array
    convention: Convention
    description: str
    joint_table: Array | None = None
    base_table: Array | None = None
    mass_properties: Mapping[str, Inertia] = field(default_factory=dict)


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
                    [0.0, 0.0, 0.0, WRIST_D3, 1],
                ]
            ),
            "standard",
            "spherical-wrist report, Table 1: standard DH, d3 = 132 mm; Appendix B parts",
            mass_properties={
                link: Inertia(mass, np.array(com) * 1e-3, np.diag(moments) * 1e-6)
                for link, (_, _, mass, com, moments) in APPENDIX_B_PARTS.items()
            }
            | {"tool": Inertia(0.0)},
        ),
    )
}


def preset_names() -> tuple[str, ...]:
    """Names of the built-in presets, sorted."""
    return tuple(sorted(PRESETS))


@checked
def get_preset(name: str) -> Preset:
    """Look a preset up by name.

    Raises:
        ParameterError: the name is not a preset.
    """
    try:
        return PRESETS[name]
    except KeyError:
        raise ParameterError(
            f"preset {name!r} is not known; allowed: {', '.join(preset_names())}",
            parameter="preset",
            value=name,
            allowed=", ".join(preset_names()),
        ) from None
