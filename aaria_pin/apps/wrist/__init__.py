"""The spherical wrist of the wrist report: forward and inverse kinematics, workspace, runs.

The package exports the wrist's kinematics, imported on first use::

    from aaria_pin.apps.wrist import wrist_fk, wrist_ik

    T_base_tool = wrist_fk([0.1, 0.5, -0.2])           # 4 × 4 [m]
    wrist_ik(T_base_tool[:3, :3]).solutions            # both branches, n × 3 [rad]
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from aaria_pin.core.lazy_exports import lazy_exports

if TYPE_CHECKING:
    from aaria_pin.apps.wrist.wrist_kinematics import WristSolutions, wrist_fk, wrist_ik

_LAZY = {
    "WristSolutions": "aaria_pin.apps.wrist.wrist_kinematics",
    "wrist_fk": "aaria_pin.apps.wrist.wrist_kinematics",
    "wrist_ik": "aaria_pin.apps.wrist.wrist_kinematics",
}

__all__ = ["WristSolutions", "wrist_fk", "wrist_ik"]

__getattr__ = lazy_exports(__name__, _LAZY)
