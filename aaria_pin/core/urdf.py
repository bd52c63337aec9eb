"""The one URDF emitter: a robot description written as URDF by filling ``urdf_templates/``.

A :class:`RobotDescription` is a tree of links and joints rooted at its first link.

- A link (:class:`LinkDescription`) carries solid parts (:class:`~aaria_pin.core.inertia.Part`,
  boxes and cylinders of a density: its inertia, and a visual and a collision shape each),
  further shapes (:class:`Shape`: boxes, cylinders, spheres or mesh files, visual, collision
  or both, with a :class:`Material`), and optionally measured mass properties that replace the
  parts' (a mesh link's come from its mesh).
- A joint (:class:`JointDescription`) is revolute, continuous, prismatic or fixed, about or
  along any unit axis of its own frame (z by default), with limits, and is placed by a 4 × 4
  transform from the parent link's frame.

Origins are written as ``xyz`` and ``rpy`` (``R = Rz·Ry·Rx``) derived from the whole rotation
matrix, so any transform, not only a single axis rotation, survives the trip. Numbers are
written in their shortest exact form. :func:`aaria_pin.core.model.model_from_description`
builds the Pinocchio model of a description without the XML; it equals the parsed URDF's.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from functools import cache
from importlib import resources
from pathlib import Path
from string import Template
from typing import Literal
from xml.sax.saxutils import quoteattr

import numpy as np

from aaria_pin.core.inertia import Inertia, Part, composite_inertia
from aaria_pin.core.se3 import Array, rpy_from_matrix
from aaria_pin.errors import ModelError

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
    "emit_urdf",
    "template_dir",
]

JointKind = Literal["revolute", "continuous", "prismatic", "fixed"]
JOINT_KINDS: tuple[JointKind, ...] = ("revolute", "continuous", "prismatic", "fixed")
"""The joint types the emitter writes."""

_UNIT_TOLERANCE = 1e-9


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


def template_dir() -> Path:
    """Folder of the URDF fragments: inside the installed package, else the checkout's."""
    packaged = Path(str(resources.files("aaria_pin"))) / "urdf_templates"
    if packaged.is_dir():
        return packaged
    return Path(__file__).resolve().parents[2] / "urdf_templates"


@cache
def _template(name: str) -> Template:
    return Template((template_dir() / name).read_text(encoding="utf-8"))


def _num(value: float) -> str:
    return repr(float(value) + 0.0)  # shortest exact form; + 0.0 turns -0.0 into 0.0


def _vec(values: Sequence[float] | Array) -> str:
    return " ".join(_num(v) for v in values)


def _whole_or_num(value: float) -> str:
    """A whole number without decimals (an axis "0 0 1"), else the shortest exact form."""
    value = float(value) + 0.0
    return str(int(value)) if value.is_integer() else repr(value)


def _colour(value: float) -> str:
    """A colour component: whole as "1", else at least two decimals ("0.30"), exactly."""
    value = float(value) + 0.0
    if value.is_integer():
        return str(int(value))
    decimals = len(np.format_float_positional(value, trim="-").partition(".")[2])
    return f"{value:.{max(2, decimals)}f}"


def _origin(T: Array) -> dict[str, str]:
    return {"xyz": _vec(T[:3, 3]), "rpy": _vec(rpy_from_matrix(T[:3, :3]))}


def _geometry(geometry: Geometry) -> str:
    if isinstance(geometry, Box):
        return f'<box size="{_vec(geometry.size)}"/>'
    if isinstance(geometry, Cylinder):
        return f'<cylinder radius="{_num(geometry.radius)}" length="{_num(geometry.length)}"/>'
    if isinstance(geometry, Sphere):
        return f'<sphere radius="{_num(geometry.radius)}"/>'
    scale = ""
    if tuple(geometry.scale) != (1.0, 1.0, 1.0):
        scale = f' scale="{_vec(geometry.scale)}"'
    return f"<mesh filename={quoteattr(geometry.filename)}{scale}/>"


def _shape_xml(shape: Shape) -> str:
    fields = {"name": shape.name, "geometry": _geometry(shape.geometry)}
    fields |= _origin(shape.T_link_shape)
    text = ""
    if shape.visual:
        material = ""
        if shape.material is not None:
            material = _template("visual_material.xml").substitute(material=shape.material.name)
        text += _template("visual.xml").substitute(fields, material=material)
    if shape.collision:
        text += _template("collision.xml").substitute(fields)
    return text


def _link_xml(link: LinkDescription) -> str:
    body = ""
    inertia = link.inertia()
    if inertia is not None:
        I = inertia.inertia_com
        body += _template("inertial.xml").substitute(
            xyz=_vec(inertia.com),
            mass=_num(inertia.mass),
            ixx=_num(I[0, 0]),
            ixy=_num(I[0, 1]),
            ixz=_num(I[0, 2]),
            iyy=_num(I[1, 1]),
            iyz=_num(I[1, 2]),
            izz=_num(I[2, 2]),
        )
    body += "".join(_shape_xml(shape) for shape in link.all_shapes())
    return _template("link.xml").substitute(name=link.name, body=body)


def _joint_xml(joint: JointDescription) -> str:
    motion = ""
    if joint.kind != "fixed":
        limits = ""
        if joint.kind != "continuous":
            limits = f' lower="{_num(joint.lower)}" upper="{_num(joint.upper)}"'
        motion = _template("joint_motion.xml").substitute(
            axis=" ".join(_whole_or_num(v) for v in joint.axis),
            limits=limits,
            effort=_num(joint.effort),
            velocity=_num(joint.velocity),
        )
    return _template("joint.xml").substitute(
        name=joint.name,
        kind=joint.kind,
        parent=joint.parent,
        child=joint.child,
        motion=motion,
        **_origin(joint.T_parent_child),
    )


