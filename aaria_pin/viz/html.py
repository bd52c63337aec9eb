"""A self-contained HTML page that plays a run: the robot in 3D and its signals beside it.

**Choice of 3D library.** The page draws with three.js (r147, vendored in ``viz/vendor`` and
inlined: one HTML file of about 0.7 MB plus the robot, which works offline and can be mailed,
with a content security policy that forbids any load). The alternatives were weighed for "one
file or folder a user can open or send, offline": meshcat's static HTML is three.js too but is
produced by a running meshcat server (a ZMQ process, pyzmq, tornado) and plays its own
animation clock, with no hook for plots beside it; viser's static export needs its client build
folder and a served page; Rerun needs its viewer application and an ``.rrd`` file. Inlining
three.js keeps the one-file page, draws the URDF's meshes and solids with WebGL (lit, depth
tested), and lets our script drive playback, so the signal plots' cursor follows it.

The run is embedded as JSON: the scene's solids as triangle meshes (vertices in their frame
[m], to 0.01 mm, and their colour), its lines (frame axes, red, green, blue = x, y, z, with the
role's colour marking the origin) and bones, and the world pose of every frame at each shown
sample (``[R row-major, p]``, 12 numbers a frame, each rounded to 5 decimals: positions to
0.01 mm, rotation entries to 1e-5), and the signal panels (:func:`signal_panels`: each IMU's
gyroscope and accelerometer, one IMU shown at a time, and the joint torques and forces) at the
same samples. The page orbits
(drag), pans (right drag), zooms (wheel), plays and pauses, has a time slider, draws the tool
path on request, and draws the panels with a cursor at the shown time; ``#t=SECONDS`` in the
address opens it paused at that time. Its status line reports what was drawn (triangles, draw
calls, inked pixels, the sample, the cursor), for tests and curious users.
"""

from __future__ import annotations

import html
import json
import os
from collections.abc import Sequence
from dataclasses import replace
from functools import cache
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError
from aaria_pin.files.io import write_text_atomic
from aaria_pin.viz.scene import COLOURS, ROLE_LABELS, WORLD, Scene, posed_geometry

if TYPE_CHECKING:
    from aaria_pin.viz._run_view import Signals
    from aaria_pin.viz.plot import Panel

__all__ = [
    "DEFAULT_MAX_SAMPLES",
    "shown_samples",
    "signal_panels",
    "viewer_html",
    "write_run_viewer",
    "write_viewer",
]

_TITLE, _DATA, _LIBRARY = "__AARIA_TITLE__", "__AARIA_DATA__", "__AARIA_LIBRARY__"
"""Placeholders of the template: the page title (twice), the run's JSON and the 3D library
(once each)."""

_VENDORED = ("three-r147.min.js", "OrbitControls-r147.js")
"""The JavaScript files inlined in the page, in order (``viz/vendor``)."""

DEFAULT_MAX_SAMPLES = 500
"""Most samples a page holds by default (the run is decimated evenly to fit)."""


def signal_panels(signals: Signals, samples: Array) -> tuple[Panel, ...]:
    """The page's panels at the shown samples: each IMU's two, the joint torques and forces.

    They are :func:`aaria_pin.viz.plot.signal_panels`'s (the ``aaria plot`` panels) less the
    joint values and the base wrench.

    Args:
        signals: the run's signals
        samples: indices (S,) of the shown samples
    """
    from aaria_pin.viz.plot import signal_panels as all_panels

    index = np.asarray(samples, dtype=int)
    shown = []
    for panel in all_panels(signals):
        joint_loads = panel.title.endswith(("torques", "forces")) and "joints" in panel.title
        if panel.group or joint_loads:
            shown.append(replace(panel, values=np.asarray(panel.values)[index]))
    return tuple(shown)


@cache
def _template() -> str:
    page = (resources.files("aaria_pin.viz") / "viewer.html.in").read_text(encoding="utf-8")
    folder = resources.files("aaria_pin.viz") / "vendor"
    library = "\n".join((folder / name).read_text(encoding="utf-8") for name in _VENDORED)
    if "</script" in library.lower() or "__AARIA_" in library:
        raise RuntimeError("a vendored script holds '</script' or a placeholder of the page")
    return page.replace(_LIBRARY, library, 1)


def shown_samples(n_samples: int, max_samples: int = DEFAULT_MAX_SAMPLES) -> np.ndarray:
    """Indices of the samples a page shows: all, or ``max_samples`` evenly spread, last kept.

    Raises:
        ParameterError: ``max_samples`` below 2.
    """
    if max_samples < 2:
        raise ParameterError(parameter="max_samples", value=max_samples, allowed="2 or more")
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


