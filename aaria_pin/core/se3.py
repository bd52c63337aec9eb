"""Small homogeneous-transform helpers shared by the DH, URDF and kinematics modules."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


def _plane_rotation(angle: float, plane: slice) -> Array:
    """Homogeneous rotation in the plane of two consecutive axes (y-z: about x; x-y: about z).

    Args:
        angle: rotation angle [rad]
        plane: the two axes' rows and columns of the 4 × 4 transform

    Returns:
        4 × 4 transform.
    """
    c, s = np.cos(angle), np.sin(angle)
    T = np.eye(4)
    T[plane, plane] = [[c, -s], [s, c]]
    return T


def rot_x(angle: float) -> Array:
    """The 4 × 4 homogeneous rotation about x by ``angle`` [rad]."""
    return _plane_rotation(angle, slice(1, 3))


def rot_z(angle: float) -> Array:
    """The 4 × 4 homogeneous rotation about z by ``angle`` [rad]."""
    return _plane_rotation(angle, slice(0, 2))


def translation(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> Array:
    """Homogeneous pure translation.

    Args:
        x: offset along x [m]
        y: offset along y [m]
        z: offset along z [m]

    Returns:
        4 × 4 transform.
    """
    T = np.eye(4)
    T[:3, 3] = (x, y, z)
    return T


def chain(*transforms: Array) -> Array:
    """Product of homogeneous transforms, left to right."""
    T = np.eye(4)
    for factor in transforms:
        T = T @ factor
    return T


def rpy_from_matrix(R: Array) -> tuple[float, float, float]:
    """URDF roll-pitch-yaw of a rotation matrix, ``R = Rz(yaw)·Ry(pitch)·Rx(roll)``.

    At gimbal lock (|pitch| = pi/2) roll is set to zero and yaw carries the whole rotation about
    the vertical, so the angles still reproduce ``R`` exactly.

    Args:
        R: 3 × 3 rotation matrix

    Returns:
        (roll, pitch, yaw) [rad]
    """
    cos_pitch = float(np.hypot(R[0, 0], R[1, 0]))
    pitch = float(np.arctan2(-R[2, 0], cos_pitch))
    if cos_pitch > 1e-10:
        roll = float(np.arctan2(R[2, 1], R[2, 2]))
        yaw = float(np.arctan2(R[1, 0], R[0, 0]))
    else:
        roll = 0.0
        yaw = float(np.arctan2(-R[0, 1], R[1, 1]))
    return roll, pitch, yaw