def _materials(description: RobotDescription) -> tuple[Material, ...]:
    """The declared materials, then the shapes' others, each once by name.

    Raises:
        ModelError: two materials of the same name with different colours.
    """
    used = [
        shape.material
        for link in description.links
        for shape in link.all_shapes()
        if shape.visual and shape.material is not None
    ]
    declared: dict[str, Material] = {}
    for material in (*description.materials, *used):
        known = declared.setdefault(material.name, material)
        if tuple(known.rgba) != tuple(material.rgba):
            raise ModelError(
                f"material {material.name!r} has colours {known.rgba} and {material.rgba};"
                " allowed: one colour per material name"
            )
    return tuple(declared.values())


def _material_xml(material: Material) -> str:
    return _template("material.xml").substitute(
        name=material.name, rgba=" ".join(_colour(v) for v in material.rgba)
    )


def _check_tree(description: RobotDescription) -> None:
    names = [link.name for link in description.links]
    if not names:
        raise ModelError(f"robot {description.name!r} has no link; allowed: at least a root link")
    if len(set(names)) != len(names):
        raise ModelError(f"robot {description.name!r}: duplicate link names in {names}")
    children = [joint.child for joint in description.joints]
    if len(set(children)) != len(children):
        raise ModelError(
            f"robot {description.name!r}: a link is the child of two joints in {children}"
        )
    joint_names = [joint.name for joint in description.joints]
    if len(set(joint_names)) != len(joint_names):
        raise ModelError(f"robot {description.name!r}: duplicate joint names in {joint_names}")
    known = set(names)
    for joint in description.joints:
        for end in (joint.parent, joint.child):
            if end not in known:
                raise ModelError(f"joint {joint.name!r}: link {end!r} is not in the robot")
    roots = known - set(children)
    if roots != {names[0]}:
        raise ModelError(
            f"robot {description.name!r}: expected one root {names[0]!r}, got {sorted(roots)}"
        )


def _check_joints(description: RobotDescription) -> None:
    for joint in description.joints:
        if joint.kind not in JOINT_KINDS:
            raise ModelError(
                f"joint {joint.name!r} kind is {joint.kind!r}; allowed: {', '.join(JOINT_KINDS)}"
            )
        T = np.asarray(joint.T_parent_child, dtype=float)
        if T.shape != (4, 4) or not np.all(np.isfinite(T)):
            raise ModelError(
                f"joint {joint.name!r} T_parent_child is not a finite 4 × 4 transform;"
                " allowed: [R p; 0 0 0 1]"
            )
        if joint.kind == "fixed":
            continue
        axis = np.asarray(joint.axis, dtype=float)
        if axis.shape != (3,) or abs(float(np.linalg.norm(axis)) - 1.0) > _UNIT_TOLERANCE:
            raise ModelError(
                f"joint {joint.name!r} axis is {joint.axis}; allowed: a unit vector of 3 numbers"
            )
        limits: tuple[float, ...] = (joint.effort, joint.velocity)
        if joint.kind != "continuous":
            limits += (joint.lower, joint.upper)
        if not np.all(np.isfinite(limits)):
            raise ModelError(f"joint {joint.name!r} limits are {limits}; allowed: finite numbers")
        if joint.kind != "continuous" and joint.lower > joint.upper:
            raise ModelError(
                f"joint {joint.name!r} lower limit is {joint.lower}; allowed: <= upper limit"
                f" {joint.upper}"
            )


_XML_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_.-]*")


def _check_names(description: RobotDescription, materials: Sequence[Material]) -> None:
    names = [description.name, *(link.name for link in description.links)]
    names += [joint.name for joint in description.joints]
    names += [material.name for material in materials]
    names += [shape.name for link in description.links for shape in link.all_shapes()]
    for name in names:
        if not _XML_NAME.fullmatch(name):
            raise ModelError(
                f"name {name!r} is not allowed in a URDF; allowed: letters, digits, '_', '.', '-'"
                " (not first)"
            )
    for material in materials:
        rgba = np.asarray(material.rgba, dtype=float)
        if rgba.shape != (4,) or not np.all((rgba >= 0.0) & (rgba <= 1.0)):
            raise ModelError(
                f"material {material.name!r} rgba is {material.rgba}; allowed: 4 numbers in [0, 1]"
            )


def emit_urdf(description: RobotDescription) -> str:
    """Write a robot description as URDF text.

    Args:
        description: links and joints; the first link is the root

    Returns:
        The URDF document.

    Raises:
        ModelError: duplicate link or joint names, a joint naming an unknown link, not one root,
            a name that is not an XML name, an unknown joint kind, an axis that is not a unit
            vector, limits that are not finite or a lower limit above the upper, a colour out
            of [0, 1], or one material name with two colours.
    """
    _check_tree(description)
    _check_joints(description)
    materials = _materials(description)
    _check_names(description, materials)
    return _template("robot.urdf").substitute(
        name=description.name,
        comment=description.comment.replace("--", "- -"),
        materials="".join(_material_xml(material) for material in materials),
        links="".join(_link_xml(link) for link in description.links),
        joints="".join(_joint_xml(joint) for joint in description.joints),
    )