def _panel(panel: Panel) -> dict[str, Any]:
    values = np.asarray(panel.values, dtype=float)
    scale = float(np.max(np.abs(values))) if values.size else 0.0
    digits = 4 if scale == 0.0 else max(0, 4 - int(np.floor(np.log10(scale))))
    return {
        "title": f"{panel.title} — {panel.ylabel}",
        "labels": list(panel.labels),
        "values": np.round(values.T, digits).tolist(),
        "group": panel.group,
    }


def _tool_frame(scene: Scene) -> int:
    """Index of the scene's tool frame (its axes' role is ``tool_frame``), or -1."""
    for item in scene.lines:
        if item.role == "tool_frame":
            return scene.frames.index(item.frame)
    return -1


def _payload(
    scene: Scene, time: Array, poses: Array, title: str, panels: Sequence[Panel]
) -> dict[str, Any]:
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
                "v": np.round(s.vertices, 5).ravel().tolist(),
                "t": s.triangles().ravel().tolist(),
                "c": [round(float(c), 4) for c in s.rgb],
            }
            for s in scene.solids
        ],
        "lines": [
            {
                "f": index[item.frame],
                "p": np.round(item.points, 5).tolist(),
                "c": np.round(item.colours(), 4).tolist(),
                "o": list(COLOURS.get(item.role, COLOURS["other"])) if item.axes else None,
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
            for role, label in ROLE_LABELS
            if role in roles or (role == "world_frame" and WORLD in scene.frames)
        ],
        "tool": _tool_frame(scene),
        "panels": [_panel(panel) for panel in panels],
    }


def viewer_html(
    scene: Scene,
    time: Array,
    poses: Array,
    title: str,
    panels: Sequence[Panel] = (),
) -> str:
    """The viewer page of a scene moving through poses, with signal panels beside it.

    Args:
        scene: the scene
        time: times of the shown samples (S,) [s]
        poses: (S, F, 4, 4) world pose of every scene frame at each shown sample
        title: the page's title
        panels: plots beside the 3D view, values at the shown samples (:func:`signal_panels`)

    Returns:
        The HTML text.
    """
    if poses.shape[:2] != (len(time), len(scene.frames)) or len(time) == 0:
        raise ParameterError(
            f"poses of shape {poses.shape} for {len(time)} samples and {len(scene.frames)}"
            " frames; allowed: (samples, frames, 4, 4), at least one sample",
            parameter="poses" if len(time) else "time",
        )
    from aaria_pin.viz.plot import check_panels

    check_panels(len(time), panels)
    data = json.dumps(_payload(scene, time, poses, title, panels), separators=(",", ":"))
    data = data.replace("<", "\\u003c")  # no "</script>" inside the script element
    # the title first (escaped for HTML, "_" as "&#95;" so it cannot spell a placeholder), then
    # the data, which is not scanned again: a title or frame name "__AARIA_TITLE__" stays as is
    page = _template().replace(_TITLE, html.escape(title).replace("_", "&#95;"))
    return page.replace(_DATA, data, 1)


def write_viewer(
    path: str | os.PathLike[str],
    scene: Scene,
    time: Array,
    poses: Array,
    title: str,
    panels: Sequence[Panel] = (),
) -> Path:
    """Write the viewer page (atomically); see :func:`viewer_html`."""
    final = Path(path)
    write_text_atomic(final, viewer_html(scene, time, poses, title, panels))
    return final


def write_run_viewer(
    path: str | os.PathLike[str],
    output: str | os.PathLike[str],
    run: int | None = None,
    max_samples: int = DEFAULT_MAX_SAMPLES,
) -> tuple[int, int]:
    """Write the viewer page of a run file, or of a data set's run (see :func:`viewer_html`).

    Args:
        path: a run file of any robot (any version), or a data set (``run``)
        output: the page to write (atomically)
        run: the run of a data set (default its first); only for a data set
        max_samples: most samples in the page (the run is decimated evenly)

    Returns:
        The number of samples shown and of the run's samples.

    Raises:
        ParameterError: a bad ``run`` or ``max_samples``.
        InputFileError: a file that cannot be read as a run.
    """
    from aaria_pin.viz.sources import load_run_view

    view = load_run_view(path, run)
    samples = shown_samples(view.time.size, max_samples)
    panels = signal_panels(view.signals, samples)
    poses = view.frame_poses(samples)
    write_viewer(output, view.scene, view.time[samples], poses, view.title, panels)
    return samples.size, view.time.size
