"""A picture (PNG, PDF or SVG) of an arm in one pose, in the paper's colours (matplotlib, metres).

Solids are filled faces in their colours (a URDF's, else their role's) shaded by a light from
above and in front (so the box sides are told apart); coordinate frames are their x, y, z axes
in red, green, blue, drawn over the solids as Mechanics Explorer draws its frames, with a dot of
their role's colour at the origin. A legend names the roles and the axes' colours. The axes
have equal scales, are tight about the arm and show metres.
"""

from __future__ import annotations

import os
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError
from aaria_pin.viz._figure import equal_axes_3d, figure_file
from aaria_pin.viz.scene import AXIS_COLOURS, COLOURS, ROLE_LABELS, PosedGeometry, posed_geometry

if TYPE_CHECKING:
    from aaria_pin.aaria.dh import Convention

__all__ = [
    "MAX_PIXELS",
    "PictureSettings",
    "draw_geometry",
    "draw_legend",
    "face_colours",
    "render_geometry",
    "render_picture",
]

MAX_PIXELS = 4000
"""Largest width or height of a picture [px]."""

_LIGHT = np.array([0.4, -0.5, 0.75])
_MAX_EDGED_FACES = 3000
"""Most faces drawn with edges (boxes and cylinders are; meshes of thousands are not)."""


