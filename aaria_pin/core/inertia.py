"""Rigid-body inertias of simple solids from their dimensions and a density, and composites.

A :class:`Part` is a solid (box or cylinder) placed in a body frame; :func:`composite_inertia`
adds parts into one :class:`Inertia` about the body's centre of mass with the parallel-axis
theorem. Cylinders have their axis along their own z.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = [
    "ALUMINIUM_DENSITY",
    "Inertia",
    "Part",
    "box_inertia",
    "composite_inertia",
    "cylinder_inertia",
    "parallel_axis",
]

ALUMINIUM_DENSITY = 2700.0
"""Default density of every body [kg/m³]."""


def _check_positive(name: str, value: float, *, parameter: str, element: str) -> None:
    if not (np.isfinite(value) and value > 0.0):
        raise ParameterError(
            f"{name} is {value!r}; allowed: a finite number > 0",
            parameter=parameter,
            value=value,
            allowed="a finite number > 0",
            element=element,
        )


def box_inertia(mass: float, size: tuple[float, float, float]) -> Array:
    """Inertia tensor of a solid box about its centre, in its own axes.

    Args:
        mass: mass [kg]
        size: edge lengths along x, y, z [m]

    Returns:
        3 × 3 inertia tensor [kg·m²].
    """
    x, y, z = size
    return mass / 12.0 * np.diag([y * y + z * z, x * x + z * z, x * x + y * y])


def cylinder_inertia(mass: float, radius: float, length: float) -> Array:
    """Inertia tensor of a solid cylinder about its centre, axis along z.

    Args:
        mass: mass [kg]
        radius: radius [m]
        length: length along z [m]

    Returns:
        3 × 3 inertia tensor [kg·m²].
    """
    transverse = mass * (3.0 * radius * radius + length * length) / 12.0
    return np.diag([transverse, transverse, mass * radius * radius / 2.0])


def parallel_axis(inertia_com: Array, mass: float, offset: Array) -> Array:
    """Move an inertia tensor from the centre of mass to a point (Steiner's theorem).

    Args:
        inertia_com: 3 × 3 inertia about the centre of mass [kg·m²]
        mass: mass [kg]
        offset: vector from the new point to the centre of mass [m]

    Returns:
        3 × 3 inertia about the new point [kg·m²].
    """
    r = np.asarray(offset, dtype=float)
    return inertia_com + mass * (float(r @ r) * np.eye(3) - np.outer(r, r))


@dataclass(frozen=True)
class Inertia:
    """Mass properties of a rigid body.

    Attributes:
        mass: mass [kg]
        com: centre of mass in the body frame [m]
        inertia_com: 3 × 3 inertia about the centre of mass, body axes [kg·m²]
    """

    mass: float
    com: Array = field(default_factory=lambda: np.zeros(3))
    inertia_com: Array = field(default_factory=lambda: np.zeros((3, 3)))


@dataclass(frozen=True)
class Part:
    """A solid of uniform density placed in a body frame.

    Attributes:
        shape: ``"box"`` or ``"cylinder"`` (axis along the part's z)
        dimensions: box ``(x, y, z)`` edge lengths or cylinder ``(radius, length)`` [m]
        T_body_part: pose of the part's centre in the body frame (4 × 4)
        density: density [kg/m³]
        role: what the part is (``"link"``, ``"housing"``, ``"rail"``, ``"slider"``, ``"tool"``)
    """

    shape: Literal["box", "cylinder"]
    dimensions: tuple[float, ...]
    T_body_part: Array
    density: float = ALUMINIUM_DENSITY
    role: str = "link"

    def __post_init__(self) -> None:
        _check_positive(
            f"{self.role} density [kg/m^3]", self.density, parameter="density", element=self.role
        )
        for value in self.dimensions:
            _check_positive(
                f"{self.role} dimension [m]", value, parameter="dimensions", element=self.role
            )

    @property
    def volume(self) -> float:
        """Volume [m³]."""
        if self.shape == "box":
            x, y, z = self.dimensions
            return x * y * z
        radius, length = self.dimensions
        return float(np.pi * radius * radius * length)

    @property
    def mass(self) -> float:
        """Mass [kg]."""
        return self.density * self.volume

    def inertia(self) -> Inertia:
        """Mass properties of the part, expressed in the body frame."""
        if self.shape == "box":
            x, y, z = self.dimensions
            I_part = box_inertia(self.mass, (x, y, z))
        else:
            radius, length = self.dimensions
            I_part = cylinder_inertia(self.mass, radius, length)
        R = self.T_body_part[:3, :3]
        return Inertia(self.mass, self.T_body_part[:3, 3].copy(), R @ I_part @ R.T)


def composite_inertia(parts: Iterable[Part]) -> Inertia:
    """Mass properties of a rigid body made of parts, about its combined centre of mass.

    Args:
        parts: the solids of the body

    Returns:
        The combined inertia; a body without parts has zero mass.
    """
    pieces = [part.inertia() for part in parts]
    mass = sum(piece.mass for piece in pieces)
    if mass == 0.0:
        return Inertia(0.0)
    com = sum((piece.mass * piece.com for piece in pieces), np.zeros(3)) / mass
    inertia_com = sum(
        (parallel_axis(piece.inertia_com, piece.mass, piece.com - com) for piece in pieces),
        np.zeros((3, 3)),
    )
    return Inertia(float(mass), com, inertia_com)
