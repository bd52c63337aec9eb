"""A self-contained HTML page that plays a run in an interactive 3D view.

The page is the template ``viewer.html.in`` (package data) with the run embedded as JSON:
the scene's solids, lines and bones in their frames' coordinates, and the world pose of every
frame at each shown sample (``[R row-major, p]``, 12 numbers a frame, each rounded to 5
decimals: positions to 0.01 mm, rotation entries to 1e-5). Its inline script projects the
scene itself onto a ``<canvas>`` (no WebGL, no library): drag to orbit, wheel to zoom, a
play/pause button and a time slider; ``#t=SECONDS`` in the address opens the page paused at
that time. Nothing is fetched when it is opened (its content security policy forbids any
load), so it works offline and can be mailed as one file.
"""

from __future__ import annotations

import html
import json
import os
from functools import cache
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError
from aaria_pin.files.io import write_text_atomic
from aaria_pin.viz.scene import COLOURS, WORLD, Scene, posed_geometry

__all__ = ["DEFAULT_MAX_SAMPLES", "shown_samples", "viewer_html", "write_viewer"]

_TITLE, _DATA = "__AARIA_TITLE__", "__AARIA_DATA__"
"""Placeholders of the template: the page title (twice) and the run's JSON (once)."""

DEFAULT_MAX_SAMPLES = 500
"""Most samples a page holds by default (the run is decimated evenly to fit)."""

_LEGEND = (
    ("joint", "joints"),
    ("link", "links, tool"),
    ("dh_frame", "DH frames"),
    ("world_frame", "world frame"),
    ("tool_frame", "tool frame"),
    ("imu_frame", "IMUs"),
)


@cache
def _template() -> str:
    return (resources.files("aaria_pin.viz") / "viewer.html.in").read_text(encoding="utf-8")


def shown_samples(n_samples: int, max_samples: int = DEFAULT_MAX_SAMPLES) -> np.ndarray:
    """Indices of the samples a page shows: all, or ``max_samples`` evenly spread, last kept.

    Raises:
        ParameterError: ``max_samples`` below 2.
    """
    if max_samples < 2:
        raise ParameterError(f"max samples {max_samples}; allowed: 2 or more")
    if n_samples <= max_samples:
        return np.arange(n_samples)
    return np.unique(np.round(np.linspace(0, n_samples - 1, max_samples)).astype(int))


def _grid(low: Array, high: Array, floor: float) -> list[list[list[float]]]:
    """Lines of a square floor grid under the arm, about 10 cells wide [m]."""
    centre = (low + high) / 2.0
    half = max(float(np.max(high[:2] - low[:2])) / 2.0 * 1.2, 0.1)
    step = 10.0 ** np.floor(np.log10(half / 3.0))
    start = np.floor((centre[:2] - half) / step) * step
    count = int(np.ceil(2 * half / step)) + 1
    lines = []
    for k in range(count):
        x, y = start[0] + k * step, start[1] + k * step
        lines.append([[x, start[1], floor], [x, start[1] + (count - 1) * step, floor]])
        lines.append([[start[0], y, floor], [start[0] + (count - 1) * step, y, floor]])
    return [[[round(float(v), 4) for v in point] for point in line] for line in lines]


def _payload(scene: Scene, time: Array, poses: Array, title: str) -> dict[str, Any]:
    index = {name: k for k, name in enumerate(scene.frames)}
    flat = np.concatenate([poses[:, :, :3, :3].reshape(*poses.shape[:2], 9), poses[:, :, :3, 3]], 2)
    low, high = np.full(3, np.inf), np.full(3, -np.inf)
    for k in np.unique(np.linspace(0, len(time) - 1, min(len(time), 25)).astype(int)):
        bounds = posed_geometry(scene, poses[k]).bounds()
        low, high = np.minimum(low, bounds[0]), np.maximum(high, bounds[1])
    roles = {s.role for s in scene.solids} | {item.role for item in scene.lines}
    return {
        "title": title,
        "times": np.round(time, 6).tolist(),
        "frames": list(scene.frames),
        "poses": np.round(flat.reshape(len(time), -1), 5).tolist(),
        "solids": [
            {
                "f": index[s.frame],
                "v": np.round(s.vertices, 5).tolist(),
                "faces": s.faces.tolist(),
                "c": list(COLOURS.get(s.role, COLOURS["other"])),
            }
            for s in scene.solids
        ],
        "lines": [
            {
                "f": index[item.frame],
                "p": np.round(item.points, 5).tolist(),
                "c": list(COLOURS.get(item.role, COLOURS["other"])),
                "w": item.width,
            }
            for item in scene.lines
        ],
        "bones": [
            {"a": index[b.frame_a], "b": index[b.frame_b], "c": list(COLOURS[b.role]), "w": b.width}
            for b in scene.bones
        ],
        "centre": ((low + high) / 2.0).round(5).tolist(),
        "radius": max(float(np.linalg.norm(high - low)) / 2.0, 0.05),
        "grid": _grid(low, high, min(float(low[2]), 0.0)),
        "legend": [
            {"label": label, "colour": list(COLOURS[role])}
            for role, label in _LEGEND
            if role in roles or (role == "world_frame" and WORLD in scene.frames)
        ],
    }


def viewer_html(scene: Scene, time: Array, poses: Array, title: str) -> str:
    """The viewer page of a scene moving through poses.

    Args:
        scene: the scene
        time: times of the shown samples (S,) [s]
        poses: (S, F, 4, 4) world pose of every scene frame at each shown sample
        title: the page's title

    Returns:
        The HTML text.
    """
    if poses.shape[:2] != (len(time), len(scene.frames)) or len(time) == 0:
        raise ParameterError(
            f"poses of shape {poses.shape} for {len(time)} samples and {len(scene.frames)}"
            " frames; allowed: (samples, frames, 4, 4), at least one sample"
        )
    data = json.dumps(_payload(scene, time, poses, title), separators=(",", ":"))
    data = data.replace("<", "\\u003c")  # no "</script>" inside the script element
    # the title first (escaped for HTML, "_" as "&#95;" so it cannot spell a placeholder), then
    # the data, which is not scanned again: a title or frame name "__AARIA_TITLE__" stays as is
    page = _template().replace(_TITLE, html.escape(title).replace("_", "&#95;"))
    return page.replace(_DATA, data, 1)


def write_viewer(
    path: str | os.PathLike[str], scene: Scene, time: Array, poses: Array, title: str
) -> Path:
    """Write the viewer page (atomically); see :func:`viewer_html`."""
    final = Path(path)
    write_text_atomic(final, viewer_html(scene, time, poses, title))
    return final
