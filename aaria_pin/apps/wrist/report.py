"""What one asks of the wrist: a rotation's pose, angles and every joint solution; its workspace.

:func:`wrist_report` answers "where is the tool, and which joint angles put it there" for a tool
rotation given by joint angles (forward), by angles in any sequence, or by a matrix (inverse;
:func:`nearest_rotation` accepts a matrix printed to 6 decimals); :func:`workspace_report`
summarises :func:`~aaria_pin.apps.wrist.wrist_kinematics.wrist_workspace`. Both give numbers
(:meth:`WristReport.to_dict`) and the text ``aaria wrist`` prints (:meth:`WristReport.text`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.apps.wrist.wrist_kinematics import REPORT_LIMITS, Workspace, wrist_fk, wrist_ik
from aaria_pin.core.rotations import angles_from_matrix, as_rotation, rotation_defect
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = [
    "EXACT_TOLERANCE",
    "MATRIX_TOLERANCE",
    "WristReport",
    "nearest_rotation",
    "workspace_report",
    "wrist_report",
]

MATRIX_TOLERANCE = 1e-5
"""Largest ``|RᵀR - I|`` entry of a matrix accepted and projected onto the nearest rotation:
the 6-decimal matrix ``aaria wrist fk`` prints is within about 3e-6 of one."""

EXACT_TOLERANCE = 1e-12
"""``|RᵀR - I|`` up to which a matrix is used as it is (no projection, no note)."""


def nearest_rotation(matrix: ArrayLike) -> tuple[Array, str | None]:
    """A 3 × 3 matrix as a rotation: as given, or projected (SVD) if within tolerance.

    Args:
        matrix: R11 … R33, 9 numbers row by row or a 3 × 3 array

    Returns:
        The rotation, and a note when it was projected (how far the matrix was, and moved).

    Raises:
        ParameterError: more than :data:`MATRIX_TOLERANCE` from a rotation, or det <= 0.
    """
    R = np.array(matrix, dtype=float).reshape(3, 3)
    defect, det = (float(v) for v in rotation_defect(R))
    if not (defect <= MATRIX_TOLERANCE and det > 0):
        raise ParameterError(
            f"matrix is not a rotation (|RᵀR - I| = {defect:.3g}, det = {det:.6g}); allowed:"
            f" |RᵀR - I| <= {MATRIX_TOLERANCE:g} and det > 0, rows as `aaria wrist fk` prints them",
            parameter="matrix",
        )
    if defect <= EXACT_TOLERANCE:
        return R, None
    rotation, _ = as_rotation(R, tolerance=EXACT_TOLERANCE, project=True)
    moved = float(np.abs(rotation - R).max())
    return rotation, (
        f"matrix is {defect:.2g} from a rotation (|RᵀR - I|); using the nearest"
        f" rotation (SVD), {moved:.2g} from it"
    )


@dataclass(frozen=True)
class WristReport:
    """A tool rotation of the wrist: its pose, its angles and every joint solution.

    Attributes:
        T_base_tool: (4, 4) the tool pose of the first solution (or of the unlimited IK's) [m]
        order: the angle sequence of ``angles``
        angles: the rotation's three angles in ``order`` [deg, or rad with ``degrees=False``]
        gimbal_lock: the angles are at a gimbal lock
        solutions: (n, 3) joint solutions [deg or rad], n = 0, 1 or 2
        singular: only θ1 ± θ3 is fixed (one member of the family is given)
        reachable: a solution lies within the joint limits
        residual: largest ``|R(solution) - R|`` entry over the solutions
        degrees: the unit of ``angles`` and ``solutions``
        notes: what was changed on the way (a projected matrix, an inexact singular member)
    """

    T_base_tool: Array
    order: str
    angles: Array
    gimbal_lock: bool
    solutions: Array
    singular: bool
    reachable: bool
    residual: float
    degrees: bool = True
    notes: tuple[str, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        """The report as JSON-ready numbers (``rotation``, ``pose``, ``angles``, ...)."""
        return {
            "rotation": self.T_base_tool[:3, :3].tolist(),
            "pose": self.T_base_tool.tolist(),
            "order": self.order,
            "angles": self.angles.tolist(),
            "gimbal_lock": self.gimbal_lock,
            "solutions": self.solutions.tolist(),
            "singular": self.singular,
            "reachable": self.reachable,
            "residual": self.residual,
        }

    def text(self) -> str:
        """The report as lines: rotation, tool point, angles, joint solutions."""
        unit = "deg" if self.degrees else "rad"
        lines = ["rotation:"]
        lines += ["  " + "  ".join(f"{v:+.6f}" for v in row) for row in self.T_base_tool[:3, :3]]
        lines.append("tool point [m]: " + "  ".join(f"{v:+.6f}" for v in self.T_base_tool[:3, 3]))
        angles = "  ".join(f"{v:+.4f}" for v in self.angles)
        lines.append(f"angles ({self.order}) [{unit}]: {angles}")
        singular = " (singular: only θ1 ± θ3 is fixed)" if self.singular else ""
        lines.append(f"joint solutions [{unit}]{singular}:")
        lines += ["  " + "  ".join(f"{v:+.4f}" for v in q) for q in self.solutions]
        if not len(self.solutions):
            lines.append("  none: unreachable within the joint limits")
        return "\n".join(lines)


def wrist_report(
    R_base_tool: ArrayLike,
    order: str = "xyz",
    limits: bool = False,
    degrees: bool = True,
    notes: tuple[str, ...] = (),
) -> WristReport:
    """Every joint solution of a tool rotation, and the pose and angles of the first.

    Args:
        R_base_tool: (3, 3) the tool rotation
        order: the angle sequence to express it in (``"xyz"``, ``"ZYZ"``, ...)
        limits: keep only solutions within the report's 0–360°, 0–180° joint ranges
        degrees: give the angles and solutions in degrees (else radians)
        notes: notes to carry (e.g. of :func:`nearest_rotation`)

    Returns:
        The report; with ``limits`` and no solution within them, the pose is the unlimited
        IK's first solution's.
    """
    ik = wrist_ik(R_base_tool, REPORT_LIMITS if limits else None)
    reference = ik.solutions[0] if len(ik.solutions) else wrist_ik(R_base_tool).solutions[0]
    pose = wrist_fk(reference)
    angles = angles_from_matrix(pose[:3, :3], order)
    scale = 180.0 / np.pi if degrees else 1.0
    if ik.residual > 1e-9:
        notes = (
            *notes,
            f"the solutions reproduce the rotation to {ik.residual:.2g} only"
            " (a member of the singular family moved into the joint limits)",
        )
    return WristReport(
        pose,
        order,
        angles.angles * scale,
        bool(angles.locked),
        ik.solutions * scale,
        ik.singular,
        ik.reachable,
        ik.residual,
        degrees,
        notes,
    )


def joints_report(joints: ArrayLike, order: str = "xyz", degrees: bool = True) -> WristReport:
    """:func:`wrist_report` of the tool rotation of joint angles (``aaria wrist fk``).

    Args:
        joints: J1 J2 J3 [deg, or rad with ``degrees`` False]
        order: the angle sequence to express the rotation in
        degrees: angles in and out in degrees (else radians)
    """
    q = np.radians(joints) if degrees else np.asarray(joints, dtype=float)
    return wrist_report(wrist_fk(q)[:3, :3], order, degrees=degrees)


def rotation_report(
    angles: ArrayLike | None,
    matrix: ArrayLike | None,
    order: str = "xyz",
    limits: bool = False,
    degrees: bool = True,
) -> WristReport:
    """:func:`wrist_report` of a tool rotation given as angles or as a matrix (``wrist ik``).

    Args:
        angles: three angles in the sequence ``order`` [deg, or rad with ``degrees`` False]
        matrix: else the rotation R11 … R33, row by row (within 1e-5 of a rotation: projected
            onto the nearest one, with a note; :func:`nearest_rotation`)
        order: the angles' sequence, and that of the angles reported
        limits: keep solutions within the report's joint ranges
        degrees: angles in and out in degrees (else radians)

    Raises:
        ParameterError: neither angles nor a matrix, or a matrix that is no rotation.
    """
    from aaria_pin.core.rotations import matrix_from_angles

    if angles is not None:
        values = np.radians(angles) if degrees else np.asarray(angles, dtype=float)
        return wrist_report(matrix_from_angles(values, order), order, limits, degrees)
    if matrix is None:
        raise ParameterError(parameter="matrix", value=None, allowed="angles or a matrix")
    rotation, note = nearest_rotation(matrix)
    return wrist_report(rotation, order, limits, degrees, () if note is None else (f"--{note}",))


def workspace_report(space: Workspace) -> tuple[dict[str, Any], str]:
    """A workspace's numbers (radius, solid angle, share of the sphere) and their text.

    Args:
        space: a sampled workspace (:func:`~aaria_pin.apps.wrist.wrist_kinematics.wrist_workspace`)

    Returns:
        ``{"radius_m", "solid_angle_sr", "solid_angle_exact_sr", "sphere_fraction",
        "samples"}`` and two lines saying the same.
    """
    low, high = space.radius
    summary = {
        "radius_m": [low, high],
        "solid_angle_sr": space.solid_angle,
        "solid_angle_exact_sr": space.solid_angle_exact,
        "sphere_fraction": space.solid_angle / (4 * np.pi),
        "samples": len(space.points),
    }
    exact = space.solid_angle_exact
    text = (
        f"tool points on the sphere of radius {high * 1000:.3f} mm "
        f"(sampled radii {low * 1000:.3f}-{high * 1000:.3f} mm)\n"
        f"covered solid angle {space.solid_angle:.4f} sr "
        f"({summary['sphere_fraction']:.1%} of the sphere)"
        + (f", exactly {exact:.4f} sr from the joint ranges" if exact is not None else "")
    )
    return summary, text
