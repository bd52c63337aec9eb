"""The ``<body>`` tree of an MJCF: a body per URDF link, its inertial, joint, shapes and sites.

One ``body`` per URDF link (fixed links too, welded to their parent), with its ``inertial``
(mass, centre of mass, full inertia in the link frame), a ``hinge`` or ``slide`` joint about
the URDF axis with its range, a ``site`` at every IMU mount, and the visual shapes (boxes,
cylinders, spheres, and STL or OBJ meshes; a link whose visual mesh MuJoCo cannot read, such as
a COLLADA ``.dae``, shows its collision meshes instead), none of them colliding. Mesh files are
named by their absolute paths (the model is for this machine's installed meshes). Everything is
read from the one parsed URDF (:func:`~aaria_pin.core.urdf_parse.parse_urdf`); numbers are
written in their shortest exact form, so the compiled model holds the URDF's floats.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from aaria_pin.core.record import ImuMount
from aaria_pin.core.se3 import Array
from aaria_pin.core.urdf_check import resolve_mesh
from aaria_pin.core.urdf_emitter import exact_number, exact_numbers
from aaria_pin.core.urdf_tree import UrdfDocument, UrdfJoint, UrdfLink, UrdfShape
from aaria_pin.errors import ModelError

__all__ = [
    "MESH_SUFFIXES",
    "NEGLIGIBLE_INERTIA",
    "NEGLIGIBLE_MASS",
    "MeshAssets",
    "body_name",
    "floored_links",
    "link_geoms",
    "link_inertial",
    "link_sites",
    "mjcf_joint",
    "placement",
]

MESH_SUFFIXES = (".stl", ".obj")
"""Mesh files MuJoCo reads, written as mesh assets (others are left out)."""

NEGLIGIBLE_MASS = 1e-12
"""Mass given to a link that moves on its own joint with no mass welded to it [kg].

MuJoCo refuses a moving body without mass or without moments (below 1e-15: a "virtual" link
between the hinges of a spherical joint, a point mass); this mass and
:data:`NEGLIGIBLE_INERTIA` change torques by about 1e-11 N·m."""
NEGLIGIBLE_INERTIA = 1e-12
"""Principal moments given to such a link, or added to a point mass's [kg·m²]."""

_MJ_MINVAL = 1e-15
"""MuJoCo's ``mjMINVAL``: the smallest principal moment its ``fullinertia`` accepts."""
_NEUTRAL_GREY = (0.7, 0.7, 0.7, 1.0)


def _quat(R: Array) -> str:
    """A rotation matrix as MuJoCo's quaternion ``w x y z``."""
    import pinocchio as pin

    x, y, z, w = pin.Quaternion(np.asarray(R, dtype=float)).coeffs()
    return exact_numbers((w, x, y, z))


def placement(xyz: Array | Sequence[float], R: Array) -> str:
    """``pos`` and ``quat`` attributes (left out where they are the identity)."""
    text = ""
    if np.any(xyz):
        text += f' pos="{exact_numbers(xyz)}"'
    if not np.array_equal(R, np.eye(3)):
        text += f' quat="{_quat(R)}"'
    return text


def _mass_properties(link: UrdfLink) -> tuple[float, Array]:
    """A link's mass [kg] and inertia about its centre of mass in the inertial frame [kg·m²]."""
    if link.inertial is None:
        return 0.0, np.zeros((3, 3))
    return link.inertial.mass, link.inertial.matrix()


def _negligible(link: UrdfLink) -> bool:
    """Whether MuJoCo takes a link as without mass or without moments (below 1e-15)."""
    mass, inertia = _mass_properties(link)
    return mass <= _MJ_MINVAL or float(np.abs(inertia).max()) <= _MJ_MINVAL


