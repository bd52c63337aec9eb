"""A run's signals as scope traces: labelled panels with units, one PNG.

Rows of two panels sharing the time axis: joint values and joint torques/forces; the base
wrench's force and moment (runs on a moving base); then one row per IMU, gyroscope on the left
and accelerometer on the right.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from aaria_pin._plotting import pyplot
from aaria_pin._se3 import Array
from aaria_pin.errors import ParameterError
from aaria_pin.io import atomic_output
from aaria_pin.viz.sources import Signals

__all__ = ["Panel", "plot_panels", "signal_panels"]

_AXES = ("x", "y", "z")


@dataclass(frozen=True)
class Panel:
    """One scope trace panel.

    Attributes:
        title: what it shows
        ylabel: quantity and unit, e.g. ``"angular velocity [rad/s]"``
        values: (T, k) traces
        labels: one legend label per trace
    """

    title: str
    ylabel: str
    values: Array
    labels: tuple[str, ...]


def signal_panels(signals: Signals, imu: str | None = None) -> list[Panel]:
    """The panels of a run, in row-major order (two per row).

    Args:
        signals: the run's signals
        imu: show only this IMU (default: every IMU of the run)

    Returns:
        The panels; an odd count leaves the last row's right panel empty.

    Raises:
        ParameterError: ``imu`` is not an IMU of the run.
    """
    if imu is not None and imu not in signals.imus:
        allowed = ", ".join(signals.imus) if signals.imus else "none (this run has no IMUs)"
        raise ParameterError(f"IMU {imu!r} is not in the run; allowed: {allowed}")
    kinds = {label.split("[")[-1].rstrip("]") for label in signals.q_labels}
    force_kinds = {label.split("[")[-1].rstrip("]") for label in signals.tau_labels}
    panels = [
        Panel("joint values", f"q [{', '.join(sorted(kinds))}]", signals.q, signals.q_labels),
        Panel(
            "joint torques and forces",
            f"tau, f [{', '.join(sorted(force_kinds))}]",
            signals.tau,
            signals.tau_labels,
        ),
    ]
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
            ),
            Panel(
                f"{name}: accelerometer",
                "specific force [m/s²]",
                values[:, 3:],
                tuple(f"f{a}" for a in _AXES),
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
    """Draw panels two per row into a PNG of ``width`` × (rows · ``row_height``) pixels.

    Args:
        time: sample times (T,) [s]
        panels: the panels (see :func:`signal_panels`)
        path: the PNG to write (atomically)
        title: the figure's title
        width: picture width [px]
        row_height: height of one row of panels [px]

    Returns:
        The path written.
    """
    if not panels:
        raise ParameterError("nothing to plot; allowed: a run with signals")
    plt = pyplot()
    rows = (len(panels) + 1) // 2
    dpi = 100
    figure, axes = plt.subplots(
        rows,
        2,
        figsize=(width / dpi, rows * row_height / dpi),
        dpi=dpi,
        sharex=True,
        squeeze=False,
    )
    try:
        for k, ax in enumerate(axes.flat):
            if k >= len(panels):
                ax.set_visible(False)
                continue
            panel = panels[k]
            for column, label in enumerate(panel.labels):
                ax.plot(time, panel.values[:, column], linewidth=1.0, label=label)
            ax.set_title(panel.title, fontsize=10)
            ax.set_ylabel(panel.ylabel, fontsize=9)
            ax.grid(True, alpha=0.3)
            ax.legend(fontsize=7, loc="upper right", ncol=min(len(panel.labels), 6))
            if k >= len(panels) - 2:
                ax.set_xlabel("time [s]")
                ax.tick_params(labelbottom=True)
        figure.suptitle(title)
        figure.tight_layout()
        final = Path(path)
        with atomic_output(final) as temporary:
            figure.savefig(temporary, format="png", dpi=dpi)
    finally:
        plt.close(figure)
    return final
