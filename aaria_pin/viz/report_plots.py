"""Pictures of the applications' reports: the torque split per joint, the wrist's workspace.

The applications (:mod:`aaria_pin.apps.torques`, :mod:`aaria_pin.apps.wrist.kinematics`) compute
the reports and import no picture; the CLI draws them with these functions (matplotlib, Agg
backend, written atomically as PNGs by :func:`aaria_pin.viz._figure.png_figure`).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin.viz._figure import png_figure

if TYPE_CHECKING:
    from aaria_pin.apps.wrist.kinematics import Workspace

__all__ = ["TORQUE_TERMS", "plot_torque_report", "plot_workspace"]

TORQUE_TERMS = ("gravity", "coriolis", "inertial")
"""The terms of a torque report's split, bottom to top of each bar."""


def plot_torque_report(
    report: dict[str, Any], path: str | os.PathLike[str], title: str = "joint torques"
) -> Path:
    """Bars of each joint's RMS torque split into gravity, Coriolis and inertial, and its peak.

    Args:
        report: a run's report (:func:`aaria_pin.apps.torques.record_torque_report`)
        path: the PNG to write (700 × 400 px)
        title: the picture's title

    Returns:
        The path written.

    Raises:
        ParameterError: matplotlib is not installed.
    """
    joints = report["joints"]
    labels = [f"{j.get('joint', j['module'])} ({j['type'][0]}, {j['unit']})" for j in joints]
    x = np.arange(len(joints))
    with png_figure(path, 700, 400) as figure:
        axes = figure.add_subplot()
        bottom = np.zeros(len(joints))
        for term, colour in zip(TORQUE_TERMS, ("tab:green", "tab:orange", "tab:blue"), strict=True):
            values = np.array([j["rms_terms"][term] for j in joints])
            axes.bar(x, values, bottom=bottom, color=colour, label=f"RMS {term}")
            bottom += values
        axes.plot(x, [j["peak_abs"] for j in joints], "kD", label="peak |tau|")
        axes.set_xticks(x, labels)
        axes.set_xlabel("joint (type, unit)")
        axes.set_ylabel("torque [N*m] or force [N]")
        axes.set_title(title)
        axes.legend()
        figure.tight_layout()
    return Path(path)


def plot_workspace(
    workspace: Workspace, path: str | os.PathLike[str], title: str = "spherical wrist workspace"
) -> Path:
    """A 3D scatter of the wrist workspace's tool points, as a 600 × 600 px PNG.

    Args:
        workspace: the sampled workspace (:func:`aaria_pin.apps.wrist.kinematics.wrist_workspace`)
        path: the PNG to write
        title: the picture's title (the radius [mm] and solid angle [sr] are added)

    Returns:
        The path written.

    Raises:
        ParameterError: matplotlib is not installed.
    """
    shown = workspace.points[:: max(1, len(workspace.points) // 20_000)]
    with png_figure(path, 600, 600) as figure:
        axes = figure.add_subplot(projection="3d")
        axes.scatter(*shown.T, s=0.5, c=shown[:, 2], cmap="viridis")
        axes.set_xlabel("x [m]")
        axes.set_ylabel("y [m]")
        axes.set_zlabel("z [m]")
        axes.set_box_aspect((1, 1, 1))
        axes.set_title(
            f"{title}\nradius {workspace.radius[1] * 1000:.1f} mm, {workspace.solid_angle:.3f} sr"
        )
    return Path(path)
