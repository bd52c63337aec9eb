"""The recorded-run identification tests' arm and oracle (apps and CLI tests share them).

:func:`small_arm_tables`: a 3-module arm (module 1 revolute, module 2 empty, module 3
prismatic) with its joint and base oscillation tables; :func:`tool_tip_error`: the tool tips of
two DH tables at the same joint values by Pinocchio's forward kinematics (independent of the
fit's own model).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from aaria_pin.aaria.dh_robot import build_dh_robot


def small_arm_tables() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The DH table (8 × 5), joint table (8 × 5) and base table (2 × 4) of the 3-module arm."""
    table = np.zeros((8, 5))
    table[0] = [np.pi / 2, 0.3, 0.0, 0.2, 1]
    table[2] = [np.pi / 3, 0.25, 0.4, 0.3, 2]
    table[6] = [0.0, 0.2, 0.0, 0.0, 1]
    joints = np.zeros((8, 5))
    joints[0] = [0.6, 0.0, 0.0, 2.3, 2.5]
    joints[2] = [0.0, 0.08, 0.0, 1.7, 1.5]
    base = np.array([[0.05, 0.0, 1.0, 0.0], [0.05, 0.0, 0.7, 0.3]])
    return table, joints, base


def tool_tip_error(table: np.ndarray, true_table: np.ndarray, q: np.ndarray) -> float:
    """Largest distance [m] between the two tables' tool tips at 50 of the joint values ``q``."""
    tips = []
    for dh in (np.asarray(table, dtype=float), np.asarray(true_table, dtype=float)):
        robot = build_dh_robot(dh)
        model = robot.model()
        data = model.model.createData()
        frame = model.frame_id("tool_tip")
        columns = [m - 1 for m in robot.chain.modules]
        rows = []
        for t in np.linspace(0, q.shape[0] - 1, 50).astype(int):
            pin.framesForwardKinematics(model.model, data, np.asarray(q[t, columns], dtype=float))
            rows.append(data.oMf[frame].translation.copy())
        tips.append(np.array(rows))
    return float(np.max(np.linalg.norm(tips[0] - tips[1], axis=1)))
