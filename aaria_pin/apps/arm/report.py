"""What a pick-and-place run reports: its phases, each joint's peak effort and the payload's share.

:func:`pick_place_report` gives the lines ``aaria arm pick-place`` prints and the warnings of
joints whose peak exceeds the URDF's effort limit; :func:`write_arm_folder` writes the arm's URDF
and meshes for a gripped cylinder, checked first.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from aaria_pin.apps.arm.dims import get_arm_preset
from aaria_pin.apps.arm.preset import ARM_JOINTS, arm_joints, arm_parts, write_arm_urdf
from aaria_pin.apps.arm.run import PickPlaceRun, effort_excess
from aaria_pin.apps.arm.task import PHASES, Cylinder

__all__ = ["pick_place_report", "write_arm_folder"]


def pick_place_report(run: PickPlaceRun) -> tuple[str, tuple[str, ...]]:
    """The phases and each joint's peak |tau| with the payload's share, and the warnings.

    Args:
        run: a pick-and-place run (:func:`~aaria_pin.apps.arm.run.simulate_pick_place`)

    Returns:
        The lines (phase times [s]; per joint its peak [N·m, or N for a prismatic joint] and
        the peak of the payload's part of it) and one warning per joint whose peak exceeds
        its URDF effort limit.
    """
    lines = [
        f"  {name:<9} {start:6.2f} - {end:6.2f} s"
        for name, (start, end) in zip(PHASES, run.path.boundaries, strict=True)
    ]
    peak = np.abs(run.tau).max(axis=0)
    share = np.abs(run.tau - run.tau_free).max(axis=0)
    units = {j.name: "N" if j.kind == "prismatic" else "N*m" for j in arm_joints(run.dims)}
    lines.append("  joint       peak |tau|       payload share (peak)")
    for joint, p, s in zip(ARM_JOINTS, peak, share, strict=True):
        lines.append(f"  {joint:<10} {p:10.4g} {units[joint]:<3}   {s:10.4g} {units[joint]}")
    warnings = tuple(
        f"{joint} peak |tau| {value:.4g} {units[joint]} exceeds the URDF effort limit "
        f"{limit:g} {units[joint]}"
        for joint, value, limit in effort_excess(run)
    )
    return "\n".join(lines), warnings


def write_arm_folder(
    folder: str | os.PathLike[str],
    preset: str = "pick-place-arm",
    radius: float = 0.03,
    height: float = 0.12,
) -> tuple[Path, int]:
    """Write an arm preset's URDF and meshes, its frame ``grasp`` at a gripped cylinder's centre.

    Args:
        folder: the output folder (made if missing)
        preset: the arm preset
        radius: the gripped cylinder's radius [m]
        height: the gripped cylinder's height [m]

    Returns:
        The URDF's path and the number of meshes written beside it (in ``meshes/``).

    Raises:
        ParameterError: an unknown preset, or a cylinder the hand cannot grip.
        OutputFileError: the folder or a file cannot be written.
    """
    dims = get_arm_preset(preset)
    Cylinder(0.0, 0.0, radius, height)  # checks the numbers
    parts = arm_parts(dims)
    return write_arm_urdf(folder, dims, (radius, height), parts), len(parts)
