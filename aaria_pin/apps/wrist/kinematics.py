"""The spherical wrist of the wrist report: closed-form forward and inverse kinematics.

Table 1 of the report, standard DH: ``a = 0``; ``alpha = -90°, +90°, 0``; ``d = 0, 0, d3``
(132 mm). Its rotation is ``R = Rz(θ1)·Ry(θ2)·Rz(θ3)`` (equation (1), the ZYZ Euler angles about
moving axes) and its tool point ``d3·(c1·s2, s1·s2, c2)``, on the sphere of radius d3
(equation (9)).

Inverse kinematics returns every solution: the two branches θ2 > 0 and θ2 < 0 (the second is the
first with ``θ1 + π, -θ2, θ3 + π``). At the singularity ``sin θ2 = 0`` only ``θ1 + θ3``
(θ2 = 0) or ``θ1 - θ3`` (θ2 = π) is fixed: within ``|sin θ2| < 1e-9`` the solution is flagged
``singular`` and one member of the family is returned, at the singularity itself the canonical
one ``θ3 = 0``. Joint limits, if given, filter the solutions (angles are taken
modulo 2π into each joint's range).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.aaria.presets import WRIST_D3
from aaria_pin.core.rotations import angles_from_matrix, as_rotation
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = [
    "REPORT_LIMITS",
    "WRIST_D3",
    "Workspace",
    "WristSolutions",
    "wrist_fk",
    "wrist_ik",
    "wrist_ik_batch",
    "wrist_workspace",
]


REPORT_LIMITS = np.radians([[0.0, 360.0], [0.0, 180.0], [-180.0, 180.0]])
"""The report's joint ranges (joint 1: 0–360°, joint 2: 0–180°; joint 3 free) [rad]."""

SINGULAR_TOLERANCE = 1e-9
"""``|sin θ2|`` below which a rotation counts as singular."""


def wrist_fk(joints: ArrayLike, d3: float = WRIST_D3) -> Array:
    """Tool poses of the wrist, equation (9) of the report, vectorized.

    Args:
        joints: (..., 3) joint angles θ1, θ2, θ3 [rad]
        d3: tool distance [m]

    Returns:
        (..., 4, 4) poses of the tool in the base frame.
    """
    q = np.asarray(joints, dtype=float)
    if q.ndim == 0 or q.shape[-1] != 3 or not np.all(np.isfinite(q)):
        raise ParameterError(f"joint angles of shape {q.shape}; allowed: finite (..., 3)")
    c1, c2, c3 = np.cos(q[..., 0]), np.cos(q[..., 1]), np.cos(q[..., 2])
    s1, s2, s3 = np.sin(q[..., 0]), np.sin(q[..., 1]), np.sin(q[..., 2])
    T = np.zeros((*q.shape[:-1], 4, 4))
    T[..., 0, :3] = np.stack([c1 * c2 * c3 - s1 * s3, -c1 * c2 * s3 - s1 * c3, c1 * s2], -1)
    T[..., 1, :3] = np.stack([s1 * c2 * c3 + c1 * s3, -s1 * c2 * s3 + c1 * c3, s1 * s2], -1)
    T[..., 2, :3] = np.stack([-s2 * c3, s2 * s3, c2], -1)
    T[..., :3, 3] = d3 * T[..., :3, 2]
    T[..., 3, 3] = 1.0
    return T


@dataclass(frozen=True)
class WristSolutions:
    """The inverse kinematics of one rotation.

    Attributes:
        solutions: (n, 3) joint angles [rad], n = 0, 1 or 2
        singular: ``sin θ2 = 0``: only θ1 ± θ3 is fixed; the solution has θ3 = 0
        reachable: at least one solution is within the joint limits
    """

    solutions: Array
    singular: bool
    reachable: bool


def _wrap_into(angles: Array, limits: Array) -> tuple[Array, np.ndarray]:
    """Angles shifted by multiples of 2π into [low, high], and whether that worked."""
    low, high = limits[:, 0], limits[:, 1]
    shifted = low + np.mod(angles - low, 2 * np.pi)
    inside = shifted <= high + 1e-12
    return shifted, np.asarray(inside.all(axis=-1), dtype=bool)


def wrist_ik_batch(rotations: ArrayLike) -> tuple[Array, Array]:
    """Both wrist branches for many rotations at once, without limits.

    Args:
        rotations: (..., 3, 3) rotation matrices

    Returns:
        Joint angles (..., 2, 3) [rad] (branch θ2 >= 0 first; at a singularity both rows are
        members of the family) and the (...) singular flag.
    """
    first = angles_from_matrix(rotations, "ZYZ", lock_tolerance=SINGULAR_TOLERANCE)
    mirrored = first.angles * np.array([1.0, -1.0, 1.0]) + np.array([np.pi, 0.0, np.pi])
    second = np.arctan2(np.sin(mirrored), np.cos(mirrored))
    return np.stack([first.angles, second], axis=-2), first.locked


