"""Pinocchio models with named sensor frames, on a fixed or a moving base.

This is the general core: it knows nothing of DH tables. Any URDF whose sensor mounts are
frames (links on fixed joints, as :mod:`aaria_pin.core.urdf` writes them) becomes a
:class:`RobotModel`.
With ``moving_base=True`` a free-flyer root joint (``root_joint``) carries the base: its
configuration is ``[x, y, z, qx, qy, qz, qw]`` in the world and its velocity the base's spatial
velocity in base axes, so the first 6 entries of an RNEA result are the wrench the base mount
applies, in base axes about the base origin.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin

from aaria_pin.core.arguments import checked
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

    @property
    def position_limits(self) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper position limits of the actuated joints, model order [rad or m].

        The model's ``lowerPositionLimit``/``upperPositionLimit``; ±inf where a joint has none
        (Pinocchio's ±1.8e308, or a joint of more than one configuration entry).
        """
        model = self.model
        joints = model.joints[2 if self.moving_base else 1 :]
        bounds = [
            (model.lowerPositionLimit[j.idx_q], model.upperPositionLimit[j.idx_q])
            if j.nq == 1
            else (-np.inf, np.inf)
            for j in joints
        ]
        lower, upper = np.array(bounds, dtype=float).reshape(-1, 2).T
        return np.where(lower > -1e300, lower, -np.inf), np.where(upper < 1e300, upper, np.inf)

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
    raise ModelError(f"frame {name!r} is not in model {model.name!r}", parameter="name", value=name)


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


_CARTESIAN = (
    (np.array([1.0, 0.0, 0.0]), "X"),
    (np.array([0.0, 1.0, 0.0]), "Y"),
    (np.array([0.0, 0.0, 1.0]), "Z"),
)
_UNALIGNED = {
    "revolute": "JointModelRevoluteUnaligned",
    "continuous": "JointModelRevoluteUnboundedUnaligned",
    "prismatic": "JointModelPrismaticUnaligned",
}
_ALIGNED = {"revolute": "JointModelR", "continuous": "JointModelRUB", "prismatic": "JointModelP"}


def _joint_model(joint: JointDescription) -> pin.JointModel:
    """The Pinocchio joint Pinocchio's URDF parser makes of a joint's kind and axis.

    An axis equal to x, y or z (Eigen's ``isApprox``, relative 1e-12) gives the joint about
    that axis (``JointModelRZ``, ``JointModelPX``, ``JointModelRUBY``, ...), any other the
    unaligned joint about the normalized axis.
    """
    axis = np.asarray(joint.axis, dtype=float)
    for unit, letter in _CARTESIAN:
        if np.linalg.norm(axis - unit) <= 1e-12 * min(float(np.linalg.norm(axis)), 1.0):
            return getattr(pin, _ALIGNED[joint.kind] + letter)()
    if joint.kind == "continuous":
        return _unbounded_unaligned(axis)
    return getattr(pin, _UNALIGNED[joint.kind])(axis / np.linalg.norm(axis))


def _unbounded_unaligned(axis: np.ndarray) -> pin.JointModel:
    """An unbounded revolute joint about an unaligned axis.

    Pinocchio's Python binding cannot set this joint's axis, so the joint is taken from the
    model its URDF parser builds of a one-joint robot (the axis written exactly, normalized by
    the parser as for any URDF).
    """
    xyz = " ".join(repr(float(v)) for v in axis)
    urdf = (
        '<robot name="axis"><link name="a"/><link name="b"/>'
        '<joint name="j" type="continuous"><parent link="a"/><child link="b"/>'
        f'<axis xyz="{xyz}"/></joint></robot>'
    )
    return pin.buildModelFromXML(urdf).joints[1]


def _limits(joint: JointDescription) -> tuple[np.ndarray, np.ndarray]:
    """Configuration limits as the parser sets them (a continuous joint's cos/sin: ±1.01)."""
    if joint.kind == "continuous":
        return np.full(2, -1.01), np.full(2, 1.01)
    return np.array([joint.lower]), np.array([joint.upper])


