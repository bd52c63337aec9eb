"""A URDF's visual geometry as scene solids: meshes, boxes, cylinders and spheres, coloured.

Every ``<visual>`` of every link whose frame the scene has becomes a
:class:`~aaria_pin.viz.scene.Solid` fixed to that link's frame (Pinocchio names a link's frame
after the link), placed by the visual's ``<origin>``. The URDF is the one parse the check and the
MJCF export read (:func:`aaria_pin.core.urdf_parse.parse_urdf`), meshes (``.dae``, ``.stl``,
``.obj``, …) are read by trimesh, each resolved as the URDF check resolves them
(:func:`aaria_pin.core.urdf_check.resolve_mesh`: ``package://`` from the installed packages'
``share`` folders). A visual's colour is its URDF material's (inline or named), else the colours
the mesh file gives its parts (a ``.dae`` material), else the ``"link"`` role's.

Meshes are decimated (quadric decimation by fast-simplification, through trimesh, vertices
merged first) so a robot keeps about ``max_triangles`` triangles in all: the UR5's visual meshes
hold 95 000 triangles (about 6 MB as page text), the Panda's 134 000; at the default 30 000
(the UR5 keeps 33 000: decimation keeps some parts' sharp features) a viewer page of the UR5 is
2 MB and a matplotlib picture draws in seconds. A mesh file that cannot be found or read is
left out and named (:attr:`UrdfVisuals.missing`).
"""

from __future__ import annotations

from collections.abc import Collection
from dataclasses import dataclass, replace
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from aaria_pin.core.se3 import Array
from aaria_pin.viz.scene import Solid, box_solid, cylinder_solid, mesh_solid

__all__ = ["DEFAULT_MAX_TRIANGLES", "UrdfVisuals", "urdf_visual_solids"]

DEFAULT_MAX_TRIANGLES = 30_000
"""Triangles a robot's meshes keep in all, by default (they are decimated to fit)."""

_ROLE = "link"
_Part = tuple[Array, NDArray[np.int64], tuple[float, float, float] | None]
"""A mesh file's part: vertices (V, 3) [file units], triangles (K, 3), its colour or None."""


@dataclass(frozen=True)
class UrdfVisuals:
    """A URDF's visual solids.

    Attributes:
        solids: one solid per visual shape (a mesh file of several coloured parts gives several)
        missing: mesh files (as written in the URDF) that could not be found or read
    """

    solids: tuple[Solid, ...]
    missing: tuple[str, ...]


def _rgb(values: Any) -> tuple[float, float, float] | None:
    if values is None:
        return None
    rgba = np.asarray(values, dtype=float).ravel()
    return (float(rgba[0]), float(rgba[1]), float(rgba[2])) if rgba.size >= 3 else None


def _part_colour(mesh: Any) -> tuple[float, float, float] | None:
    """The colour a mesh file gives a part: its material's main colour, or its face colours'."""
    visual: Any = getattr(mesh, "visual", None)
    material = getattr(visual, "material", None)
    if material is not None and getattr(material, "main_color", None) is not None:
        colour = np.asarray(material.main_color, dtype=float)[:3] / 255.0
        return (float(colour[0]), float(colour[1]), float(colour[2]))
    if getattr(visual, "kind", None) == "face":
        colour = np.asarray(visual.face_colors, dtype=float)[:, :3].mean(axis=0) / 255.0
        return (float(colour[0]), float(colour[1]), float(colour[2]))
    return None


@lru_cache(maxsize=64)
def _mesh_parts(path: str) -> tuple[_Part, ...]:
    """The parts of a mesh file, each placed by the file's own scene graph (cached)."""
    import trimesh

    loaded: Any = trimesh.load(path, force="scene")
    parts = []
    for mesh in loaded.dump(concatenate=False):
        if len(mesh.faces) == 0:
            continue
        vertices = np.asarray(mesh.vertices, dtype=float)
        parts.append((vertices, np.asarray(mesh.faces, dtype=np.int64), _part_colour(mesh)))
    return tuple(parts)


