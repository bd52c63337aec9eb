"""The spherical wrist of the wrist report: closed-form forward and inverse kinematics.

Table 1 of the report, standard DH: ``a = 0``; ``alpha = -90°, +90°, 0``; ``d = 0, 0, d3``
(132 mm). Its rotation is ``R = Rz(θ1)·Ry(θ2)·Rz(θ3)`` (equation (1), the ZYZ Euler angles about
moving axes) and its tool point ``d3·(c1·s2, s1·s2, c2)``, on the sphere of radius d3
(equation (9)).

Inverse kinematics returns every solution: the two branches θ2 > 0 and θ2 < 0 (the second is the
first with ``θ1 ± π, -θ2, θ3 ± π``), angles in (-π, π], each checked by forward kinematics (the
``residual``, about 1e-15, also within 1e-12 of the singularity, where the angles come from
:func:`aaria_pin.core.rotations.angles_from_matrix`'s residual rotation). At the singularity
``sin θ2 = 0`` only ``θ1 + θ3`` (θ2 = 0) or ``θ1 - θ3`` (θ2 = π) is fixed: within
``|sin θ2| < 1e-9`` the solution is flagged ``singular`` and one member of the family is
returned, at the singularity itself the canonical one ``θ3 = 0``. Joint limits, if given, filter
the solutions (angles are taken modulo 2π into each joint's range); for a singular rotation
the whole family is searched for a member inside them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.aaria.presets import WRIST_D3
from aaria_pin.core.arguments import checked
from aaria_pin.core.rotations import angles_from_matrix, as_rotation, half_open
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = [
    "REPORT_LIMITS",
    "WRIST_D3",
    "Workspace",
    "WristBatch",
    "WristSolutions",
    "checked_limits",
    "fk_residual",
    "wrist_fk",
    "wrist_ik",
    "wrist_ik_batch",
    "wrist_workspace",
]


REPORT_LIMITS = np.radians([[0.0, 360.0], [0.0, 180.0], [-180.0, 180.0]])
"""The report's joint ranges (joint 1: 0–360°, joint 2: 0–180°; joint 3 free) [rad]."""

SINGULAR_TOLERANCE = 1e-9
"""``|sin θ2|`` below which a rotation counts as singular."""


