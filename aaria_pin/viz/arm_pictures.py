"""Pictures of a pick-and-place run: a PNG contact sheet of its poses, a GIF animation.

The arm's scene (:func:`aaria_pin.viz._arm_source.arm_scene`: each link's mesh, the cylinder,
the world and grasp frames) is posed at the run's samples (the run's model, the cylinder where
it stands, travels with the hand, or was put down) and drawn by the viewers' renderer
(:func:`aaria_pin.viz.render.draw_geometry`) with matplotlib's Agg backend
(:func:`aaria_pin.viz._plotting.pyplot`); the animation is written by matplotlib's ``PillowWriter``.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.apps.arm.run import PickPlaceRun, cylinder_track
from aaria_pin.apps.arm.task import PHASES
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = [
    "ANIMATION_FPS",
    "ANIMATION_SIZES",
    "cylinder_poses",
    "sheet_samples",
    "write_animation",
    "write_contact_sheet",
]

ANIMATION_FPS = (1, 50)
"""Lowest and highest animation frame rate [frames per second of run time]."""

ANIMATION_SIZES = (100, 1200)
"""Smallest and largest side of the (square) animation [px]."""


def cylinder_poses(run: PickPlaceRun) -> Array:
    """The cylinder's centre pose in the world at every sample (T, 4, 4) [m]."""
    c = run.cylinder
    return cylinder_track(run.path.held, (c.x, c.y), run.place, c.height, run.tool_pose)


def sheet_samples(run: PickPlaceRun) -> list[tuple[int, str]]:
    """The samples a contact sheet shows: the start and the end of every phase, with labels."""
    time = run.path.time
    marks = [(0, "start")]
    for name, (_, end) in zip(PHASES, run.path.boundaries, strict=True):
        marks.append((int(min(np.searchsorted(time, end), time.size - 1)), f"after {name}"))
    return marks


class _Drawer:
    """The run's scene, posed at chosen samples, drawn into 3D axes."""

    def __init__(self, run: PickPlaceRun, samples: ArrayLike) -> None:
        from aaria_pin.viz._arm_source import arm_scene

        self.run = run
        c = run.cylinder
        self.scene = arm_scene(run.dims, (c.radius, c.height), run.parts)
        self.samples = np.asarray(samples, dtype=int)
        poses = np.empty((self.samples.size, len(self.scene.frames), 4, 4))
        poses[:, 0] = np.eye(4)
        poses[:, 1:-1] = run.link_poses(list(self.scene.frames[1:-1]), self.samples)
        poses[:, -1] = cylinder_poses(run)[self.samples]
        self.poses = poses
        reach, top = run.dims.upper_arm + run.dims.forearm, run.dims.pillar_height + 0.05
        self.bounds = (np.array([-reach, -reach, 0.0]), np.array([reach, reach, top]))

    def draw(self, ax: Any, row: int, title: str) -> None:
        from aaria_pin.viz.render import draw_geometry
        from aaria_pin.viz.scene import posed_geometry

        ax.cla()
        draw_geometry(ax, posed_geometry(self.scene, self.poses[row]), self.bounds)
        ax.set_box_aspect((1.0, 1.0, 1.0), zoom=1.6)  # no axes drawn: the arm fills the panel
        c = self.run.cylinder
        ax.scatter(*self.run.place, 0.0, marker="x", color="k")
        ax.scatter(c.x, c.y, 0.0, marker="o", color="k", s=8)
        ax.view_init(elev=25, azim=-60)
        ax.set_axis_off()
        k = self.samples[row]
        ax.set_title(f"{title}  t = {self.run.path.time[k]:.2f} s", fontsize=8)


def write_contact_sheet(path: str | os.PathLike[str], run: PickPlaceRun, dpi: int = 90) -> Path:
    """Write a PNG of the arm at the start and the end of every phase (2 × 4 panels)."""
    from aaria_pin.files.io import atomic_output
    from aaria_pin.viz._plotting import pyplot

    plt = pyplot()
    marks = sheet_samples(run)
    drawer = _Drawer(run, np.array([k for k, _ in marks]))
    fig = plt.figure(figsize=(12, 6.5))
    final = Path(path)
    try:
        for panel, (_, label) in enumerate(marks):
            ax = fig.add_subplot(2, 4, panel + 1, projection="3d", computed_zorder=False)
            drawer.draw(ax, panel, label)
        fig.tight_layout()
        with atomic_output(final) as temporary:
            fig.savefig(temporary, dpi=dpi, format="png")
    finally:
        plt.close(fig)
    return final


def write_animation(
    path: str | os.PathLike[str], run: PickPlaceRun, fps: int = 10, size: int = 300, dpi: int = 60
) -> Path:
    """Write a GIF of the task, ``fps`` frames per second of run time, ``size`` px square.

    Args:
        path: the GIF to write (atomically)
        run: the pick-and-place run
        fps: frames per second of run time
        size: width and height of the frames [px]
        dpi: dots per inch the figure is drawn at (text size: larger is larger text)

    Raises:
        ParameterError: fps outside :data:`ANIMATION_FPS`, size outside
            :data:`ANIMATION_SIZES`.
    """
    from aaria_pin.files.io import atomic_output
    from aaria_pin.viz._plotting import pyplot

    low, high = ANIMATION_FPS
    if not low <= fps <= high:
        raise ParameterError(parameter="fps", value=fps, allowed=f"{low} to {high}")
    smallest, largest = ANIMATION_SIZES
    if not smallest <= size <= largest:
        raise ParameterError(parameter="size", value=size, allowed=f"{smallest} to {largest} px")
    plt = pyplot()
    from matplotlib.animation import FuncAnimation, PillowWriter

    time = run.path.time
    frames = np.unique(np.searchsorted(time, np.arange(0.0, time[-1], 1.0 / fps)))
    drawer = _Drawer(run, frames)
    fig = plt.figure(figsize=(size / dpi, size / dpi), dpi=dpi)
    final = Path(path)
    try:
        ax = fig.add_subplot(projection="3d", computed_zorder=False)
        animation = FuncAnimation(
            fig,
            lambda row: drawer.draw(ax, int(row), "pick and place"),
            frames=range(frames.size),
            blit=False,
        )
        with atomic_output(final) as temporary:
            animation.save(str(temporary), writer=PillowWriter(fps=fps), dpi=dpi)
    finally:
        plt.close(fig)
    return final