@lru_cache(maxsize=256)
def _decimated(path: str, index: int, ratio: float) -> tuple[Array, NDArray[np.int64]]:
    """Part ``index`` of a mesh file with about ``ratio`` of its triangles (cached)."""
    import trimesh

    vertices, triangles, _ = _mesh_parts(path)[index]
    if ratio >= 1.0 or len(triangles) < 200:
        return vertices, triangles
    mesh = trimesh.Trimesh(vertices, triangles)
    mesh.merge_vertices(merge_tex=True, merge_norm=True)
    try:
        smaller = mesh.simplify_quadric_decimation(face_count=max(int(len(triangles) * ratio), 50))
    except ImportError:  # fast-simplification missing: the mesh is kept whole
        return vertices, triangles
    return np.asarray(smaller.vertices, dtype=float), np.asarray(smaller.faces, dtype=np.int64)


def urdf_visual_solids(
    urdf: str,
    frames: Collection[str],
    urdf_dir: Path | None = None,
    max_triangles: int = DEFAULT_MAX_TRIANGLES,
) -> UrdfVisuals:
    """Solids of a URDF's visuals, each fixed to its link's frame.

    Args:
        urdf: the URDF text
        frames: frames the scene can draw on (a link not among them is left out)
        urdf_dir: the URDF's folder, for relative mesh paths (None: none)
        max_triangles: triangles the meshes keep in all (they are decimated to fit)

    Returns:
        The solids, and the mesh files left out.
    """
    from aaria_pin.core.urdf_check import resolve_mesh
    from aaria_pin.core.urdf_parse import parse_urdf

    document = parse_urdf(urdf)
    wanted = set(frames)
    shapes = [
        (link.name, visual.origin.transform(), visual.geometry, _rgb(document.colour(visual)))
        for link in document.links
        if link.name in wanted
        for visual in link.visuals
    ]
    meshes: dict[str, str] = {}
    missing: list[str] = []
    for _, _, geometry, _ in shapes:
        if geometry is not None and geometry.kind == "mesh":
            file = resolve_mesh(geometry.filename, urdf_dir)
            try:
                parts = _mesh_parts(str(file)) if file is not None else None
            except Exception:  # any reader error: the mesh is left out, named
                parts = None
            if parts:
                meshes[geometry.filename] = str(file)
            else:
                missing.append(geometry.filename)
    total = sum(len(p[1]) for file in set(meshes.values()) for p in _mesh_parts(file))
    ratio = 1.0 if total <= max_triangles else max_triangles / total
    solids: list[Solid] = []
    for frame, T, geometry, colour in shapes:
        if geometry is None:
            continue
        if geometry.kind == "box":
            solids.append(replace(box_solid(frame, T, list(geometry.size), _ROLE), colour=colour))
        elif geometry.kind == "cylinder":
            solid = cylinder_solid(frame, T, geometry.radius, geometry.length, _ROLE)
            solids.append(replace(solid, colour=colour))
        elif geometry.kind == "sphere":
            import trimesh

            sphere = trimesh.creation.icosphere(subdivisions=2, radius=geometry.radius)
            solids.append(mesh_solid(frame, T, sphere.vertices, sphere.faces, _ROLE, colour))
        elif geometry.kind == "mesh" and geometry.filename in meshes:
            found = meshes[geometry.filename]
            factors = np.array(geometry.scale, dtype=float)
            for k, (_, _, part_colour) in enumerate(_mesh_parts(found)):
                vertices, triangles = _decimated(found, k, round(ratio, 4))
                solids.append(
                    mesh_solid(
                        frame, T, vertices * factors, triangles, _ROLE, colour or part_colour
                    )
                )
    return UrdfVisuals(tuple(solids), tuple(dict.fromkeys(missing)))