def _joint_angles(joints: ArrayLike) -> Array:
    """Joint angles as a float array (..., 3), refused with the reason when they are not."""
    try:
        q = np.asarray(joints, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(
            "joint angles are not numbers; allowed: finite numbers, shape (..., 3) [rad]",
            parameter="joints",
        ) from None
    if q.ndim == 0 or q.shape[-1] != 3:
        raise ParameterError(
            f"joint angles have shape {q.shape}; allowed: (..., 3) [rad]",
            parameter="joints",
            value=q.shape,
            allowed="(..., 3)",
        )
    if not np.all(np.isfinite(q)):
        bad = np.argwhere(~np.isfinite(q))[0]
        shown = ", ".join(f"{v:g}" for v in q[tuple(bad[:-1])])
        raise ParameterError(
            f"joint angles ({shown}) hold {float(q[tuple(bad)]):g} at θ{bad[-1] + 1};"
            " allowed: finite numbers [rad]",
            parameter="joints",
        )
    return q


@checked
def wrist_fk(joints: ArrayLike, d3: float = WRIST_D3) -> Array:
    """Tool poses of the wrist, equation (9) of the report, vectorized.

    Args:
        joints: (..., 3) joint angles θ1, θ2, θ3 [rad]
        d3: tool distance [m]

    Returns:
        (..., 4, 4) poses of the tool in the base frame.

    Raises:
        ParameterError: angles that are not finite numbers of shape (..., 3).
    """
    q = _joint_angles(joints)
    T = np.zeros((*q.shape[:-1], 4, 4))
    _fill_rotation(q, T)
    T[..., :3, 3] = d3 * T[..., :3, 2]
    T[..., 3, 3] = 1.0
    return T


def _fill_rotation(q: Array, out: Array) -> None:
    """Write ``Rz(θ1)·Ry(θ2)·Rz(θ3)`` of (..., 3) angles into ``out[..., :3, :3]``."""
    c1, c2, c3 = np.cos(q[..., 0]), np.cos(q[..., 1]), np.cos(q[..., 2])
    s1, s2, s3 = np.sin(q[..., 0]), np.sin(q[..., 1]), np.sin(q[..., 2])
    c1c2, s1c2 = c1 * c2, s1 * c2
    out[..., 0, 0] = c1c2 * c3 - s1 * s3
    out[..., 0, 1] = -c1c2 * s3 - s1 * c3
    out[..., 0, 2] = c1 * s2
    out[..., 1, 0] = s1c2 * c3 + c1 * s3
    out[..., 1, 1] = -s1c2 * s3 + c1 * c3
    out[..., 1, 2] = s1 * s2
    out[..., 2, 0] = -s2 * c3
    out[..., 2, 1] = s2 * s3
    out[..., 2, 2] = c2


def fk_residual(joints: ArrayLike, rotations: ArrayLike) -> Array:
    """How far the rotations of joint angles are from given rotations.

    Args:
        joints: (..., 3) joint angles [rad]
        rotations: (..., 3, 3) rotations, broadcast against the angles

    Returns:
        The (...) largest entry of ``|R(joints) - rotations|``.
    """
    q = _joint_angles(joints)
    target = np.asarray(rotations, dtype=float)
    R = np.empty((*q.shape[:-1], 3, 3))
    _fill_rotation(q, R)
    R -= target
    return np.abs(R).max(axis=(-1, -2))


@dataclass(frozen=True)
class WristSolutions:
    """The inverse kinematics of one rotation.

    Attributes:
        solutions: (n, 3) joint angles [rad], n = 0, 1 or 2, each in (-π, π] unless joint
            limits move it into their range
        singular: ``|sin θ2| < 1e-9``: only θ1 + θ3 (θ2 ≈ 0) or θ1 − θ3 (θ2 ≈ π) is fixed and
            one member of that family is returned
        reachable: at least one solution is within the joint limits
        residual: the largest entry of ``|R(solution) - R|`` over the solutions (about 1e-15;
            larger when the matrix given is that far from a rotation, or, up to 1e-9·2π, for
            a member of a singular family moved into the limits at ``0 < |sin θ2| < 1e-9``)
    """

    solutions: Array
    singular: bool
    reachable: bool
    residual: float = 0.0


class WristBatch(NamedTuple):
    """Both wrist branches for many rotations.

    Attributes:
        solutions: (..., 2, 3) joint angles [rad] in (-π, π], branch θ2 >= 0 first (at a
            singularity both rows are members of the family)
        singular: (...) ``|sin θ2| < 1e-9``
        residual: (...) largest entry of ``|R(solution) - R|`` of the first row (the second's
            is within 1.4e-15 of it): the solutions are off by this much (about 1e-15 for
            rotations; the orthonormality defect of a matrix that is not quite one)
    """

    solutions: Array
    singular: Array
    residual: Array


def _other_branch(first: Array) -> Array:
    """The other branch ``θ1 ± π, -θ2, θ3 ± π`` of (..., 3) angles in (-π, π] (one rounding)."""
    turned = half_open(np.where(first > 0, first - np.pi, first + np.pi))  # a tiny a > 0: -π
    return np.stack([turned[..., 0], half_open(-first[..., 1]), turned[..., 2]], axis=-1)


def _shift_into(angle: Any, low: Any, high: Any) -> tuple[Any, Any]:
    """An angle shifted by a multiple of 2π into [low, high], and whether that worked."""
    slack = 1e-12  # either side: an angle of -7e-17 against a low limit of 0 is inside
    shifted = low - slack + np.mod(angle - low + slack, 2 * np.pi)
    return shifted, shifted <= high + slack


def _wrap_into(angles: Array, limits: Array) -> tuple[Array, np.ndarray]:
    """Angles shifted by multiples of 2π into [low, high], and whether that worked."""
    shifted, inside = _shift_into(angles, limits[:, 0], limits[:, 1])
    return shifted, np.asarray(inside.all(axis=-1), dtype=bool)


def checked_limits(limits: ArrayLike) -> Array:
    """Joint ranges as a (3, 2) float array, refused with the joint at fault otherwise.

    Args:
        limits: 3 × 2 joint ranges ``[low, high]`` [rad]

    Raises:
        ParameterError: not 3 × 2 numbers, a bound that is NaN or infinite, or low > high.
    """
    try:
        bounds = np.asarray(limits, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(
            "limits are not numbers; allowed: 3 × 2 finite [low, high] [rad]", parameter="limits"
        ) from None
    if bounds.shape != (3, 2):
        raise ParameterError(
            f"limits have shape {bounds.shape}; allowed: 3 × 2 [low, high] [rad]",
            parameter="limits",
        )
    for joint, (low, high) in enumerate(bounds.tolist(), start=1):
        if not (np.isfinite(low) and np.isfinite(high)):
            problem = "not finite"
        elif low > high:
            problem = "reversed"
        else:
            continue
        raise ParameterError(
            f"limits of joint {joint} are [{low:g}, {high:g}] rad ({problem});"
            " allowed: finite [low, high] with low <= high",
            parameter="limits",
            element=f"joint {joint}",
            value=[low, high],
            allowed="finite [low, high] with low <= high [rad]",
        )
    return bounds


def _family_member(first: Array, bounds: Array) -> Array | None:
    """A member of a singular family inside the limits, or None.

    At θ2 ≈ 0 every ``(θ1, θ2, θ3)`` with the same θ1 + θ3 gives the rotation, at θ2 ≈ π every
    one with the same θ1 − θ3. For each θ2 of the family (the extracted one and its negative)
    inside its range, the θ1 that the range of θ3 allows form an interval (modulo 2π); the
    member returned is the middle of its overlap with the range of θ1.
    """
    theta1, theta2, theta3 = (float(v) for v in first)
    two_pi = 2 * np.pi
    for candidate in (theta2, -theta2):
        shifted2, inside = _shift_into(candidate, bounds[1, 0], bounds[1, 1])
        if not inside:
            continue
        sign = 1.0 if np.cos(candidate) > 0 else -1.0  # θ1 + sign·θ3 is fixed
        fixed = theta1 + sign * theta3
        # θ1 = fixed - sign·θ3 + 2πn over θ3 in [low3, high3]
        ends = sorted((fixed - sign * bounds[2, 0], fixed - sign * bounds[2, 1]))
        n = np.ceil((bounds[0, 0] - ends[1]) / two_pi - 1e-12)
        low1 = max(bounds[0, 0], ends[0] + two_pi * n)
        high1 = min(bounds[0, 1], ends[1] + two_pi * n)
        if low1 > high1 + 1e-12:
            continue
        q1 = 0.5 * (low1 + high1)
        q3 = sign * (fixed + two_pi * n - q1)
        q3 = float(np.clip(q3, bounds[2, 0], bounds[2, 1]))
        return np.array([q1, shifted2, q3])
    return None


def wrist_ik_batch(rotations: ArrayLike) -> WristBatch:
    """Both wrist branches for many rotations at once, without limits.

    Args:
        rotations: (..., 3, 3) rotation matrices (orthonormal within 1e-6, det +1)

    Returns:
        The solutions, the singular flag and each rotation's residual (see
        :class:`WristBatch`): the first branch checked by forward kinematics, the second
        equal to it within 1.4e-15.
    """
    first = angles_from_matrix(rotations, "ZYZ", lock_tolerance=SINGULAR_TOLERANCE)  # checked
    R = np.asarray(rotations, dtype=float)
    solutions = np.stack([first.angles, _other_branch(first.angles)], axis=-2)
    # the other branch is the first with θ1 ± π, -θ2, θ3 ± π, one rounding (<= 4.5e-16) each:
    # its rotation is the first's to 1.4e-15, so checking the first alone (3.7 million/s
    # against 1.3 million/s for both rows, measured) says how far both are off
    residual = fk_residual(first.angles, R)
    return WristBatch(solutions, first.locked, residual)


@checked
def wrist_ik(rotation: ArrayLike, limits: ArrayLike | None = None) -> WristSolutions:
    """Every joint solution of the wrist for a tool rotation.

    Args:
        rotation: 3 × 3 rotation matrix (checked: orthonormal within 1e-6, det +1)
        limits: optional 3 × 2 joint ranges ``[low, high]`` [rad] (e.g. :data:`REPORT_LIMITS`)

    Returns:
        The solutions, each checked by forward kinematics (``residual``). At a singularity
        without limits, the member of the family that the rotation module extracts (θ3 = 0 at
        the singularity itself); with limits, a member inside them if the family has one.

    Raises:
        ParameterError: not a rotation matrix, or bad limits.
    """
    R, _ = as_rotation(rotation)
    if R.shape != (3, 3):
        raise ParameterError(f"rotation has shape {R.shape}; allowed: (3, 3)", parameter="rotation")
    bounds = None if limits is None else checked_limits(limits)
    first = angles_from_matrix(R, "ZYZ", lock_tolerance=SINGULAR_TOLERANCE)
    singular = bool(first.locked)
    solutions = (
        first.angles[None] if singular else np.stack([first.angles, _other_branch(first.angles)])
    )
    if bounds is not None:
        shifted, inside = _wrap_into(solutions, bounds)
        solutions = shifted[inside]
        if singular and not len(solutions):
            member = _family_member(first.angles, bounds)
            solutions = np.empty((0, 3)) if member is None else member[None]
    residual = float(fk_residual(solutions, R).max()) if len(solutions) else 0.0
    return WristSolutions(solutions, singular, bool(len(solutions)), residual)


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
        raise ParameterError(parameter="samples", value=samples, allowed="an integer >= 1")
    bounds = np.array([[-np.pi, np.pi]] * 3) if limits is None else checked_limits(limits)
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
