"""The run record of any URDF robot: a ``signals`` table with named columns, and its inputs.

The Aaria ``senSen`` layout (:mod:`aaria_pin.aaria.sensen`) has fixed columns for six modules and 14
IMU slots. A robot loaded from a URDF has its own joints and IMUs, so its record names them:

``signals`` (T × C): column ``time`` [s]; one column ``q:<joint>`` per actuated joint in model
order [rad or m]; then six columns per IMU in layout order, ``<imu>_wx``, ``<imu>_wy``,
``<imu>_wz`` (angular velocity [rad/s]) and ``<imu>_fx``, ``<imu>_fy``, ``<imu>_fz`` (specific
force [m/s²]), both in the IMU's own axes. :func:`signal_columns` gives the names.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = ["IMU_SIGNALS", "GenericRunRecord", "ImuMount", "signal_columns"]

IMU_SIGNALS = ("wx", "wy", "wz", "fx", "fy", "fz")
"""The six signals of an IMU, in column order (the Aaria ``senSen`` layout uses them too)."""


@dataclass(frozen=True)
class ImuMount:
    """An IMU rigidly mounted on a frame of the robot.

    Attributes:
        name: the IMU's name (also its frame's name in the model)
        parent: the frame it is mounted on (a link, joint or fixed frame of the URDF)
        T_parent_imu: its pose in the parent frame, 4 × 4 [m]
    """

    name: str
    parent: str
    T_parent_imu: Array


def signal_columns(joint_names: Sequence[str], imu_names: Sequence[str]) -> tuple[str, ...]:
    """Column names of ``signals``: time, one per joint, six per IMU (module docstring)."""
    return (
        "time",
        *(f"q:{joint}" for joint in joint_names),
        *(f"{imu}_{signal}" for imu in imu_names for signal in IMU_SIGNALS),
    )


@dataclass
class GenericRunRecord:
    """Everything one run of a URDF robot records.

    Attributes:
        signals: T × C time, joint values and IMU signals (module docstring)
        joint_names: the actuated joints, in model order (n names)
        q: joint values, T × n [rad or m]
        qd: joint velocities, T × n [rad/s or m/s]
        qdd: joint accelerations, T × n [rad/s² or m/s²]
        tau: joint torques [N·m] or forces [N], T × n
        base_pose: ``T_world_base``, T × 4 × 4 [m] (the identity on a fixed base)
        base_wrench: wrench the base mount applies, ``[fx fy fz mx my mz]`` in world-aligned
            axes about the base origin, T × 6 [N, N·m] (zeros on a fixed base)
        tool_pose: ``T_world_tool``, T × 4 × 4 [m]
        imu_mounts: the IMU layout, in column order
        urdf: the URDF text the model was built from
        joint_table: n × 5 joint oscillation table, or None for a motion given otherwise
        base_table: 2 × 4 or 6 × 4 base oscillation table, or None (fixed base, or a base
            motion given otherwise)
        attributes: rate, duration, seed, noise settings, base and tool frames, units, version
    """

    signals: Array
    joint_names: tuple[str, ...]
    q: Array
    qd: Array
    qdd: Array
    tau: Array
    base_pose: Array
    base_wrench: Array
    tool_pose: Array
    imu_mounts: tuple[ImuMount, ...]
    urdf: str
    joint_table: Array | None = None
    base_table: Array | None = None
    attributes: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        n_samples, n_joints = np.shape(self.q)[0], len(self.joint_names)
        expected = {
            "signals": (n_samples, len(self.columns)),
            "q": (n_samples, n_joints),
            "qd": (n_samples, n_joints),
            "qdd": (n_samples, n_joints),
            "tau": (n_samples, n_joints),
            "base_pose": (n_samples, 4, 4),
            "base_wrench": (n_samples, 6),
            "tool_pose": (n_samples, 4, 4),
        }
        for name, shape in expected.items():
            if np.shape(getattr(self, name)) != shape:
                raise ParameterError(
                    f"run record {name} has shape {np.shape(getattr(self, name))}; allowed: {shape}"
                )

    @property
    def columns(self) -> tuple[str, ...]:
        """Names of the ``signals`` columns."""
        return signal_columns(self.joint_names, [mount.name for mount in self.imu_mounts])

    @property
    def time(self) -> Array:
        """Sample times [s]."""
        return self.signals[:, 0]

    @property
    def imu(self) -> Array:
        """IMU signals, T × S × 6 ``[wx wy wz fx fy fz]`` (a view of ``signals``)."""
        start = 1 + len(self.joint_names)
        return self.signals[:, start:].reshape(self.signals.shape[0], len(self.imu_mounts), 6)

    def imu_signals(self, name: str) -> Array:
        """The T × 6 signals of one IMU by name.

        Raises:
            ParameterError: no IMU of that name.
        """
        names = [mount.name for mount in self.imu_mounts]
        if name not in names:
            raise ParameterError(f"IMU {name!r} is not in this run; allowed: {', '.join(names)}")
        return self.imu[:, names.index(name)]