def _append_fixed_links(
    model: pin.Model,
    joint_id: int,
    link: str,
    children: Mapping[str, Sequence[JointDescription]],
    inertias: Mapping[str, pin.Inertia | None],
) -> None:
    """Add to a joint's inertia those of the links fixed to its link, in the first version's order.

    Adding a frame to a Pinocchio model adds the frame's inertia to its joint
    (``addFrame(frame, append_inertia=True)``), a zero one too, which rescales the joint's
    centre of mass by ``m·(1/m)``: not always exactly 1. The first version of
    :func:`model_from_description` added each fixed link's joint frame and body frame (zero
    inertia) and then the link's inertia, link by link in this order (a link's fixed joints last
    to first, then depth first); the same operations in the same order keep the models of DH
    arms bit for bit. The frames themselves are added in the URDF parser's order, without
    inertia.
    """
    zero = pin.Inertia.Zero()
    stack = [(link, pin.SE3.Identity())]
    while stack:
        parent, placement = stack.pop()
        for joint in reversed(children.get(parent, ())):
            if joint.kind != "fixed":
                continue
            offset = placement * pin.SE3(joint.T_parent_child)
            for _frame in ("fixed joint frame", "body frame"):
                model.inertias[joint_id] += offset.act(zero)
            child_inertia = inertias[joint.child]
            if child_inertia is not None:
                model.appendBodyToJoint(joint_id, child_inertia, offset)
            stack.append((joint.child, offset))


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
    ``emit_urdf(description)``: the same joints in the same order (revolute, continuous and
    prismatic about any axis, the Cartesian ones as ``JointModelRX`` ... ``JointModelPZ``),
    placements, limits and inertias (fixed links merged into their moving parent), and the same
    frames in the same order (one per joint, link and fixed joint, with their parents,
    placements and the parser's frame inertias). It skips writing and parsing XML, which
    matters when thousands of random arms are built. Visual and collision shapes do not enter
    the model.

    Args:
        description: links and joints; the first link is the root
        moving_base: add a free-flyer root joint carrying the base
        base_frame: name of the base frame
        tool_frame: name of the tool frame
        sensor_frames: IMU frame names in record order (default: frames named ``imu_*``)

    Returns:
        The robot model.

    Raises:
        ModelError: a named frame is missing.
    """
    model = pin.Model()
    model.name = description.name
    children: dict[str, list[JointDescription]] = {}
    for joint in description.joints:
        children.setdefault(joint.parent, []).append(joint)
    inertias: dict[str, pin.Inertia | None] = {}
    for link in description.links:
        mass_properties = link.inertia()
        inertias[link.name] = (
            None
            if mass_properties is None
            else pin.Inertia(mass_properties.mass, mass_properties.com, mass_properties.inertia_com)
        )

    def add_frame(name: str, joint: int, parent: int, placement: pin.SE3, kind: Any) -> int:
        return int(model.addFrame(pin.Frame(name, joint, parent, placement, kind), False))

    root = description.links[0].name
    root_inertia = inertias[root]
    body = pin.FrameType.BODY
    if moving_base:
        joint_id = model.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "root_joint")
        joint_frame = add_frame("root_joint", joint_id, 0, pin.SE3.Identity(), pin.FrameType.JOINT)
        root_frame = add_frame(root, joint_id, joint_frame, pin.SE3.Identity(), body)
    else:
        joint_id = 0
        frame = pin.Frame(root, 0, 0, pin.SE3.Identity(), body)
        if root_inertia is not None:
            frame.inertia = root_inertia  # the parser keeps a fixed root's inertia on its frame
        root_frame = int(model.addFrame(frame, False))
    if root_inertia is not None:
        model.appendBodyToJoint(joint_id, root_inertia, pin.SE3.Identity())
    _append_fixed_links(model, joint_id, root, children, inertias)

    # Depth first, a link's joints by name: urdfdom lists a link's children by joint name and
    # Pinocchio's parser visits them in that order.
    def below(link: str, joint_id: int, placement: pin.SE3, frame: int) -> list[Any]:
        out = sorted(children.get(link, []), key=lambda joint: joint.name, reverse=True)
        return [(joint, joint_id, placement, frame) for joint in out]  # last popped first

    stack = below(root, joint_id, pin.SE3.Identity(), root_frame)
    while stack:
        joint, joint_id, placement, link_frame = stack.pop()
        offset = placement * pin.SE3(joint.T_parent_child)
        child_inertia = inertias[joint.child]
        if joint.kind == "fixed":
            frame = pin.Frame(joint.name, joint_id, link_frame, offset, pin.FrameType.FIXED_JOINT)
            if child_inertia is not None:
                frame.inertia = child_inertia  # as the parser: the fixed link's inertia
            fixed = int(model.addFrame(frame, False))
            child_frame = add_frame(joint.child, joint_id, fixed, offset, body)
            stack += below(joint.child, joint_id, offset, child_frame)
            continue
        lower, upper = _limits(joint)
        new_joint = model.addJoint(
            joint_id,
            _joint_model(joint),
            offset,
            joint.name,
            np.array([joint.effort]),
            np.array([joint.velocity]),
            lower,
            upper,
        )
        joint_frame = add_frame(
            joint.name, new_joint, link_frame, pin.SE3.Identity(), pin.FrameType.JOINT
        )
        child_frame = add_frame(joint.child, new_joint, joint_frame, pin.SE3.Identity(), body)
        if child_inertia is not None:
            model.appendBodyToJoint(new_joint, child_inertia, pin.SE3.Identity())
        _append_fixed_links(model, new_joint, joint.child, children, inertias)
        stack += below(joint.child, new_joint, pin.SE3.Identity(), child_frame)
    return _finish(model, None, moving_base, base_frame, tool_frame, sensor_frames)


@checked
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
        ModelError: the URDF cannot be parsed (urdfdom's own messages, which it prints to the
            process's standard error, are captured and named in the one line), or a named frame
            is missing.

    Warns:
        UserWarning: urdfdom complained (e.g. of a shape it skips) but the model was built.
    """
    from aaria_pin.core.native_stderr import captured_stderr

    failure: Exception | None = None
    with captured_stderr() as printed:  # urdfdom prints its complaints to fd 2
        try:
            if moving_base:
                model = pin.buildModelFromXML(urdf, pin.JointModelFreeFlyer())
            else:
                model = pin.buildModelFromXML(urdf)
        except (RuntimeError, ValueError) as exc:
            failure = exc
    said = printed.folded()
    if failure is not None:
        reason = f"urdfdom: {said}" if said else " ".join(str(failure).split())
        raise ModelError(  # no allowed field: the CLI prints the line as written
            f"URDF is not valid ({reason}); allowed: a URDF Pinocchio's reader (urdfdom) parses",
            parameter="urdf",
            value=reason,
        )
    if said:
        warnings.warn(f"urdfdom: {said}", UserWarning, stacklevel=2)
    return _finish(model, urdf, moving_base, base_frame, tool_frame, sensor_frames)
