"""The library's compiled X-Y-Z gimbal over arrays of the tests' own angles, sample by sample.

The library turns the gimbal only inside the base's sine motion (``base_kinematics`` in
``aaria_pin.core._kinematics_kernel`` calls its compiled ``_gimbal`` per sample). The tests call
the same compiled ``_gimbal`` here on angles they choose, to hold it to the 0.1 array code bit
for bit, to finite differences, and to ``core.mjcf.gimbal_xyz_coordinates`` (its inverse).
"""

from __future__ import annotations

import numpy as np

from aaria_pin.errors import ParameterError


def gimbal_xyz_motion(
    angles: np.ndarray, rates: np.ndarray, accelerations: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``R_world_base = Rx(ax)·Ry(ay)·Rz(az)`` (T, 3, 3), body rates and their derivative (T, 3).

    Angles [rad], rates [rad/s] and accelerations [rad/s²] of the gimbal, each (T, 3).
    """
    from aaria_pin.core._kinematics_kernel import _gimbal

    n = angles.shape[0]
    for name, value in (("angles", angles), ("rates", rates), ("accelerations", accelerations)):
        if np.shape(value) != (n, 3):
            raise ParameterError(
                f"gimbal {name} have shape {np.shape(value)}; allowed: ({n}, 3)",
                parameter=name,
                value=np.shape(value),
                allowed=f"({n}, 3)",
            )
    R, omega, omega_dot = np.empty((n, 3, 3)), np.empty((n, 3)), np.empty((n, 3))
    a, r, c = (np.ascontiguousarray(x, dtype=float) for x in (angles, rates, accelerations))
    for t in range(n):
        _gimbal(*a[t], *r[t], *c[t], R[t], omega[t], omega_dot[t])
    return R, omega, omega_dot
