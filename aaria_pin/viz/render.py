"""A PNG of an arm in one pose, in the paper's colours (matplotlib, 3D axes in metres).

Solids are filled faces shaded by a light from above and in front (so the box sides are told
apart); coordinate frames are lines drawn over the solids, as Mechanics Explorer draws its
frames. The axes have equal aspect and show metres.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError
from aaria_pin.viz._figure import png_figure
from aaria_pin.viz.scene import COLOURS, PosedGeometry

__all__ = ["MAX_PIXELS", "draw_geometry", "face_colours", "render_geometry"]

MAX_PIXELS = 4000
"""Largest width or height of a picture [px]."""

_LIGHT = np.array([0.4, -0.5, 0.75])


def face_colours(geometry: PosedGeometry, light: Array = _LIGHT) -> Array:
    """RGB (N, 3) of each face: its role's colour, Lambert-shaded by a fixed light.

    Args:
        geometry: the posed scene
        light: direction towards the light, world axes

    Returns:
        Colours in 0–1; the darkest face keeps 55 % of its role's brightness.
    """
    faces = geometry.faces
    if faces.shape[0] == 0:
        return np.zeros((0, 3))
    normal = np.cross(faces[:, 2] - faces[:, 0], faces[:, 1] - faces[:, 0])
    spread = np.cross(faces[:, 3] - faces[:, 1], faces[:, 2] - faces[:, 0])
    normal = np.where(np.linalg.norm(normal, axis=1, keepdims=True) > 0, normal, spread)
    length = np.linalg.norm(normal, axis=1, keepdims=True)
    unit = normal / np.where(length > 0, length, 1.0)
    lit = np.abs(unit @ (light / np.linalg.norm(light)))
    base = np.array([COLOURS.get(role, COLOURS["other"]) for role in geometry.face_roles])
    return np.asarray(base * (0.55 + 0.45 * lit)[:, None])


def draw_geometry(
    axes: Any, geometry: PosedGeometry, bounds: tuple[Array, Array] | None = None
) -> None:
    """Draw a posed scene into 3D axes: shaded faces, frame lines over them, equal aspect.

    Args:
        axes: matplotlib 3D axes (made with ``computed_zorder=False``, so lines stay on top)
        geometry: the posed scene
        bounds: lowest and highest corner [m] the axes must show (default: the scene's), in a
            cube about their centre
    """
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

    if geometry.faces.shape[0]:
        solids = Poly3DCollection(
            list(geometry.faces),
            facecolors=face_colours(geometry),
            edgecolors=(0.1, 0.1, 0.1, 0.35),
            linewidths=0.3,
        )
        solids.set_zorder(1)
        axes.add_collection3d(solids)
    if geometry.segments.shape[0]:
        colours = [COLOURS.get(role, COLOURS["other"]) for role in geometry.segment_roles]
        frames = Line3DCollection(
            list(geometry.segments), colors=colours, linewidths=geometry.segment_widths
        )
        frames.set_zorder(2)
        axes.add_collection3d(frames)
    low, high = geometry.bounds() if bounds is None else (np.asarray(b) for b in bounds)
    centre, half = (low + high) / 2.0, max(float(np.max(high - low)) / 2.0, 0.05) * 1.05
    axes.set_xlim(centre[0] - half, centre[0] + half)
    axes.set_ylim(centre[1] - half, centre[1] + half)
    axes.set_zlim(centre[2] - half, centre[2] + half)
    axes.set_box_aspect((1.0, 1.0, 1.0))


def render_geometry(
    geometry: PosedGeometry,
    path: str | os.PathLike[str],
    title: str,
    *,
    width: int = 1000,
    height: int = 800,
    elevation: float = 20.0,
    azimuth: float = -60.0,
) -> Path:
    """Draw a posed scene into a PNG of exactly ``width`` × ``height`` pixels.

    Args:
        geometry: the posed scene
        path: the PNG to write (atomically)
        title: the picture's title
        width: picture width [px]
        height: picture height [px]
        elevation: view elevation [deg]
        azimuth: view azimuth [deg]

    Returns:
        The path written.

    Raises:
        ParameterError: a size outside 100–:data:`MAX_PIXELS` px, or matplotlib missing.
    """
    for name, value in (("width", width), ("height", height)):
        if not 100 <= value <= MAX_PIXELS:
            raise ParameterError(f"{name} {value} px; allowed: 100 to {MAX_PIXELS} px")
    with png_figure(path, width, height) as figure:
        axes = figure.add_subplot(projection="3d", computed_zorder=False)
        draw_geometry(axes, geometry)
        axes.set_xlabel("x [m]")
        axes.set_ylabel("y [m]")
        axes.set_zlabel("z [m]")
        axes.view_init(elev=elevation, azim=azimuth)
        axes.set_title(title)
        figure.subplots_adjust(left=0.0, right=1.0, bottom=0.02, top=0.95)
    return Path(path)
