"""Pictures of the applications' reports: the torque split per joint, the wrist's workspace.

The applications (:mod:`aaria_pin.apps.torques`, :mod:`aaria_pin.apps.wrist.wrist_kinematics`)
compute the reports and import no picture; the CLI draws them with these functions (matplotlib, Agg
backend, written atomically as PNG, PDF or SVG by :func:`aaria_pin.viz._figure.figure_file`).

The torque split is drawn as grouped bars, never stacked: the RMS of a sum is not the sum of the
RMS of its terms (a UR5 or Aaria joint whose gravity and inertial terms partly cancel would stack
to more than its RMS), so each joint has four bars side by side, the RMS of tau and the RMS of
its gravity, Coriolis and inertial terms, each equal to the printed value.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin.viz._figure import equal_axes_3d, figure_file

if TYPE_CHECKING:
    from aaria_pin.apps.wrist.wrist_kinematics import Workspace

__all__ = [
    "TORQUE_BARS",
    "TORQUE_TERMS",
    "draw_torque_report",
    "draw_workspace",
    "plot_torque_report",
    "plot_workspace",
]

TORQUE_TERMS = ("gravity", "coriolis", "inertial")
"""The terms of a torque report's split."""

TORQUE_BARS = (
    ("rms", "RMS of tau", "0.35"),
    ("gravity", "RMS of gravity term", "tab:green"),
    ("coriolis", "RMS of Coriolis term", "tab:orange"),
    ("inertial", "RMS of inertial term", "tab:blue"),
)
"""The bars of each joint, left to right: report key, legend label, colour."""

_UNIT_AXES = {"N*m": "RMS torque [N·m]", "N": "RMS force [N]"}


def draw_torque_report(figure: Any, report: dict[str, Any], title: str) -> list[Any]:
    """Draw a torque report into a figure: one axes per unit (N·m, N), grouped bars per joint.

    Each joint has the bars of :data:`TORQUE_BARS` side by side (their labels are the bar
    containers' labels) and a diamond at its peak |tau|.

    Args:
        figure: the matplotlib figure
        report: a run's report (:func:`aaria_pin.apps.torques.record_torque_report`)
        title: the figure's title

    Returns:
        The axes, one per unit, in the order the joints first use them.
    """
    joints = report["joints"]
    units = list(dict.fromkeys(j["unit"] for j in joints))
    widths = [sum(j["unit"] == unit for j in joints) + 1 for unit in units]
    grid = figure.subplots(1, len(units), squeeze=False, width_ratios=widths)[0]
    width = 0.8 / len(TORQUE_BARS)
    for axes, unit in zip(grid, units, strict=True):
        shown = [j for j in joints if j["unit"] == unit]
        x = np.arange(len(shown))
        for k, (key, label, colour) in enumerate(TORQUE_BARS):
            values = [j["rms"] if key == "rms" else j["rms_terms"][key] for j in shown]
            offset = (k - (len(TORQUE_BARS) - 1) / 2) * width
            axes.bar(x + offset, values, width, color=colour, label=label)
        axes.plot(x, [j["peak_abs"] for j in shown], "kD", markersize=4, label="peak |tau|")
        axes.set_xticks(x, [str(j.get("joint", j["module"])) for j in shown], rotation=30)
        axes.set_ylabel(_UNIT_AXES.get(unit, f"RMS [{unit}]"))
        axes.grid(True, axis="y", alpha=0.3)
    grid[0].legend(fontsize=8)
    figure.suptitle(title)
    return list(grid)


def plot_torque_report(
    report: dict[str, Any], path: str | os.PathLike[str], title: str = "joint torques"
) -> Path:
    """Grouped bars of each joint's RMS torque and its terms' RMS, and its peak.

    Args:
        report: a run's report (:func:`aaria_pin.apps.torques.record_torque_report`)
        path: the picture to write (800 × 420 px): ``.png``, ``.pdf`` or ``.svg``
        title: the picture's title

    Returns:
        The path written.

    Raises:
        ParameterError: matplotlib is not installed.
        OutputFileError: another suffix.
    """
    with figure_file(path, 800, 420, layout="constrained") as figure:
        draw_torque_report(figure, report, title)
    return Path(path)


def draw_workspace(axes: Any, workspace: Workspace, title: str) -> None:
    """Draw the wrist workspace's tool points into 3D axes with equal scales, tight.

    Args:
        axes: matplotlib 3D axes
        workspace: the sampled workspace (see
            :func:`~aaria_pin.apps.wrist.wrist_kinematics.wrist_workspace`)
        title: the title (the radius [mm] and solid angle [sr] are added)
    """
    shown = workspace.points[:: max(1, len(workspace.points) // 20_000)]
    axes.scatter(*shown.T, s=0.5, c=shown[:, 2], cmap="viridis")
    axes.set_xlabel("x [m]")
    axes.set_ylabel("y [m]")
    axes.set_zlabel("z [m]")
    equal_axes_3d(axes, shown.min(axis=0), shown.max(axis=0))
    axes.set_title(
        f"{title}\nradius {workspace.radius[1] * 1000:.1f} mm, {workspace.solid_angle:.3f} sr"
    )


def plot_workspace(
    workspace: Workspace, path: str | os.PathLike[str], title: str = "spherical wrist workspace"
) -> Path:
    """A 3D scatter of the wrist workspace's tool points (:func:`draw_workspace`), 600 × 600 px.

    Args:
        workspace: the sampled workspace (see
            :func:`~aaria_pin.apps.wrist.wrist_kinematics.wrist_workspace`)
        path: the picture to write: ``.png``, ``.pdf`` or ``.svg``
        title: the picture's title (the radius [mm] and solid angle [sr] are added)

    Returns:
        The path written.

    Raises:
        ParameterError: matplotlib is not installed.
        OutputFileError: another suffix.
    """
    with figure_file(path, 600, 600) as figure:
        draw_workspace(figure.add_subplot(projection="3d"), workspace, title)
    return Path(path)
