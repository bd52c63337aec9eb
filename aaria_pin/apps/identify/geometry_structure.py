"""The arm's structure from its signals, and the DH table and IMU mounts of a parameter vector.

What the set-up defines rather than measures: the base IMU's frame is the base frame and the
tool IMU's frame is the tool-tip frame (``imu_base`` at the base origin, ``imu_tool`` at the
tool tip, both unrotated), so their mounts are identity. A revolute module's ``theta`` and a
prismatic module's rail length ``d`` do not act on the kinematics; the table gives 0 and the
shortest rail the encoder's range fits in. The base row (row 8) is zeros; the tool row is
``[0, a7, 0, 0, 1]``.
"""

from __future__ import annotations

import numpy as np

from aaria_pin.apps.identify.geometry_input import BASE_PARENT, TOOL_PARENT, ArmSignals
from aaria_pin.apps.identify.geometry_model import ArmLayout, rotation_from_vector, wrap_angle
from aaria_pin.apps.identify.geometry_start import detect_kind
from aaria_pin.core.record import ImuMount
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = [
    "arm_layout",
    "estimated_mounts",
    "joint_kinds",
    "length_indices",
    "table_lengths",
    "table_of",
]

_MOVING = 1e-9  # [rad or m] an encoder whose range is below this does not move


_ROUND_UP = 1e-3  # [m] a length this close below 0 is 0


def arm_layout(signals: ArmSignals) -> tuple[ArmLayout, int]:
    """The arm's structure from the encoders and the IMUs' parents.

    Args:
        signals: a DH arm's signals: 6 joint columns by module, a base, a tool and link IMUs

    Returns:
        The layout (joint kinds still unknown: ``""``) and the base IMU's index.

    Raises:
        ParameterError: no base or tool IMU, a moving module without an IMU on its link (or
            one with IMUs that never moves), no moving module.
    """
    parents = list(signals.parents)
    for needed in (BASE_PARENT, TOOL_PARENT):
        if needed not in parents:
            raise ParameterError(
                f"record has no IMU on {needed!r}; allowed: a DH run with base and tool IMUs",
                parameter="record",
                value=needed,
                allowed="base and tool IMUs",
            )
    base, tool = parents.index(BASE_PARENT), parents.index(TOOL_PARENT)
    modules, link_imus = [], []
    for module in range(1, 7):
        on_link = tuple(i for i, p in enumerate(parents) if p == f"link{module}")
        moving = float(np.ptp(signals.q[:, module - 1])) > _MOVING
        if not moving and not on_link:
            continue
        if not on_link or not moving:
            problem = "moves but no IMU is on its link" if moving else "has IMUs but never moves"
            raise ParameterError(
                f"module {module} {problem}; allowed: a moving joint with an IMU on its link, "
                "or an empty module",
                parameter="record",
                value=f"module {module}",
                allowed="a moving joint with an IMU on its link, or an empty module",
            )
        modules.append(module)
        link_imus.append(on_link)
    if not modules:
        raise ParameterError(
            "no module moves; allowed: at least one moving joint",
            parameter="record",
            allowed="at least one moving joint",
        )
    return ArmLayout(tuple(modules), ("",) * len(modules), tuple(link_imus), tool), base


def joint_kinds(
    signals: ArmSignals, layout: ArmLayout, base: int, qd: Array
) -> tuple[tuple[str, float], ...]:
    """Each module's joint kind from the gyroscopes on either side of it (``detect_kind``).

    Args:
        signals: the arm's signals
        layout: its layout (:func:`arm_layout`)
        base: the base IMU's index
        qd: the layout's joint velocities, T × m

    Returns:
        Per module of the layout ``"revolute"`` or ``"prismatic"`` and the statistic that
        decided (about 1 revolute, 0 prismatic; the threshold is 0.5).
    """
    kinds = []
    for index, group in enumerate(layout.link_imus):
        parent = base if index == 0 else layout.link_imus[index - 1][0]
        imu = signals.imu
        kinds.append(detect_kind(imu[:, group[0], :3], imu[:, parent, :3], qd[:, index]))
    return tuple(kinds)


def length_indices(layout: ArmLayout) -> list[int]:
    """Indices of the DH lengths that must not be negative: d (revolute), every a, a7."""
    out = []
    for index, kind in enumerate(layout.kinds):
        if kind == "revolute":
            out.append(3 * index + 1)
        out.append(3 * index + 2)
    out.append(layout.n_dh - 1)
    return out


def table_lengths(layout: ArmLayout) -> tuple[list[int], list[int]]:
    """Rows and columns of the table's lengths that must not be negative."""
    rows, columns = [6], [1]
    for module, kind in zip(layout.modules, layout.kinds, strict=True):
        rows.append(module - 1)
        columns.append(1)
        if kind == "revolute":
            rows.append(module - 1)
            columns.append(3)
    return rows, columns


def table_of(layout: ArmLayout, x: Array, q: Array) -> Array:
    """The 8 × 5 table of a parameter vector (lengths within a millimetre below 0 set to 0)."""
    x = x.copy()
    lengths = length_indices(layout)
    x[lengths] = np.where((x[lengths] < 0) & (x[lengths] > -_ROUND_UP), 0.0, x[lengths])
    table = np.zeros((8, 5))
    for index, (module, kind) in enumerate(zip(layout.modules, layout.kinds, strict=True)):
        alpha, second, a = x[3 * index : 3 * index + 3]
        if kind == "revolute":
            table[module - 1] = [wrap_angle(alpha), a, 0.0, second, 1]
        else:
            rail = 2.0 * float(np.max(np.abs(q[:, index]))) * (1 + 1e-9)
            table[module - 1] = [wrap_angle(alpha), a, wrap_angle(second), rail, 2]
    table[6] = [0.0, x[layout.n_dh - 1], 0.0, 0.0, 1]
    return table


def estimated_mounts(signals: ArmSignals, layout: ArmLayout, x: Array) -> tuple[ImuMount, ...]:
    """Every IMU's mount of a parameter vector, in the signals' order.

    The base and tool IMUs are identity (as defined); slots with no predicted IMU get a zero
    pose and parent ``""``.
    """
    poses: dict[int, Array] = {}
    for index, group in enumerate(layout.link_imus):
        for position, imu in enumerate(group):
            offset = layout.mount_offset(index, position)
            T = np.eye(4)
            T[:3, :3] = rotation_from_vector(x[offset : offset + 3])
            T[:3, 3] = x[offset + 3 : offset + 6]
            poses[imu] = T
    out = []
    for i, (name, parent) in enumerate(zip(signals.imu_names, signals.parents, strict=True)):
        if parent in (BASE_PARENT, TOOL_PARENT):
            out.append(ImuMount(name, parent, np.eye(4)))
        elif i in poses:
            out.append(ImuMount(name, parent, poses[i]))
        else:
            out.append(ImuMount(name, "", np.zeros((4, 4))))
    return tuple(out)
