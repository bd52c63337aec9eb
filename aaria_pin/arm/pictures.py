"""Pictures of a pick-and-place run: a PNG contact sheet of its poses, a GIF animation.

Each link's mesh (:func:`aaria_pin.arm.preset.arm_parts`) is drawn at its pose in the world
(Pinocchio's frame placements), with the cylinder where it stands, travels with the hand, or
was put down. matplotlib's Agg backend (:func:`aaria_pin._plotting.pyplot`) draws them; the
animation is written by matplotlib's ``PillowWriter``.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin._se3 import Array
from aaria_pin.arm.parts import cylinder_mesh
from aaria_pin.arm.preset import arm_parts, build_arm_model
from aaria_pin.arm.run import PickPlaceRun, cylinder_track, link_poses
from aaria_pin.arm.task import PHASES
from aaria_pin.errors import ParameterError

__all__ = ["cylinder_poses", "sheet_samples", "write_animation", "write_contact_sheet"]


def cylinder_poses(run: PickPlaceRun) -> Array:
    """The cylinder's centre pose in the world at every sample (T, 4, 4) [m]."""
    c = run.cylinder
    held = (float(run.path.boundaries[2, 1]), float(run.path.boundaries[6, 0]))
    return cylinder_track(run.path.time, held, (c.x, c.y), run.place, c.height, run.tool_pose)


def sheet_samples(run: PickPlaceRun) -> list[tuple[int, str]]:
    """The samples a contact sheet shows: the start and the end of every phase, with labels."""
    time = run.path.time
    marks = [(0, "start")]
    for name, (_, end) in zip(PHASES, run.path.boundaries, strict=True):
        marks.append((int(min(np.searchsorted(time, end), time.size - 1)), f"after {name}"))
    return marks


class _Drawer:
    def __init__(self, run: PickPlaceRun) -> None:
        self.run = run
        self.parts = arm_parts(run.dims)
        model = build_arm_model(run.dims)
        self.names = list(self.parts)
        self.poses = link_poses(model, run.path.q, self.names)
        self.cylinder = cylinder_mesh(run.cylinder.radius, run.cylinder.height, sections=24)
        self.cylinder_poses = cylinder_poses(run)

    def draw(self, ax: Any, k: int, title: str) -> None:
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        ax.cla()
        items = [
            (part.mesh, self.poses[k, j], part.rgba) for j, part in enumerate(self.parts.values())
        ]
        items.append((self.cylinder, self.cylinder_poses[k], (0.85, 0.15, 0.15, 1.0)))
        for mesh, T, rgba in items:
            vertices = mesh.vertices @ T[:3, :3].T + T[:3, 3]
            ax.add_collection3d(
                Poly3DCollection(
                    vertices[mesh.faces], facecolors=[rgba], linewidths=0.0, shade=True
                )
            )
        c = self.run.cylinder
        ax.scatter(*self.run.place, 0.0, marker="x", color="k")
        ax.scatter(c.x, c.y, 0.0, marker="o", color="k", s=8)
        reach = self.run.dims.upper_arm + self.run.dims.forearm
        top = self.run.dims.pillar_height + 0.05
        ax.set(xlim=(-reach, reach), ylim=(-reach, reach), zlim=(0.0, top))
        ax.set_box_aspect((2 * reach, 2 * reach, top), zoom=1.4)
        ax.view_init(elev=25, azim=-60)
        ax.set_axis_off()
        ax.set_title(f"{title}  t = {self.run.path.time[k]:.2f} s", fontsize=8)


def write_contact_sheet(path: str | os.PathLike[str], run: PickPlaceRun, dpi: int = 90) -> Path:
    """Write a PNG of the arm at the start and the end of every phase (2 × 4 panels)."""
    from aaria_pin._plotting import pyplot
    from aaria_pin.io import atomic_output

    plt = pyplot()
    drawer = _Drawer(run)
    fig = plt.figure(figsize=(12, 6.5))
    final = Path(path)
    try:
        for panel, (k, label) in enumerate(sheet_samples(run)):
            ax = fig.add_subplot(2, 4, panel + 1, projection="3d")
            drawer.draw(ax, k, label)
        fig.tight_layout()
        with atomic_output(final) as temporary:
            fig.savefig(temporary, dpi=dpi, format="png")
    finally:
        plt.close(fig)
    return final


def write_animation(
    path: str | os.PathLike[str], run: PickPlaceRun, fps: int = 10, dpi: int = 60
) -> Path:
    """Write a GIF of the task, ``fps`` frames per second of run time.

    Raises:
        ParameterError: fps outside 1–50.
    """
    from aaria_pin._plotting import pyplot
    from aaria_pin.io import atomic_output

    if not 1 <= fps <= 50:
        raise ParameterError(f"animation fps {fps!r}; allowed: 1 to 50")
    plt = pyplot()
    from matplotlib.animation import FuncAnimation, PillowWriter

    drawer = _Drawer(run)
    time = run.path.time
    frames = np.unique(np.searchsorted(time, np.arange(0.0, time[-1], 1.0 / fps)))
    fig = plt.figure(figsize=(5, 5))
    final = Path(path)
    try:
        ax = fig.add_subplot(projection="3d")
        animation = FuncAnimation(
            fig, lambda k: drawer.draw(ax, int(k), "pick and place"), frames=frames, blit=False
        )
        with atomic_output(final) as temporary:
            animation.save(str(temporary), writer=PillowWriter(fps=fps), dpi=dpi)
    finally:
        plt.close(fig)
    return final
