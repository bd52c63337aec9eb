"""The hand's orientation by ZYZ Euler angles (report, section 4.2.6), gimbal lock included.

The hand's three joints (``hand_yaw`` about z, ``hand_pitch`` about the new y, ``hand_roll``
about the new z) sit at the forearm's tip, mounted upside down (``Rx(π)``), so with all three at
zero the hand's approach axis z points straight down. With the forearm's heading
``ψ_f = α + β`` (shoulder plus elbow angle, both about the vertical), the hand's rotation in
the world is::

    R = Rz(ψ_f) · Rx(π) · Rz(φ) · Ry(θ) · Rz(ψ)

and ``(φ, θ, ψ)`` are the ZYZ angles (moving axes) of ``(Rz(ψ_f)·Rx(π))ᵀ · R``, extracted by
:func:`aaria_pin.core.rotations.angles_from_matrix` (shared with the spherical wrist). A vertical
grasp, the pick-and-place task's, is a gimbal lock (θ = 0): only φ + ψ is defined. The rotation
module then puts the whole turn into φ (ψ = 0); given the previous hand angles,
:func:`hand_angles` keeps ψ where it was instead and gives φ the rest, so a sequence of poses
moves the hand continuously; the outer angles are also unwrapped to within π of the previous
ones.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.apps.arm.ik import wrap
from aaria_pin.core.rotations import angles_from_matrix, as_rotation, elementary, matrix_from_angles
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = [
    "HAND_SEQUENCE",
    "HandAngles",
    "downward_grasp",
    "hand_angles",
    "hand_rotation",
]

HAND_SEQUENCE = "ZYZ"
"""The hand's Euler sequence (moving axes): yaw, pitch, roll joints."""


class HandAngles(NamedTuple):
    """Hand joint angles for one orientation.

    Attributes:
        angles: (φ, θ, ψ) of ``hand_yaw``, ``hand_pitch``, ``hand_roll`` [rad]
        locked: True at gimbal lock (θ within the rotation module's tolerance of 0 or π)
    """

    angles: Array
    locked: bool


def downward_grasp(yaw: float) -> Array:
    """A hand pointing straight down whose x axis (the finger's travel) is at ``yaw`` [rad].

    ``Rz(yaw)·Rx(π)`` (3 × 3); at the forearm's heading α + β it is also the hand's frame in
    the world with its joints at zero.
    """
    return np.asarray(elementary(2, yaw) @ elementary(0, np.pi))


def hand_rotation(angles: ArrayLike, heading: float) -> Array:
    """The hand's rotation in the world from its joint angles (3 × 3).

    Args:
        angles: (φ, θ, ψ) [rad]
        heading: the forearm's heading α + β [rad]
    """
    return downward_grasp(heading) @ matrix_from_angles(angles, HAND_SEQUENCE)


def hand_angles(
    rotation: ArrayLike, heading: float, previous: ArrayLike | None = None
) -> HandAngles:
    """Hand joint angles that give the hand a rotation in the world.

    Args:
        rotation: the hand's rotation in the world (3 × 3; checked to be a rotation)
        heading: the forearm's heading α + β [rad]
        previous: the hand's previous angles (φ, θ, ψ) [rad], for continuity, or None

    Returns:
        The angles (the rotation of :func:`hand_rotation` equals ``rotation``) and the lock
        flag.

    Raises:
        ParameterError: a matrix that is not a rotation, or previous angles that are not three
            finite numbers.
    """
    R, _ = as_rotation(rotation)
    if R.shape != (3, 3):
        raise ParameterError(
            f"hand rotation has shape {R.shape}; allowed: (3, 3)", parameter="rotation"
        )
    relative = downward_grasp(heading).T @ R
    extracted = angles_from_matrix(relative, HAND_SEQUENCE)
    phi, theta, psi = (float(v) for v in extracted.angles)
    locked = bool(extracted.locked)
    if previous is not None:
        prev = np.asarray(previous, dtype=float)
        if prev.shape != (3,) or not np.all(np.isfinite(prev)):
            raise ParameterError(
                f"previous hand angles {prev!r}; allowed: three finite numbers",
                parameter="previous",
                value=prev,
            )
        if locked:
            # θ ≈ 0: R = Rz(φ + ψ); θ ≈ π: R = Rz(φ - ψ)·Ry(π). Keep ψ, move φ.
            total = phi + psi if theta < np.pi / 2 else phi - psi
            psi = float(prev[2])
            phi = total - psi if theta < np.pi / 2 else total + psi
        phi = float(prev[0] + wrap(phi - prev[0]))
        psi = float(prev[2] + wrap(psi - prev[2]))
    return HandAngles(np.array([phi, theta, psi]), locked)
