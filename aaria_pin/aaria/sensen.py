"""The run record of an Aaria simulation and the paper's 91-column ``senSen`` layout.

``senSen`` (T × 91): column 0 time [s]; columns 1–6 the joint values q of modules 1–6 [rad or m]
(zero for an empty module); then 6 columns per IMU slot in slot order (base, tool, link 1 A,
link 1 B, …, link 6 B), each ``[wx wy wz fx fy fz]``: angular velocity [rad/s] and specific
force [m/s²] in the IMU's own axes (zero for the slots of an empty module).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from aaria_pin.aaria.dh_robot import imu_slot_names
from aaria_pin.core.record import IMU_SIGNALS
from aaria_pin.core.se3 import Array

__all__ = [
    "IMU_SIGNALS",
    "N_MODULES",
    "N_SENSEN_COLUMNS",
    "SENSEN_COLUMNS",
    "RunRecord",
    "imu_slot_order",
    "new_sensen",
]

N_MODULES = 6


def imu_slot_order() -> tuple[str, ...]:
    """The 14 IMU slot names in ``senSen`` order."""
    return imu_slot_names(range(1, N_MODULES + 1))


SENSEN_COLUMNS: tuple[str, ...] = (
    "time",
    *(f"q{module}" for module in range(1, N_MODULES + 1)),
    *(f"{slot}_{signal}" for slot in imu_slot_order() for signal in IMU_SIGNALS),
)
"""Names of the 91 ``senSen`` columns, e.g. ``imu_link3_b_fz``."""

N_SENSEN_COLUMNS = len(SENSEN_COLUMNS)


def new_sensen(time: Array) -> tuple[Array, Array, Array]:
    """A ``senSen`` array with its time column filled, and views of its other blocks.

    Args:
        time: sample times, shape (T,) [s]

    Returns:
        ``senSen`` (T × 91, zeros but the time column), the joint-value block (T × 6 view of
        columns 1–6) and the IMU block (T × 14 × 6 view of columns 7–90, ``[wx wy wz fx fy fz]``
        per slot), to be filled in place.
    """
    n = time.shape[0]
    sensen = np.zeros((n, N_SENSEN_COLUMNS))
    sensen[:, 0] = time
    imu = sensen[:, 1 + N_MODULES :].reshape(n, len(imu_slot_order()), len(IMU_SIGNALS))
    return sensen, sensen[:, 1 : 1 + N_MODULES], imu


@dataclass
class RunRecord:
    """Everything one simulation run records (module order, zeros for empty modules).

    Attributes:
        senSen: T × 91 signals (see the module docstring)
        senSenDH: 8 × 5 DH table used
        senSenJ: 8 × 5 joint oscillation table used
        senSenB: base oscillation table used, as given (2 × 4 or 6 × 4)
        q: joint values, T × 6 [rad or m]
        qd: joint velocities, T × 6 [rad/s or m/s]
        qdd: joint accelerations, T × 6 [rad/s² or m/s²]
        tau: joint torques [N·m] or forces [N], T × 6
        base_wrench: wrench the base mount applies, ``[fx fy fz mx my mz]`` in world-aligned axes
            about the base origin, T × 6 [N, N·m]
        tool_pose: tool-tip pose in the world, T × 4 × 4
        imu_mount: each slot's pose in its parent frame, 14 × 4 × 4
        attributes: rate, duration, seed, noise settings, gravity, units, version
    """

    senSen: Array
    senSenDH: Array
    senSenJ: Array
    senSenB: Array
    q: Array
    qd: Array
    qdd: Array
    tau: Array
    base_wrench: Array
    tool_pose: Array
    imu_mount: Array
    attributes: dict[str, Any] = field(default_factory=dict)

    ARRAY_NAMES = (
        "senSen",
        "senSenDH",
        "senSenJ",
        "senSenB",
        "q",
        "qd",
        "qdd",
        "tau",
        "base_wrench",
        "tool_pose",
        "imu_mount",
    )

    @property
    def time(self) -> Array:
        """Sample times [s]."""
        return self.senSen[:, 0]

    def arrays(self) -> dict[str, Array]:
        """The record's arrays by name, in file order."""
        return {name: getattr(self, name) for name in self.ARRAY_NAMES}
