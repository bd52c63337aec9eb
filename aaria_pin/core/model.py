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

from aaria_pin.core.urdf import JointDescription, RobotDescription
from aaria_pin.errors import ModelError

__all__ = ["GRAVITY", "RobotModel", "build_model", "frame_index", "model_from_description"]

GRAVITY = np.array([0.0, 0.0, -9.81])
"""Gravity in the world frame [m/s²]."""


@dataclass(frozen=True)
class RobotModel:
    """A Pinocchio model and the names that matter to a simulation.

    Attributes:
        model: the Pinocchio model (gravity set to :data:`GRAVITY`)
        urdf: the URDF text it was built from (None when built from a description)
        moving_base: whether a free-flyer root joint carries the base
        base_frame: the base frame's name
        tool_frame: the tool frame's name
        sensor_frames: IMU frame names, in record order
    """

    model: pin.Model
    urdf: str | None
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
        return frame_index(self.model, name)

    def neutral(self) -> np.ndarray:
        """Configuration with the base at the world origin and every joint at zero."""
        return np.asarray(pin.neutral(self.model))


def frame_index(model: pin.Model, name: str) -> int:
    """Index of a frame by name, a link (body frame) first when a joint has the same name.

    Raises:
        ModelError: no frame of that name.
    """
    if model.existFrame(name, pin.FrameType.BODY):
        return int(model.getFrameId(name, pin.FrameType.BODY))
    for index, frame in enumerate(model.frames):
        if frame.name == name:
            return index
    raise ModelError(f"frame {name!r} is not in model {model.name!r}")


def _finish(
    model: pin.Model,
    urdf: str | None,
    moving_base: bool,
    base_frame: str,
    tool_frame: str,
    sensor_frames: Sequence[str] | None,
) -> RobotModel:
    model.gravity.linear = GRAVITY
    if sensor_frames is None:
        sensor_frames = [frame.name for frame in model.frames if frame.name.startswith("imu_")]
    robot = RobotModel(model, urdf, moving_base, base_frame, tool_frame, tuple(sensor_frames))
    for name in (base_frame, tool_frame, *robot.sensor_frames):
        robot.frame_id(name)
    return robot


def model_from_description(
    description: RobotDescription,
    *,
    moving_base: bool = False,
    base_frame: str = "base",
    tool_frame: str = "tool_tip",
    sensor_frames: Sequence[str] | None = None,
) -> RobotModel:
    """Build the Pinocchio model of a robot description directly, without URDF text.

    The model equals the one Pinocchio's URDF parser builds from
    ``emit_urdf(description)``: the same joints (revolute and prismatic about z), placements,
    limits and inertias (fixed links merged into their moving parent), and a frame for every link
    and fixed joint, with the same names. It skips writing and parsing XML, which matters when
    thousands of random arms are built.

    Args:
        description: links and joints; the first link is the root
        moving_base: add a free-flyer root joint carrying the base
        base_frame: name of the base frame
        tool_frame: name of the tool frame
        sensor_frames: IMU frame names in record order (default: frames named ``imu_*``)

    Returns:
        The robot model.
    """
    model = pin.Model()
    model.name = description.name
    children: dict[str, list[JointDescription]] = {}
    for joint in description.joints:
        children.setdefault(joint.parent, []).append(joint)
    links = {link.name: link for link in description.links}

    def inertia(link: str) -> pin.Inertia | None:
        mass_properties = links[link].inertia()
        if mass_properties is None:
            return None
        return pin.Inertia(mass_properties.mass, mass_properties.com, mass_properties.inertia_com)

    root = description.links[0].name
    joint_id, frame_id = 0, 0
    if moving_base:
        joint_id = model.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "root_joint")
        frame_id = model.addJointFrame(joint_id, 0)
    stack = [
        (
            root,
            joint_id,
            pin.SE3.Identity(),
            model.addBodyFrame(root, joint_id, pin.SE3.Identity(), frame_id),
        )
    ]
    if (root_inertia := inertia(root)) is not None:
        model.appendBodyToJoint(joint_id, root_inertia, pin.SE3.Identity())
    while stack:
        link, joint_id, placement, link_frame = stack.pop()
        for joint in reversed(children.get(link, [])):
            offset = placement * pin.SE3(joint.T_parent_child)
            child_inertia = inertia(joint.child)
            if joint.kind == "fixed":
                fixed = model.addFrame(
                    pin.Frame(joint.name, joint_id, link_frame, offset, pin.FrameType.FIXED_JOINT)
                )
                child_frame = model.addBodyFrame(joint.child, joint_id, offset, fixed)
                if child_inertia is not None:
                    model.appendBodyToJoint(joint_id, child_inertia, offset)
                stack.append((joint.child, joint_id, offset, child_frame))
                continue
            joint_model = pin.JointModelRZ() if joint.kind == "revolute" else pin.JointModelPZ()
            new_joint = model.addJoint(
                joint_id,
                joint_model,
                offset,
                joint.name,
                np.array([joint.effort]),
                np.array([joint.velocity]),
                np.array([joint.lower]),
                np.array([joint.upper]),
            )
            joint_frame = model.addJointFrame(new_joint, link_frame)
            child_frame = model.addBodyFrame(
                joint.child, new_joint, pin.SE3.Identity(), joint_frame
            )
            if child_inertia is not None:
                model.appendBodyToJoint(new_joint, child_inertia, pin.SE3.Identity())
            stack.append((joint.child, new_joint, pin.SE3.Identity(), child_frame))
    return _finish(model, None, moving_base, base_frame, tool_frame, sensor_frames)


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
    return _finish(model, urdf, moving_base, base_frame, tool_frame, sensor_frames)