def link_inertial(link: UrdfLink, floor: bool) -> str:
    """The ``<inertial>`` of a link, its inertia in the link frame ("" for a massless frame).

    A positive definite inertia is written whole (``fullinertia``, no ``quat``); MuJoCo
    refuses others there (a point mass, a flat body, moments below 1e-15 kg·m²), so theirs is
    written as principal moments (``diaginertia``, negative round-off set to 0) in its
    principal axes (``quat``).

    Args:
        link: the URDF link
        floor: the link moves on its own joint and nothing welded to it has mass and moments
            (a "virtual" link between the hinges of a spherical joint, a point mass); MuJoCo
            refuses such a body, so a massless one gets :data:`NEGLIGIBLE_MASS` and
            :data:`NEGLIGIBLE_INERTIA`, and a point mass :data:`NEGLIGIBLE_INERTIA` added to
            its moments
    """
    mass, inertia = _mass_properties(link)
    if floor and mass > _MJ_MINVAL:
        inertia = inertia + NEGLIGIBLE_INERTIA * np.eye(3)
    elif floor:
        moment = exact_number(NEGLIGIBLE_INERTIA)
        diagonal = f'diaginertia="{moment} {moment} {moment}"'
        return f'<inertial pos="0 0 0" mass="{exact_number(NEGLIGIBLE_MASS)}" {diagonal}/>'
    if mass <= 0.0 and not np.any(inertia):
        return ""  # a massless frame; a zero mass with moments (Bolt's feet) keeps its moments
    origin = link.inertial.origin if link.inertial is not None else None
    xyz = np.zeros(3) if origin is None else np.array(origin.xyz)
    R = np.eye(3) if origin is None else origin.rotation()
    inertia = R @ inertia @ R.T
    position = f'pos="{exact_numbers(xyz)}" mass="{exact_number(mass)}"'
    moments, axes = np.linalg.eigh(inertia)
    if moments[0] > _MJ_MINVAL:
        full = [inertia[k] for k in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))]
        return f'<inertial {position} fullinertia="{exact_numbers(full)}"/>'
    if np.linalg.det(axes) < 0:
        axes[:, 0] = -axes[:, 0]
    moments = np.maximum(moments, 0.0)
    return f'<inertial {position} quat="{_quat(axes)}" diaginertia="{exact_numbers(moments)}"/>'


class MeshAssets:
    """The mesh assets of a model: one per mesh file and scale, by absolute path.

    Meshes only draw (masses come from the URDF's inertials): each is declared
    ``inertia="shell"``, which MuJoCo accepts for open or thin meshes too, where a volume
    would be refused ("mesh volume is too small").
    """

    def __init__(self, urdf_dir: Path | None) -> None:
        self.urdf_dir = urdf_dir
        self.assets: dict[tuple[str, str], str] = {}
        self.skipped: list[str] = []

    def asset(self, filename: str, factors: Sequence[float]) -> str | None:
        """The asset name of a mesh file, or None when MuJoCo cannot read it or it is missing."""
        path = resolve_mesh(filename, self.urdf_dir)
        if path is None or path.suffix.lower() not in MESH_SUFFIXES:
            self.skipped.append(filename)
            return None
        scale = "" if all(f == 1.0 for f in factors) else f' scale="{exact_numbers(factors)}"'
        key = (str(path.resolve()), scale)
        return self.assets.setdefault(key, f"mesh_{len(self.assets)}")

    def xml(self) -> str:
        """The ``<mesh>`` elements of the ``<asset>`` section."""
        return "".join(
            f'    <mesh name="{name}" file={quoteattr(path)}{scale} inertia="shell"/>\n'
            for (path, scale), name in self.assets.items()
        )


def _geom(shape: UrdfShape, rgba: Sequence[float], meshes: MeshAssets) -> str | None:
    """A ``<geom>`` of a URDF visual or collision, or None if MuJoCo cannot draw it."""
    geometry = shape.geometry
    if geometry is None:
        return None
    if geometry.kind == "box":
        size = f'type="box" size="{exact_numbers(np.array(geometry.size) / 2)}"'
    elif geometry.kind == "cylinder":
        size = f'type="cylinder" size="{exact_numbers((geometry.radius, geometry.length / 2))}"'
    elif geometry.kind == "sphere":
        size = f'type="sphere" size="{exact_number(geometry.radius)}"'
    elif geometry.kind == "mesh":
        name = meshes.asset(geometry.filename, geometry.scale)
        if name is None:
            return None
        size = f'type="mesh" mesh="{name}"'
    else:
        return None
    pose = placement(shape.origin.xyz, shape.origin.rotation())
    return f'<geom {size}{pose} rgba="{exact_numbers(rgba)}"/>'


