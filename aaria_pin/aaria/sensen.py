"""The paper's 91-column ``senSen`` layout, a column view of an Aaria run's record.

``senSen`` (T × 91): column 0 time [s]; columns 1–6 the joint values q of modules 1–6 [rad or m]
(zero for an empty module); then 6 columns per IMU slot in slot order (base, tool, link 1 A,
link 1 B, …, link 6 B), each ``[wx wy wz fx fy fz]``: angular velocity [rad/s] and specific
force [m/s²] in the IMU's own axes (zero for the slots of an empty module).

An Aaria run's :class:`~aaria_pin.core.record.RunRecord` keeps the paper's module order (joints
``joint1`` … ``joint6``, the 14 IMU slots in ``senSen`` order), so ``senSen`` is a
:class:`~aaria_pin.core.record.ColumnView` over its ``time``, ``q`` and ``imu``
(:func:`sensen_view`): ``record.view("senSen")``.
"""

from __future__ import annotations

from aaria_pin.aaria.dh_robot import imu_slot_names
from aaria_pin.core.record import IMU_SIGNALS, VIEW_UNITS, ColumnView, signals_view

__all__ = [
    "IMU_SIGNALS",
    "JOINT_NAMES",
    "N_MODULES",
    "N_SENSEN_COLUMNS",
    "SENSEN_COLUMNS",
    "SENSEN_UNITS",
    "imu_slot_order",
    "sensen_view",
]

N_MODULES = 6

JOINT_NAMES: tuple[str, ...] = tuple(f"joint{module}" for module in range(1, N_MODULES + 1))
"""The joints of an Aaria run's record, one per module (zero columns for an empty module)."""


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

SENSEN_UNITS = VIEW_UNITS
"""The ``units`` attribute of ``senSen``."""


def sensen_view() -> ColumnView:
    """``senSen`` as a view of a record's ``time``, ``q`` (6 modules) and ``imu`` (14 slots).

    It is the record's flat signal view under the paper's column names.
    """
    return signals_view(JOINT_NAMES, imu_slot_order(), SENSEN_COLUMNS, SENSEN_UNITS)