def wrist_ik(rotation: ArrayLike, limits: ArrayLike | None = None) -> WristSolutions:
    """Every joint solution of the wrist for a tool rotation.

    Args:
        rotation: 3 × 3 rotation matrix (checked: orthonormal within 1e-6, det +1)
        limits: optional 3 × 2 joint ranges ``[low, high]`` [rad] (e.g. :data:`REPORT_LIMITS`)

    Returns:
        The solutions, each verified by forward kinematics.

    Raises:
        ParameterError: not a rotation matrix, or bad limits.
    """
    R, _ = as_rotation(rotation)
    if R.shape != (3, 3):
        raise ParameterError(f"rotation has shape {R.shape}; allowed: (3, 3)")
    first = angles_from_matrix(R, "ZYZ", lock_tolerance=SINGULAR_TOLERANCE)
    singular = bool(first.locked)
    theta1, theta2, theta3 = first.angles
    candidates = [np.array([theta1, theta2, theta3])]
    if not singular:  # the other branch: θ1 + π, -θ2, θ3 + π
        other = np.array([theta1 + np.pi, -theta2, theta3 + np.pi])
        candidates.append(np.arctan2(np.sin(other), np.cos(other)))
    solutions = np.array(candidates)
    for q in solutions:
        if not np.allclose(wrist_fk(q)[:3, :3], R, atol=1e-9):  # pragma: no cover - a bug
            raise AssertionError(f"wrist IK solution {q} does not reproduce the rotation")
    if limits is None:
        return WristSolutions(solutions, singular, True)
    bounds = np.asarray(limits, dtype=float)
    if bounds.shape != (3, 2) or not np.all(bounds[:, 0] <= bounds[:, 1]):
        raise ParameterError(f"limits of shape {bounds.shape}; allowed: 3 × 2 [low, high]")
    shifted, inside = _wrap_into(solutions, bounds)
    kept = shifted[inside]
    return WristSolutions(kept, singular, bool(len(kept)))


@dataclass(frozen=True)
class Workspace:
    """Where the wrist's tool point can go.

    Attributes:
        points: (N, 3) sampled tool points [m]
        radius: (min, max) distance of the points from the wrist centre [m]
        solid_angle: solid angle the points cover, from a grid of equal-area cells [sr]
        solid_angle_exact: the same from the joint ranges, where they allow a closed form [sr]
    """

    points: Array
    radius: tuple[float, float]
    solid_angle: float
    solid_angle_exact: float | None


def wrist_workspace(
    samples: int = 200_000,
    limits: ArrayLike | None = REPORT_LIMITS,
    d3: float = WRIST_D3,
    seed: int = 0,
    cells: int | None = None,
) -> Workspace:
    """Sample the tool points the wrist reaches within its joint limits.

    Args:
        samples: number of random joint configurations
        limits: 3 × 2 joint ranges [rad] (None: every angle)
        d3: tool distance [m]
        seed: seed of the samples
        cells: number of equal-area cells of the sphere used to measure the covered solid angle
            (default ``samples / 50``, 100 to 10,000, so a reachable cell is rarely left empty)

    Returns:
        The sampled workspace: the points lie on the sphere of radius d3.
    """
    if not (isinstance(samples, int) and samples >= 1):
        raise ParameterError(f"samples {samples!r}; allowed: an integer >= 1")
    bounds = np.array([[-np.pi, np.pi]] * 3) if limits is None else np.asarray(limits, float)
    if bounds.shape != (3, 2) or not np.all(bounds[:, 0] <= bounds[:, 1]):
        raise ParameterError(f"limits of shape {bounds.shape}; allowed: 3 × 2 [low, high]")
    rng = np.random.default_rng(seed)
    q = rng.uniform(bounds[:, 0], bounds[:, 1], (samples, 3))
    points = wrist_fk(q, d3)[:, :3, 3]
    radii = np.linalg.norm(points, axis=1)
    # equal-area cells: uniform in z = cos(polar angle) and in azimuth
    cells = cells or int(np.clip(samples // 50, 100, 10_000))
    rows = max(1, int(np.sqrt(cells / 2)))
    unit = points / radii[:, None]
    band = np.minimum(((unit[:, 2] + 1) / 2 * rows).astype(int), rows - 1)
    sector = np.minimum(
        ((np.arctan2(unit[:, 1], unit[:, 0]) + np.pi) / (2 * np.pi) * 2 * rows).astype(int),
        2 * rows - 1,
    )
    hit = np.unique(band * 2 * rows + sector).size
    solid_angle = 4 * np.pi * hit / (2 * rows * rows)
    exact = None
    span1 = min(bounds[0, 1] - bounds[0, 0], 2 * np.pi)
    if bounds[1, 0] >= 0 and bounds[1, 1] <= np.pi:
        exact = float(span1 * (np.cos(bounds[1, 0]) - np.cos(bounds[1, 1])))
    return Workspace(points, (float(radii.min()), float(radii.max())), solid_angle, exact)