def link_geoms(link: UrdfLink, document: UrdfDocument, meshes: MeshAssets) -> list[str]:
    """A link's visual geoms; its collision meshes where a visual mesh cannot be read."""
    geoms: list[str] = []
    unreadable: list[Sequence[float]] = []
    for visual in link.visuals:
        colour = document.colour(visual) if visual.material is not None else None
        rgba = _NEUTRAL_GREY if colour is None else colour
        geom = _geom(visual, rgba, meshes)
        if geom is not None:
            geoms.append(geom)
        elif visual.geometry is not None and visual.geometry.kind == "mesh":
            unreadable.append(rgba)
    if unreadable:
        for collision in link.collisions:
            if collision.geometry is not None and collision.geometry.kind == "mesh":
                geom = _geom(collision, unreadable[0], meshes)
                if geom is not None:
                    geoms.append(geom)
    return geoms


def body_name(link: str) -> str:
    """The body of a link: its name, but ``world`` (MuJoCo's world body) becomes ``world_link``."""
    return "world_link" if link == "world" else link


def _frame_links(document: UrdfDocument) -> dict[str, str]:
    """Frame name → the link it is fixed to: every link, and every joint's child link."""
    links = {name: name for name in document.link_names}
    for joint in document.joints:
        links.setdefault(joint.name, joint.child)
    return links


def link_sites(
    document: UrdfDocument, imu_mounts: Sequence[ImuMount], tool_frame: str | None
) -> dict[str, list[str]]:
    """Link name → its ``<site>`` elements: one per IMU, at its mount, and the tool's.

    Raises:
        ModelError: an IMU's parent or the tool frame is not a link or joint of the URDF.
    """
    frame_links = _frame_links(document)
    sites: dict[str, list[str]] = {}
    for mount in imu_mounts:
        if not mount.parent:
            continue  # an empty slot: no IMU
        if mount.parent not in frame_links:
            raise ModelError(
                f"IMU {mount.name!r}: parent frame {mount.parent!r} is not in the URDF; "
                "allowed: a link or joint of the URDF",
                parameter="imu_mounts",
                value=mount.parent,
                element=mount.name,
            )
        T = np.asarray(mount.T_parent_imu, dtype=float)
        sites.setdefault(frame_links[mount.parent], []).append(
            f"<site name={quoteattr(mount.name)}{placement(T[:3, 3], T[:3, :3])}"
            ' size="0.01" rgba="1 0.5 0 1"/>'
        )
    if tool_frame:
        if tool_frame not in frame_links:
            raise ModelError(
                f"tool frame {tool_frame!r} is not in the URDF; allowed: a link or joint",
                parameter="tool_frame",
                value=tool_frame,
            )
        sites.setdefault(frame_links[tool_frame], []).append(
            f'<site name={quoteattr(tool_frame)} size="0.005" rgba="1 0 0 1"/>'
        )
    return sites


def floored_links(document: UrdfDocument, base: str | None) -> set[str]:
    """Moving links without mass or moments: :func:`link_inertial`'s ``floor``.

    A link on its own joint (or ``base`` on the base chain) none of whose welded links (itself
    and those on fixed joints below it) has both mass and moments.
    """
    fixed_children: dict[str, list[str]] = {}
    moving = set() if base is None else {base}
    for joint in document.joints:
        if joint.kind == "fixed":
            fixed_children.setdefault(joint.parent, []).append(joint.child)
        else:
            moving.add(joint.child)

    def negligible(link: str) -> bool:
        welded = fixed_children.get(link, [])
        return _negligible(document.link(link)) and all(negligible(child) for child in welded)

    return {link for link in moving if negligible(link)}


def mjcf_joint(joint: UrdfJoint, attributes: str = "") -> str:
    """The MJCF joint of a URDF revolute, continuous or prismatic joint.

    Args:
        joint: the URDF joint
        attributes: more attributes, written last (e.g. its actuator's, with a leading space)

    Returns:
        The ``<joint …/>`` element.
    """
    axis = np.array(joint.axis, dtype=float)
    axis = axis / np.linalg.norm(axis)
    limits = ' limited="false"'
    if joint.kind != "continuous" and joint.lower < joint.upper:
        # MuJoCo refuses an empty range: such a joint is left unlimited
        limits = f' limited="true" range="{exact_numbers((joint.lower, joint.upper))}"'
    kind = "slide" if joint.kind == "prismatic" else "hinge"
    return (
        f'<joint name={quoteattr(joint.name)} type="{kind}" axis="{exact_numbers(axis)}"{limits}'
        f"{attributes}/>"
    )