def face_colours(geometry: PosedGeometry, light: Array = _LIGHT) -> Array:
    """RGB (N, 3) of each face: its colour, Lambert-shaded by a fixed light.

    Args:
        geometry: the posed scene
        light: direction towards the light, world axes

    Returns:
        Colours in 0–1 (a face's own colour, else its role's); the darkest face keeps 55 % of
        its colour's brightness.
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
    if geometry.face_rgb is not None:
        base = np.asarray(geometry.face_rgb, dtype=float)
    else:
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
        many = geometry.faces.shape[0] > _MAX_EDGED_FACES  # a mesh's edges would blacken it
        solids = Poly3DCollection(
            list(geometry.faces),
            facecolors=face_colours(geometry),
            edgecolors="none" if many else (0.1, 0.1, 0.1, 0.35),
            linewidths=0.3,
        )
        solids.set_zorder(1)
        axes.add_collection3d(solids)
    if geometry.segments.shape[0]:
        if geometry.segment_rgb is not None:
            colours = np.asarray(geometry.segment_rgb, dtype=float)
        else:
            colours = np.array([COLOURS.get(r, COLOURS["other"]) for r in geometry.segment_roles])
        frames = Line3DCollection(
            list(geometry.segments), colors=colours, linewidths=geometry.segment_widths
        )
        frames.set_zorder(2)
        axes.add_collection3d(frames)
    if geometry.origins is not None and len(geometry.origins):
        dots = [COLOURS.get(role, COLOURS["other"]) for role in geometry.origin_roles]
        axes.scatter(*np.asarray(geometry.origins).T, c=dots, s=14, depthshade=False, zorder=3)
    low, high = geometry.bounds() if bounds is None else (np.asarray(b) for b in bounds)
    equal_axes_3d(axes, low, high, min_half=0.05)


def draw_legend(axes: Any, geometry: PosedGeometry, **options: Any) -> Any:
    """A legend of what a posed scene shows: its solids' and frames' roles, the axes' colours.

    Solids in their own colours (a URDF's) are named "links (URDF colours)".

    Args:
        axes: the axes to put it on
        geometry: the posed scene
        **options: more arguments of ``axes.legend`` (e.g. ``loc``)

    Returns:
        The legend.
    """
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    roles = set(geometry.face_roles) | set(geometry.origin_roles) | set(geometry.segment_roles)
    own = geometry.face_rgb is not None and any(
        not np.allclose(rgb, COLOURS.get(role, COLOURS["other"]))
        for rgb, role in zip(geometry.face_rgb, geometry.face_roles, strict=True)
    )
    handles: list[Any] = []
    if own:
        grey = (0.45, 0.45, 0.45)
        handles.append(Patch(facecolor=grey, edgecolor="k", label="links (URDF colours)"))
    for role, label in ROLE_LABELS:
        if role not in roles:
            continue
        colour = COLOURS[role]
        if role in geometry.origin_roles:
            handles.append(Line2D([], [], marker="o", linestyle="", color=colour, label=label))
        elif not own and role in geometry.face_roles:
            handles.append(Patch(facecolor=colour, edgecolor="k", label=label))
    if "bone" in roles:
        handles.append(Line2D([], [], color=COLOURS["bone"], linewidth=3, label="links"))
    if geometry.origin_roles:
        for axis, colour in zip("xyz", AXIS_COLOURS, strict=True):
            handles.append(Line2D([], [], color=colour, linewidth=2, label=f"{axis} axis"))
    return axes.legend(handles=handles, **options)


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
    """Draw a posed scene with its legend into a PNG, PDF or SVG (by the suffix).

    A PNG is exactly ``width`` × ``height`` pixels; a PDF or SVG is that size cropped to what is
    drawn (:func:`aaria_pin.viz._figure.figure_file`).

    Args:
        geometry: the posed scene
        path: the picture to write (atomically): ``.png``, ``.pdf`` or ``.svg``
        title: the picture's title
        width: picture width [px]
        height: picture height [px]
        elevation: view elevation [deg]
        azimuth: view azimuth [deg]

    Returns:
        The path written.

    Raises:
        ParameterError: a size outside 100–:data:`MAX_PIXELS` px, or matplotlib missing.
        OutputFileError: another suffix.
    """
    for name, value in (("width", width), ("height", height)):
        if not 100 <= value <= MAX_PIXELS:
            raise ParameterError(
                f"{name} {value} px; allowed: 100 to {MAX_PIXELS} px", parameter=name
            )
    with figure_file(path, width, height) as figure:
        axes = figure.add_subplot(projection="3d", computed_zorder=False)
        draw_geometry(axes, geometry)
        axes.set_xlabel("x [m]")
        axes.set_ylabel("y [m]")
        axes.set_zlabel("z [m]")
        axes.view_init(elev=elevation, azim=azimuth)
        axes.set_title(title)
        draw_legend(axes, geometry, loc="upper left", fontsize=8, framealpha=0.9)
        figure.subplots_adjust(left=0.0, right=1.0, bottom=0.02, top=0.95)
    return Path(path)


@dataclass(frozen=True)
class PictureSettings:
    """How a picture is drawn.

    Attributes:
        width: picture width [px] (100 to :data:`MAX_PIXELS`)
        height: picture height [px] (100 to :data:`MAX_PIXELS`)
        elevation: view elevation above the x-y plane [deg]
        azimuth: view azimuth about z [deg]
    """

    width: int = 1000
    height: int = 800
    elevation: float = 20.0
    azimuth: float = -60.0


def render_picture(
    path: str | os.PathLike[str],
    *,
    preset: str | None = None,
    dh_file: str | os.PathLike[str] | None = None,
    convention: Convention = "aaria",
    run_file: str | os.PathLike[str] | None = None,
    run: int | None = None,
    time: float | None = None,
    settings: PictureSettings = PictureSettings(),
) -> str:
    """Draw an arm in 3D: a preset or a DH table file at rest, or a run at a time.

    Args:
        path: the picture to write (atomically): ``.png``, ``.pdf`` or ``.svg``
        preset: a DH table preset or a plug-in's model preset, every joint at zero
        dh_file: a DH table file (CSV, ``.npy``, or ``.mat`` holding ``senSenDH``)
        convention: the convention of ``dh_file``'s table
        run_file: a run file of any robot, or a data set (``run``)
        run: the run of a data set (default its first); only with ``run_file``
        time: the time in the run [s] (default its start); only with ``run_file``
        settings: the picture's size and view

    Returns:
        The picture's title (the preset, the file, or the run and the time shown).

    Raises:
        ParameterError: not exactly one of ``preset``, ``dh_file``, ``run_file``; a time
            outside the run; a bad size.
        OptionConflictError: ``run`` or ``time`` without ``run_file``, a ``convention`` other
            than ``"aaria"`` without ``dh_file``.
        InputFileError: a file that cannot be read.
    """
    from aaria_pin.viz.sources import load_run_view, preset_view, sample_at, table_view

    if [preset, dh_file, run_file].count(None) != 2:
        raise ParameterError(
            parameter="preset", value=preset, allowed="exactly one of preset, dh_file, run_file"
        )
    from aaria_pin.core.conflicts import OptionConflictError

    for name, value, other in (("time", time, "run_file"), ("run", run, "run_file")):
        if run_file is None and value is not None:
            raise OptionConflictError(parameter=name, other=other, given_with=False, value=value)
    if dh_file is None and convention != "aaria":  # a preset's or a run's is its own
        raise OptionConflictError(
            parameter="convention", other="dh_file", given_with=False, value=convention
        )
    if run_file is not None:
        view = load_run_view(run_file, run)
        k = sample_at(view.time, view.time[0] if time is None else time)
        scene, poses = view.scene, view.frame_poses(np.array([k]))[0]
        title = f"{view.title}, t = {view.time[k]:.3f} s"
    elif preset is not None:
        scene, poses = preset_view(preset)
        title = scene.name
    else:
        from aaria_pin.files.io import read_table

        table_path = Path(str(dh_file))
        scene, poses = table_view(read_table(table_path, "senSenDH"), convention, table_path.stem)
        title = table_path.name
    render_geometry(posed_geometry(scene, poses), path, title, **asdict(settings))
    return title
