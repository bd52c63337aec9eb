"""A parsed URDF: the frozen dataclass tree :func:`~aaria_pin.core.urdf_parse.parse_urdf` makes.

A :class:`UrdfDocument` holds a robot's links (:class:`UrdfLink`: inertial, visuals and
collisions with their geometry, origin and colour) and joints (:class:`UrdfJoint`: kind, ends,
origin, axis, limits, mimic), its named materials and every mesh file it names, with the
numbers exactly as the URDF text gives them.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from aaria_pin.core.se3 import Array

__all__ = [
    "JOINT_TYPES",
    "UrdfDocument",
    "UrdfGeometry",
    "UrdfInertial",
    "UrdfJoint",
    "UrdfLink",
    "UrdfOrigin",
    "UrdfShape",
    "Vector3",
]

JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed")
"""URDF joint types a simulation supports (``floating`` and ``planar`` are refused)."""

Vector3 = tuple[float, float, float]


@dataclass(frozen=True)
class UrdfOrigin:
    """An ``<origin>``: position [m] and roll, pitch, yaw [rad] (``R = Rz·Ry·Rx``)."""

    xyz: Vector3 = (0.0, 0.0, 0.0)
    rpy: Vector3 = (0.0, 0.0, 0.0)

    def rotation(self) -> Array:
        """The rotation matrix (Pinocchio's ``rpyToMatrix``, as its URDF reader)."""
        import pinocchio as pin

        return np.asarray(pin.rpy.rpyToMatrix(*self.rpy))

    def transform(self) -> Array:
        """The 4 × 4 pose."""
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = self.rotation(), self.xyz
        return T


@dataclass(frozen=True)
class UrdfGeometry:
    """A ``<geometry>``'s shape.

    Attributes:
        kind: its tag: ``box``, ``cylinder``, ``sphere``, ``mesh`` (others are kept by tag only)
        size: a box's edge lengths [m]
        radius: a cylinder's or sphere's radius [m]
        length: a cylinder's length [m]
        filename: a mesh's file as written
        scale: a mesh's scale factors
    """

    kind: str
    size: Vector3 = (0.0, 0.0, 0.0)
    radius: float = 0.0
    length: float = 0.0
    filename: str = ""
    scale: Vector3 = (1.0, 1.0, 1.0)


@dataclass(frozen=True)
class UrdfShape:
    """A ``<visual>`` or ``<collision>``.

    Attributes:
        geometry: its shape (None only for a joint's parts, which are not kept)
        origin: its pose in the link frame
        material: the name of its ``<material>`` ("" unnamed), None without one
        rgba: the colour given inline in its material, else None
    """

    geometry: UrdfGeometry | None
    origin: UrdfOrigin = field(default_factory=UrdfOrigin)
    material: str | None = None
    rgba: tuple[float, ...] | None = None


@dataclass(frozen=True)
class UrdfInertial:
    """A link's ``<inertial>``: mass [kg], inertia about the centre of mass [kg·m²].

    Attributes:
        origin: the centre of mass and the inertia's axes in the link frame
        mass: mass (0 without ``<mass>``)
        inertia: ``ixx ixy ixz iyy iyz izz`` (0 where not given)
    """

    origin: UrdfOrigin
    mass: float
    inertia: tuple[float, float, float, float, float, float]

    def matrix(self) -> Array:
        """The 3 × 3 inertia matrix in the inertial frame [kg·m²]."""
        ixx, ixy, ixz, iyy, iyz, izz = self.inertia
        return np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])


@dataclass(frozen=True)
class UrdfLink:
    """A ``<link>``: its inertial (None without one), visuals and collisions in order."""

    name: str
    inertial: UrdfInertial | None = None
    visuals: tuple[UrdfShape, ...] = ()
    collisions: tuple[UrdfShape, ...] = ()


@dataclass(frozen=True)
class UrdfJoint:
    """A joint of the URDF.

    Attributes:
        name: joint name
        kind: one of :data:`JOINT_TYPES`
        parent: parent link
        child: child link
        lower: lower position limit [rad or m] (-inf for a continuous joint)
        upper: upper position limit [rad or m] (+inf for a continuous joint)
        velocity: velocity limit [rad/s or m/s] (inf if not given)
        mimic: (leader joint, multiplier, offset) of a mimic joint, else None
        effort: effort limit [N·m or N] (inf if not given or 0)
        origin: the joint frame in the parent link frame
        axis: the joint axis in its frame, as written (not normalised)
    """

    name: str
    kind: str
    parent: str
    child: str
    lower: float
    upper: float
    velocity: float
    mimic: tuple[str, float, float] | None
    effort: float = np.inf
    origin: UrdfOrigin = field(default_factory=UrdfOrigin)
    axis: Vector3 = (1.0, 0.0, 0.0)


@dataclass(frozen=True)
class UrdfDocument:
    """A parsed, checked URDF.

    Attributes:
        name: the robot's name
        root_link: the one link that is no joint's child
        links: links in document order
        joints: joints in document order
        materials: (name, rgba) of every material with a colour, first definition of a name
            (top level, or inside a visual and reused by name)
        meshes: every mesh file name as written, in document order
    """

    name: str
    root_link: str
    links: tuple[UrdfLink, ...]
    joints: tuple[UrdfJoint, ...]
    materials: tuple[tuple[str, tuple[float, ...]], ...]
    meshes: tuple[str, ...]

    @property
    def link_names(self) -> tuple[str, ...]:
        """Link names in document order."""
        return tuple(link.name for link in self.links)

    def link(self, name: str) -> UrdfLink:
        """A link by name (KeyError if absent)."""
        for link in self.links:
            if link.name == name:
                return link
        raise KeyError(name)

    def colour(self, shape: UrdfShape) -> tuple[float, ...] | None:
        """A shape's colour: inline, else its named material's, else None."""
        if shape.rgba is not None:
            return shape.rgba
        return dict(self.materials).get(shape.material or "") if shape.material else None
