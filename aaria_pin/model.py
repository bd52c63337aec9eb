"""Pinocchio models with named sensor frames, on a fixed or a moving base.

This is the general core: it knows nothing of DH tables. Any URDF whose sensor mounts are
frames (links on fixed joints, as the DH emitter writes them) becomes a :class:`RobotModel`.
With ``moving_base=True`` a free-flyer root joint (``root_joint``) carries the base: its
configuration is ``[x, y, z, qx, qy, qz, qw]`` in the world and its velocity the base's spatial
velocity in base axes, so the first 6 entries of an RNEA result are the wrench the base mount
applies, in base axes about the base origin.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from aaria_pin.errors import ModelError

__all__ = ["GRAVITY", "RobotModel", "build_model"]

GRAVITY = np.array([0.0, 0.0, -9.81])
"""Gravity in the world frame [m/s²]."""


@dataclass(frozen=True)
class RobotModel:
    """A Pinocchio model and the names that matter to a simulation.

    Attributes:
        model: the Pinocchio model (gravity set to :data:`GRAVITY`)
        urdf: the URDF text it was built from
        moving_base: whether a free-flyer root joint carries the base
        base_frame: the base frame's name
        tool_frame: the tool frame's name
        sensor_frames: IMU frame names, in record order
    """

    model: pin.Model
    urdf: str
    moving_base: bool
    base_frame: str
    tool_frame: str
    sensor_frames: tuple[str, ...]

    @property
    def base_nq(self) -> int:
        """Configuration entries of the base (7 on a moving base, else 0)."""
        return 7 if self.moving_base else 0

    @property
    def base_nv(self) -> int:
        """Velocity entries of the base (6 on a moving base, else 0)."""
        return 6 if self.moving_base else 0

    @property
    def joint_names(self) -> tuple[str, ...]:
        """Names of the actuated joints, in model order (the root joint excluded)."""
        first = 2 if self.moving_base else 1
        return tuple(self.model.names[first:])

    @property
    def n_joints(self) -> int:
        """Number of actuated degrees of freedom."""
        return int(self.model.nv) - self.base_nv

    def frame_id(self, name: str) -> int:
        """Index of a frame by name.

        Raises:
            ModelError: no frame of that name.
        """
        if not self.model.existFrame(name):
            raise ModelError(f"frame {name!r} is not in model {self.model.name!r}")
        return int(self.model.getFrameId(name))

    def neutral(self) -> np.ndarray:
        """Configuration with the base at the world origin and every joint at zero."""
        return np.asarray(pin.neutral(self.model))


def build_model(
    urdf: str,
    *,
    moving_base: bool = False,
    base_frame: str = "base",
    tool_frame: str = "tool_tip",
    sensor_frames: Sequence[str] | None = None,
) -> RobotModel:
    """Build a Pinocchio model from URDF text.

    Args:
        urdf: the URDF document
        moving_base: add a free-flyer root joint carrying the base
        base_frame: name of the base frame
        tool_frame: name of the tool frame
        sensor_frames: IMU frame names in record order; default: every frame whose name starts
            with ``imu_``, in model order

    Returns:
        The robot model.

    Raises:
        ModelError: the URDF cannot be parsed, or a named frame is missing.
    """
    try:
        if moving_base:
            model = pin.buildModelFromXML(urdf, pin.JointModelFreeFlyer())
        else:
            model = pin.buildModelFromXML(urdf)
    except (RuntimeError, ValueError) as exc:
        raise ModelError(f"URDF cannot be built into a model: {exc}") from None
    model.gravity.linear = GRAVITY
    if sensor_frames is None:
        sensor_frames = [frame.name for frame in model.frames if frame.name.startswith("imu_")]
    robot = RobotModel(model, urdf, moving_base, base_frame, tool_frame, tuple(sensor_frames))
    for name in (base_frame, tool_frame, *robot.sensor_frames):
        robot.frame_id(name)
    return robot
