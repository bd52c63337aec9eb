"""A robot description: the tree of links and joints the URDF emitter writes.

A :class:`RobotDescription` is a tree of links and joints rooted at its first link
(:func:`aaria_pin.core.urdf_emitter.emit_urdf` writes it as URDF).

- A link (:class:`LinkDescription`) carries solid parts (:class:`~aaria_pin.core.inertia.Part`,
  boxes and cylinders of a density: its inertia, and a visual and a collision shape each),
  further shapes (:class:`Shape`: boxes, cylinders, spheres or mesh files, visual, collision
  or both, with a :class:`Material`), and optionally measured mass properties that replace the
  parts' (a mesh link's come from its mesh).
- A joint (:class:`JointDescription`) is revolute, continuous, prismatic or fixed, about or
  along any unit axis of its own frame (z by default), with limits, and is placed by a 4 × 4
  transform from the parent link's frame.

Materials and joint kinds are named here once. :func:`aaria_pin.core.model.model_from_description`
builds the Pinocchio model of a description without the XML; it equals the parsed URDF's.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Literal, get_args

import numpy as np

from aaria_pin.core.inertia import Inertia, Part, composite_inertia
from aaria_pin.core.se3 import Array

__all__ = [
    "JOINT_GREEN",
    "JOINT_KINDS",
    "LINK_BLUE",
    "PART_MATERIALS",
    "Box",
    "Cylinder",
    "Geometry",
    "JointDescription",
    "JointKind",
    "LinkDescription",
    "Material",
    "Mesh",
    "RobotDescription",
    "Shape",
    "Sphere",
]

JointKind = Literal["revolute", "continuous", "prismatic", "fixed"]
JOINT_KINDS: tuple[JointKind, ...] = get_args(JointKind)
"""The joint types the emitter writes."""


@dataclass(frozen=True)
class Box:
    """A box centred on its shape frame.

    Attributes:
        size: edge lengths along x, y, z [m]
    """

    size: tuple[float, float, float]


@dataclass(frozen=True)
class Cylinder:
    """A cylinder centred on its shape frame, axis along z.

    Attributes:
        radius: radius [m]
        length: length along z [m]
    """

    radius: float
    length: float


@dataclass(frozen=True)
class Sphere:
    """A sphere centred on its shape frame.

    Attributes:
        radius: radius [m]
    """

    radius: float


@dataclass(frozen=True)
class Mesh:
    """A mesh file, in its shape frame.

    Attributes:
        filename: the ``filename`` as written in the URDF (relative to it, or ``package://``)
        scale: scale factors along x, y, z (written only when not all 1)
    """

    filename: str
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)


Geometry = Box | Cylinder | Sphere | Mesh
"""A shape's geometry."""


@dataclass(frozen=True)
class Material:
    """A named colour, declared once at the top of the URDF.

    Attributes:
        name: material name
        rgba: red, green, blue, alpha, each in [0, 1]
    """

    name: str
    rgba: tuple[float, float, float, float]


JOINT_GREEN = Material("joint_green", (0.13, 0.69, 0.30, 1.0))
"""Colour of housings, rails and sliders."""
LINK_BLUE = Material("link_blue", (0.20, 0.35, 0.85, 1.0))
"""Colour of links and tools."""
PART_MATERIALS = (JOINT_GREEN, LINK_BLUE)
"""The materials of solid parts, declared by default in every robot."""

_MATERIAL_OF_ROLE = {
    "housing": JOINT_GREEN,
    "rail": JOINT_GREEN,
    "slider": JOINT_GREEN,
    "link": LINK_BLUE,
    "tool": LINK_BLUE,
}


@dataclass(frozen=True)
class Shape:
    """A visual and/or collision shape of a link (no mass: a link's mass is its parts').

    Attributes:
        geometry: box, cylinder, sphere or mesh
        T_link_shape: pose of the shape frame in the link frame (4 × 4)
        material: its colour (visuals only), or None
        name: the ``name`` attribute of its ``<visual>`` and ``<collision>`` (default
            ``<link>_shape_<index>``)
        visual: write a ``<visual>``
        collision: write a ``<collision>``
    """

    geometry: Geometry
    T_link_shape: Array = field(default_factory=lambda: np.eye(4))
    material: Material | None = None
    name: str = ""
    visual: bool = True
    collision: bool = True


def _part_shape(part: Part, name: str) -> Shape:
    """The visual and collision shape of a solid part, coloured by its role."""
    geometry: Geometry
    if part.shape == "box":
        x, y, z = part.dimensions
        geometry = Box((x, y, z))
    else:
        radius, length = part.dimensions
        geometry = Cylinder(radius, length)
    material = _MATERIAL_OF_ROLE.get(part.role, LINK_BLUE)
    return Shape(geometry, part.T_body_part, material, name)


@dataclass(frozen=True)
class LinkDescription:
    """A link: its name, its solids, further shapes, and optionally measured mass properties.

    A link without solids or mass properties is a massless frame link; measured mass properties
    (from a CAD report, or a mesh and a density) replace those computed from the solids.

    Attributes:
        name: link name
        parts: solid parts: their inertias add up, each is a visual and a collision box or
            cylinder
        mass_properties: mass properties in the link frame, replacing the parts'
        shapes: further visual/collision shapes (written after the parts'), massless
    """

    name: str
    parts: tuple[Part, ...] = ()
    mass_properties: Inertia | None = None
    shapes: tuple[Shape, ...] = ()

    def inertia(self) -> Inertia | None:
        """The link's mass properties: the measured ones, else the solids', else None."""
        if self.mass_properties is not None:
            return self.mass_properties
        return composite_inertia(self.parts) if self.parts else None

    def all_shapes(self) -> tuple[Shape, ...]:
        """The parts' shapes (named ``<link>_<role>_<index>``), then :attr:`shapes`."""
        solids = tuple(
            _part_shape(part, f"{self.name}_{part.role}_{index}")
            for index, part in enumerate(self.parts)
        )
        start = len(solids)
        extra = tuple(
            shape if shape.name else replace(shape, name=f"{self.name}_shape_{start + index}")
            for index, shape in enumerate(self.shapes)
        )
        return solids + extra


@dataclass(frozen=True)
class JointDescription:
    """A joint between two links.

    Attributes:
        name: joint name
        kind: ``"revolute"``, ``"continuous"`` (revolute without position limits),
            ``"prismatic"`` or ``"fixed"``
        parent: parent link name
        child: child link name
        T_parent_child: pose of the joint (and child link) frame in the parent link frame at
            q = 0
        lower: lower limit [rad or m] (not written for a continuous joint)
        upper: upper limit [rad or m] (not written for a continuous joint)
        effort: effort limit [N·m or N]
        velocity: velocity limit [rad/s or m/s]
        axis: the joint's axis in its own frame (a unit vector)
    """

    name: str
    kind: JointKind
    parent: str
    child: str
    T_parent_child: Array
    lower: float = 0.0
    upper: float = 0.0
    effort: float = 1.0e4
    velocity: float = 1.0e2
    axis: tuple[float, float, float] = (0.0, 0.0, 1.0)


@dataclass(frozen=True)
class RobotDescription:
    """A robot as a tree of links and joints, rooted at ``links[0]``.

    Attributes:
        name: robot name
        links: the links, root first
        joints: the joints, each naming two links of ``links``
        comment: a comment written at the top of the URDF
        materials: materials declared at the top in this order (the solid parts' by default);
            any other material a shape uses is declared after them
    """

    name: str
    links: tuple[LinkDescription, ...]
    joints: tuple[JointDescription, ...]
    comment: str = field(default="generated by aaria_pin")
    materials: tuple[Material, ...] = PART_MATERIALS
