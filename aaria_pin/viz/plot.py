"""A run's signals as scope traces: labelled panels with units, one picture (PNG, PDF or SVG).

Rows of two panels sharing the time axis: revolute joints, angles [rad] and torques [N·m];
prismatic joints, positions [m] and forces [N] (so a large lift force does not flatten the
torques); the base wrench's force and moment (runs on a moving base); then one row per IMU,
gyroscope on the left and accelerometer on the right. Each panel's legend sits outside its
axes, to the right, so it covers no trace.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError
from aaria_pin.viz._figure import figure_file
from aaria_pin.viz.sources import Signals

__all__ = ["Panel", "check_panels", "plot_panels", "plot_run", "signal_panels"]

_AXES = ("x", "y", "z")

_JOINT_ROWS = (
    # kind, then (title, y label) of the joint values panel and of the torques/forces panel
    ("revolute", ("revolute joints: angles", "angle [rad]"),
     ("revolute joints: torques", "torque [N·m]")),
    ("prismatic", ("prismatic joints: positions", "position [m]"),
     ("prismatic joints: forces", "force [N]")),
)  # fmt: skip


@dataclass(frozen=True)
class Panel:
    """One scope trace panel.

    Attributes:
        title: what it shows
        ylabel: quantity and unit, e.g. ``"angular velocity [rad/s]"``
        values: (T, k) traces
        labels: one legend label per trace
        group: the IMU it shows (the viewer page shows one IMU's panels at a time); empty:
            not an IMU's
    """

    title: str
    ylabel: str
    values: Array
    labels: tuple[str, ...]
    group: str = ""


def check_panels(samples: int, panels: Sequence[Panel]) -> None:
    """Check that every panel holds one trace per label, each of ``samples`` values.

    Raises:
        ParameterError: a panel whose traces do not match (``parameter="panels"``).
    """
    for panel in panels:
        if np.shape(panel.values) != (samples, len(panel.labels)):
            raise ParameterError(
                parameter="panels",
                value=f"{panel.title!r} of shape {np.shape(panel.values)}",
                allowed=f"(samples, labels) = ({samples}, {len(panel.labels)})",
            )


def _name(label: str) -> str:
    """A label without its unit (the panel's y label gives it): ``"q1 [rad]"`` → ``"q1"``."""
    return label.rsplit(" [", 1)[0]


def _joint_panels(signals: Signals) -> list[Panel]:
    """One row per joint kind present: values on the left, torques or forces on the right."""
    kinds = signals.kinds
    panels = []
    for kind, (q_title, q_unit), (tau_title, tau_unit) in _JOINT_ROWS:
        columns = [k for k, joint in enumerate(kinds) if joint == kind]
        if not columns:
            continue
        q_labels = tuple(_name(signals.q_labels[k]) for k in columns)
        tau_labels = tuple(_name(signals.tau_labels[k]) for k in columns)
        panels += [
            Panel(q_title, q_unit, signals.q[:, columns], q_labels),
            Panel(tau_title, tau_unit, signals.tau[:, columns], tau_labels),
        ]
    return panels


def signal_panels(signals: Signals, imu: str | None = None) -> list[Panel]:
    """The panels of a run, in row-major order (two per row).

    Args:
        signals: the run's signals
        imu: show only this IMU (default: every IMU of the run)

    Returns:
        The panels, an even count: joints by kind, base wrench, IMUs.

    Raises:
        ParameterError: ``imu`` is not an IMU of the run.
    """
    if imu is not None and imu not in signals.imus:
        allowed = ", ".join(signals.imus) if signals.imus else "none (this run has no IMUs)"
        raise ParameterError(
            f"IMU {imu!r} is not in the run; allowed: {allowed}", parameter="imu", value=imu
        )
    panels = _joint_panels(signals)
    if signals.base_wrench is not None:
        panels += [
            Panel(
                "base wrench: force",
                "force [N]",
                signals.base_wrench[:, :3],
                tuple(f"f{a}" for a in _AXES),
            ),
            Panel(
                "base wrench: moment about the base origin",
                "moment [N·m]",
                signals.base_wrench[:, 3:],
                tuple(f"m{a}" for a in _AXES),
            ),
        ]
    for name, values in signals.imus.items():
        if imu is not None and name != imu:
            continue
        panels += [
            Panel(
                f"{name}: gyroscope",
                "angular velocity [rad/s]",
                values[:, :3],
                tuple(f"w{a}" for a in _AXES),
                name,
            ),
            Panel(
                f"{name}: accelerometer",
                "specific force [m/s²]",
                values[:, 3:],
                tuple(f"f{a}" for a in _AXES),
                name,
            ),
        ]
    return panels


def plot_panels(
    time: Array,
    panels: list[Panel],
    path: str | os.PathLike[str],
    title: str,
    *,
    width: int = 1400,
    row_height: int = 260,
) -> Path:
    """Draw panels two per row into a picture of ``width`` × (rows · ``row_height``) pixels.

    Args:
        time: sample times (T,) [s]
        panels: the panels (see :func:`signal_panels`)
        path: the picture to write (atomically): ``.png``, ``.pdf`` or ``.svg`` (by the suffix)
        title: the figure's title
        width: picture width [px]
        row_height: height of one row of panels [px]

    Returns:
        The path written.

    Raises:
        ParameterError: no panel, a panel whose labels do not match its traces, or matplotlib
            missing.
    """
    if not panels:
        raise ParameterError("nothing to plot; allowed: a run with signals", parameter="panels")
    check_panels(len(time), panels)
    rows = (len(panels) + 1) // 2
    with figure_file(path, width, rows * row_height, layout="constrained") as figure:
        axes = figure.subplots(rows, 2, sharex=True, squeeze=False)
        for k, ax in enumerate(axes.flat):
            if k >= len(panels):
                ax.set_visible(False)
                continue
            panel = panels[k]
            for trace, label in zip(panel.values.T, panel.labels, strict=True):
                ax.plot(time, trace, linewidth=1.0, label=label)
            ax.set_title(panel.title, fontsize=10)
            ax.set_ylabel(panel.ylabel, fontsize=9)
            ax.grid(True, alpha=0.3)
            ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
            if k >= len(panels) - 2:
                ax.set_xlabel("time [s]")
                ax.tick_params(labelbottom=True)
        figure.suptitle(title)
    return Path(path)


def plot_run(
    path: str | os.PathLike[str],
    output: str | os.PathLike[str],
    run: int | None = None,
    imu: str | None = None,
    width: int = 1400,
) -> tuple[int, int]:
    """Plot a run's joint values, torques and forces, base wrench and IMUs into one picture.

    Args:
        path: a run file of any robot (any version), or a data set (``run``)
        output: the picture to write (atomically): ``.png``, ``.pdf`` or ``.svg``
        run: the run of a data set (default its first); only for a data set
        imu: show only this IMU (default every IMU)
        width: picture width [px], 400 to :data:`~aaria_pin.viz.render.MAX_PIXELS`

    Returns:
        The number of panels drawn and of samples.

    Raises:
        ParameterError: a bad width, ``run`` or ``imu``.
        InputFileError: a file that cannot be read as a run.
    """
    from aaria_pin.viz.render import MAX_PIXELS
    from aaria_pin.viz.sources import load_run_view

    if not 400 <= width <= MAX_PIXELS:
        raise ParameterError(
            f"width {width} px; allowed: 400 to {MAX_PIXELS} px", parameter="width"
        )
    view = load_run_view(path, run)
    panels = signal_panels(view.signals, imu)
    title = view.title if imu is None else f"{view.title}: {imu}"
    plot_panels(view.time, panels, output, title, width=width)
    return len(panels), view.time.size
