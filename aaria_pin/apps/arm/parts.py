"""Meshes of the arm's parts (trimesh), their STL files, and mass properties from mesh × density.

Every part is a closed triangle mesh built from trimesh primitives: boxes, polygonal cylinders,
rings (annuli) and extrusions of convex outlines (a link's "stadium": a bar with round ends).
A part made of several solids concatenates them; the solids never overlap, so the volume
integrals of the concatenated mesh are the sums of the solids' (no boolean union is needed).

Mass properties come from trimesh's divergence-theorem integrals: ``Trimesh.mass_properties``
with ``density`` set gives the mass, the centre of mass and the inertia tensor about the
centre of mass in the mesh's own axes (``moment_inertia``), already scaled by the density.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.inertia import Inertia
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = [
    "CYLINDER_SECTIONS",
    "MeshPart",
    "box_mesh",
    "combine",
    "cylinder_mesh",
    "export_stl",
    "mesh_inertia",
    "prism_inertia",
    "ring_mesh",
    "stadium_mesh",
]

CYLINDER_SECTIONS = 48
"""Sides of the polygon that approximates a circle in every round part."""


def _positive(name: str, value: float, parameter: str) -> float:
    if not (np.isfinite(value) and value > 0.0):
        raise ParameterError(
            f"{name} is {value!r}; allowed: a finite number > 0", parameter=parameter, value=value
        )
    return float(value)


def _moved(mesh: Any, center: Sequence[float]) -> Any:
    mesh.apply_translation(np.asarray(center, dtype=float))
    return mesh


def box_mesh(size: Sequence[float], center: Sequence[float] = (0.0, 0.0, 0.0)) -> Any:
    """A solid box.

    Args:
        size: edge lengths along x, y, z [m]
        center: its centre in the part frame [m]

    Returns:
        A watertight ``trimesh.Trimesh``.
    """
    import trimesh

    for axis, value in zip("xyz", size, strict=True):
        _positive(f"box size along {axis}", value, "size")
    return _moved(trimesh.creation.box(extents=np.asarray(size, dtype=float)), center)


def cylinder_mesh(
    radius: float,
    length: float,
    center: Sequence[float] = (0.0, 0.0, 0.0),
    sections: int = CYLINDER_SECTIONS,
) -> Any:
    """A solid cylinder (a prism on a regular polygon inscribed in the circle), axis along z.

    Args:
        radius: radius of the circle the polygon is inscribed in [m]
        length: length along z [m]
        center: its centre in the part frame [m]
        sections: sides of the polygon

    Returns:
        A watertight ``trimesh.Trimesh``.
    """
    import trimesh

    _positive("cylinder radius", radius, "radius")
    _positive("cylinder length", length, "length")
    mesh = trimesh.creation.cylinder(radius=radius, height=length, sections=sections)
    return _moved(mesh, center)


def ring_mesh(
    inner: float,
    outer: float,
    length: float,
    center: Sequence[float] = (0.0, 0.0, 0.0),
    sections: int = CYLINDER_SECTIONS,
) -> Any:
    """A thick ring (a collar around the pillar), axis along z.

    Args:
        inner: inner radius [m]
        outer: outer radius [m], > inner
        length: length along z [m]
        center: its centre in the part frame [m]
        sections: sides of the polygons

    Returns:
        A watertight ``trimesh.Trimesh``.
    """
    import trimesh

    _positive("ring inner radius", inner, "inner")
    _positive("ring length", length, "length")
    if not outer > inner:
        raise ParameterError(
            f"ring outer radius {outer!r} m; allowed: > inner radius {inner} m",
            parameter="outer",
            value=outer,
        )
    mesh = trimesh.creation.annulus(r_min=inner, r_max=outer, height=length, sections=sections)
    return _moved(mesh, center)


def stadium_mesh(
    length: float,
    width: float,
    thickness: float,
    z_center: float = 0.0,
    sections: int = CYLINDER_SECTIONS,
) -> Any:
    """A link bar: the extrusion of a stadium (a rectangle with half-disc ends) along z.

    The outline runs from the circle of diameter ``width`` about the origin to the one about
    ``(length, 0)``; it is convex, so a triangle fan triangulates it (no polygon library needed).

    Args:
        length: distance between the centres of the round ends [m]
        width: width of the bar = diameter of the ends [m]
        thickness: extrusion height along z [m]
        z_center: height of its mid-plane in the part frame [m]
        sections: sides of each full circle's polygon (half of them per end)

    Returns:
        A watertight ``trimesh.Trimesh``.
    """
    import trimesh

    _positive("bar length", length, "length")
    _positive("bar width", width, "width")
    _positive("bar thickness", thickness, "thickness")
    r = width / 2.0
    half = sections // 2
    right = np.linspace(-np.pi / 2, np.pi / 2, half + 1)
    left = np.linspace(np.pi / 2, 3 * np.pi / 2, half + 1)
    outline = np.vstack(
        [
            np.column_stack([length + r * np.cos(right), r * np.sin(right)]),
            np.column_stack([r * np.cos(left), r * np.sin(left)]),
        ]
    )
    centre = outline.mean(axis=0)
    vertices = np.vstack([centre, outline])
    n = len(outline)
    faces = np.array([[0, 1 + k, 1 + (k + 1) % n] for k in range(n)])
    mesh = trimesh.creation.extrude_triangulation(vertices, faces, height=thickness)
    mesh.merge_vertices()
    return _moved(mesh, (0.0, 0.0, z_center - thickness / 2.0))


def combine(*meshes: Any) -> Any:
    """One mesh of several solids that do not overlap (their mass properties add up)."""
    import trimesh

    return trimesh.util.concatenate(list(meshes))


def mesh_inertia(mesh: Any, density: float) -> Inertia:
    """Mass properties of a closed mesh of uniform density.

    Args:
        mesh: a watertight ``trimesh.Trimesh``, outward normals, part frame [m]
        density: density [kg/m³]

    Returns:
        Mass [kg], centre of mass [m] and the inertia about it in the mesh axes [kg·m²].

    Raises:
        ParameterError: a density that is not > 0, or a mesh that is not watertight or has a
            non-positive volume (inward normals).
    """
    _positive("density", density, "density")
    if not mesh.is_watertight or not mesh.volume > 0.0:
        raise ParameterError(
            f"mesh of volume {float(mesh.volume):.6g} m^3 (watertight: {mesh.is_watertight});"
            " allowed: a closed mesh with outward normals",
            parameter="mesh",
        )
    solid = mesh.copy()
    solid.density = float(density)
    properties = solid.mass_properties
    inertia = np.asarray(properties["inertia"], dtype=float)
    return Inertia(
        mass=float(properties["mass"]),
        com=np.asarray(properties["center_mass"], dtype=float),
        inertia_com=(inertia + inertia.T) / 2.0,
    )


def prism_inertia(mass: float, circumradius: float, length: float, sections: int) -> Array:
    """Closed form: inertia of a solid right prism on a regular polygon, about its centre.

    A regular n-gon of circumradius R has the polar moment ``m·R²·(2 + cos(2π/n))/6`` per
    unit mass about its centre (``m·R²/2`` as n → ∞, the circular cylinder's); the transverse
    moments add the rod term ``m·L²/12``. Axis along z.

    Args:
        mass: mass [kg]
        circumradius: radius of the polygon's circumscribed circle [m]
        length: length along z [m]
        sections: sides of the polygon (≥ 3)

    Returns:
        3 × 3 inertia tensor [kg·m²].
    """
    polar = mass * circumradius**2 * (2.0 + np.cos(2.0 * np.pi / sections)) / 6.0
    transverse = polar / 2.0 + mass * length**2 / 12.0
    return np.diag([transverse, transverse, polar])


@dataclass(frozen=True)
class MeshPart:
    """A link's solid: its mesh in the link frame, density and colour.

    Attributes:
        name: the part's name (its STL file is ``<name>.stl``)
        mesh: a watertight ``trimesh.Trimesh`` in the link frame [m]
        density: density [kg/m³]
        rgba: display colour, four numbers in [0, 1]
    """

    name: str
    mesh: Any
    density: float
    rgba: tuple[float, float, float, float] = (0.2, 0.35, 0.85, 1.0)

    def inertia(self) -> Inertia:
        """Mass properties from the mesh and the density (see :func:`mesh_inertia`)."""
        return mesh_inertia(self.mesh, self.density)


def export_stl(mesh: Any, path: str | os.PathLike[str]) -> Path:
    """Write a mesh as a binary STL file, atomically.

    Args:
        mesh: the ``trimesh.Trimesh``
        path: the ``.stl`` file

    Returns:
        The path written.
    """
    from aaria_pin.files.io import atomic_output

    final = Path(path)
    with atomic_output(final) as temporary:
        temporary.write_bytes(mesh.export(file_type="stl"))
    return final
