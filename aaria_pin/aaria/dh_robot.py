"""From a DH chain to a robot: bodies with density-based inertias, IMU slots, URDF, names.

Frame and link names (stable; other tools read them):

- ``base``: the root link, the paper's base frame; ``dh0``: the frame the first module acts in
  (``base · R_WDH`` for an Aaria table), on a fixed joint ``dh0_joint``.
- ``link{i}`` on joint ``joint{i}`` for module (table row) ``i``: its frame is the module's
  post-joint frame. Empty modules have neither.
- ``tool`` (fixed joint ``tool_joint`` at the last link's end frame) and ``tool_tip`` (fixed joint
  ``tool_tip_joint``, ``Tx(a_7)`` further on, DH orientation).
- IMU slots, massless links on fixed joints ``<slot>_joint``: ``imu_base`` (parent ``base``),
  ``imu_tool`` (parent ``tool_tip``), ``imu_link{i}_a`` and ``imu_link{i}_b`` (parent ``link{i}``).

Bodies: a revolute module's link carries a cylinder housing along its joint axis, centred on the
joint; a prismatic module's link carries a slider block centred on the joint, and its rail (a rod
of the rail length, centred on the joint frame at q = 0) is fixed to the parent link. Each link
has a box along the segment from its joint to its end (length a for an Aaria table); a zero
length gives no box. The tool is a box of length a_7.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.aaria.dh import Convention, KinematicChain, chain_from_table
from aaria_pin.core.arguments import checked
from aaria_pin.core.inertia import ALUMINIUM_DENSITY, Inertia, Part
from aaria_pin.core.se3 import Array, translation
from aaria_pin.core.urdf import JointDescription, LinkDescription, RobotDescription
from aaria_pin.core.urdf_emitter import emit_urdf
from aaria_pin.errors import ParameterError

if TYPE_CHECKING:
    from aaria_pin.core.model import RobotModel

__all__ = [
    "BASE_FRAME",
    "TOOL_FRAME",
    "BodyDimensions",
    "DHRobot",
    "ImuSlot",
    "build_dh_robot",
    "default_imu_slots",
    "describe_chain",
    "imu_slot_links",
    "imu_slot_names",
    "link_name",
    "mount_imu_slots",
]

MAX_DENSITY = 1.0e5
"""Largest density accepted [kg/m³] (the densest element, osmium, is 22,590)."""
MAX_SECTION = 10.0
"""Largest cross-section or housing dimension accepted [m]."""

BASE_FRAME = "base"
TOOL_FRAME = "tool_tip"
_SEGMENT_EPS = 1e-12
_IMU_B_FRACTION = 0.9


@checked
@dataclass(frozen=True)
class BodyDimensions:
    """Dimensions and densities of the bodies built around a DH chain.

    Attributes:
        link_width: link box size along the post-joint y axis [m]
        link_height: link box size along the post-joint z axis [m]
        housing_radius: radius of a revolute joint's cylinder housing [m]
        housing_length: length of the housing along the joint axis [m]
        rail_radius: radius of a prismatic joint's rail rod [m]
        density: density of every body [kg/m³]
        density_overrides: density per link name (``"link3"``, ``"tool"``) [kg/m³]
    """

    link_width: float = 0.06
    link_height: float = 0.06
    housing_radius: float = 0.05
    housing_length: float = 0.10
    rail_radius: float = 0.015
    density: float = ALUMINIUM_DENSITY
    density_overrides: Mapping[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for name in (
            "link_width",
            "link_height",
            "housing_radius",
            "housing_length",
            "rail_radius",
        ):
            value = getattr(self, name)
            if not (np.isfinite(value) and 0 < value <= MAX_SECTION):
                raise ParameterError(
                    f"{name} is {value!r} m; allowed: a length 0 < length <= {MAX_SECTION:g} m",
                    parameter=name,
                    value=value,
                    allowed=f"a length 0 < length <= {MAX_SECTION:g} m",
                )
        densities = {"every body": self.density, **self.density_overrides}
        for name, value in densities.items():
            if not (np.isfinite(value) and 0 < value <= MAX_DENSITY):
                raise ParameterError(  # the message as written (its CLI text is tested)
                    f"density of {name} is {value!r} kg/m^3; allowed: 0 < density"
                    f" <= {MAX_DENSITY:g}",
                    parameter="density" if name == "every body" else "density_overrides",
                    value=value,
                    element=None if name == "every body" else name,
                )

    def density_of(self, link: str) -> float:
        """Density of one link [kg/m³]."""
        return float(self.density_overrides.get(link, self.density))


@dataclass(frozen=True)
class ImuSlot:
    """Where an IMU is mounted.

    Attributes:
        name: slot (and URDF link / Pinocchio frame) name, e.g. ``imu_link3_a``
        parent: parent link name, or ``None`` for the slot of an empty module
        T_parent_imu: pose of the IMU in its parent frame (4 × 4)
    """

    name: str
    parent: str | None
    T_parent_imu: Array


def link_name(module: int) -> str:
    """Link name of a module (table row, 1-based)."""
    return f"link{module}"


def imu_slot_names(modules: range | tuple[int, ...] = range(1, 7)) -> tuple[str, ...]:
    """IMU slot names in record order: base, tool, then A and B of each module."""
    names = ["imu_base", "imu_tool"]
    for module in modules:
        names += [f"imu_link{module}_a", f"imu_link{module}_b"]
    return tuple(names)


def imu_slot_links(modules: range | tuple[int, ...] = range(1, 7)) -> tuple[str, ...]:
    """The link of each IMU slot, in the order of :func:`imu_slot_names`."""
    return (BASE_FRAME, TOOL_FRAME, *(link_name(m) for m in modules for _ in "ab"))


def _frame_along(direction: Array, origin: Array) -> Array:
    """A frame at ``origin`` whose x axis is ``direction`` and whose z is closest to z."""
    length = float(np.linalg.norm(direction))
    x = direction / length if length > _SEGMENT_EPS else np.array([1.0, 0.0, 0.0])
    reference = np.array([0.0, 0.0, 1.0]) if abs(x[2]) < 0.9 else np.array([0.0, -1.0, 0.0])
    z = reference - (reference @ x) * x
    z /= np.linalg.norm(z)
    y = (z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0])
    T = np.eye(4)
    T[:3, 0], T[:3, 1], T[:3, 2], T[:3, 3] = x, y, z, origin
    return T


def default_imu_slots(
    chain: KinematicChain, dims: BodyDimensions | None = None
) -> tuple[ImuSlot, ...]:
    """Default IMU mounts: base and tool tip at their frame origins, two per link.

    On link i, slot A sits at the middle of the link segment and slot B at 90 % of it, on
    opposite faces of the link box (offset by ± half the link height along the side normal), so
    the two never share an axis; both keep the post-joint frame's orientation. An Aaria chain
    always has 14 slots; slots of empty modules have no parent.

    Args:
        chain: the kinematic chain
        dims: body dimensions (for the link height)

    Returns:
        Slots in record order (base, tool, link A/B in module order).
    """
    dims = dims or BodyDimensions()
    modules = range(1, 7) if chain.convention == "aaria" else range(1, len(chain.joints) + 1)
    names = imu_slot_names(modules)
    slots = [ImuSlot(names[0], BASE_FRAME, np.eye(4)), ImuSlot(names[1], TOOL_FRAME, np.eye(4))]
    by_module = {joint.module: joint for joint in chain.joints}
    for index, module in enumerate(modules):
        name_a, name_b = names[2 + 2 * index], names[3 + 2 * index]
        joint = by_module.get(module)
        if joint is None:
            slots += [ImuSlot(name_a, None, np.eye(4)), ImuSlot(name_b, None, np.eye(4))]
            continue
        side = _frame_along(joint.link_end, np.zeros(3))[:3, 2] * dims.link_height / 2.0
        slots.append(
            ImuSlot(name_a, link_name(module), translation(*(0.5 * joint.link_end + side)))
        )
        slots.append(
            ImuSlot(
                name_b, link_name(module), translation(*(_IMU_B_FRACTION * joint.link_end - side))
            )
        )
    return tuple(slots)


def _link_parts(chain: KinematicChain, dims: BodyDimensions) -> dict[str, list[Part]]:
    parts: dict[str, list[Part]] = {"dh0": []}
    parent = "dh0"
    T_parent_prev_end = np.eye(4)
    for joint in chain.joints:
        name = link_name(joint.module)
        rho = dims.density_of(name)
        own: list[Part] = []
        T_parent_joint = T_parent_prev_end @ joint.T_prev_joint
        if joint.kind == "revolute":
            own.append(
                Part(
                    "cylinder",
                    (dims.housing_radius, dims.housing_length),
                    np.eye(4),
                    rho,
                    "housing",
                )
            )
        else:
            own.append(
                Part(
                    "box",
                    (dims.link_width, dims.link_height, dims.link_width),
                    np.eye(4),
                    rho,
                    "slider",
                )
            )
            rail_length = joint.upper - joint.lower
            if rail_length > _SEGMENT_EPS:
                parts[parent].append(
                    Part(
                        "cylinder",
                        (dims.rail_radius, rail_length),
                        T_parent_joint @ translation(z=(joint.upper + joint.lower) / 2),
                        dims.density_of(parent),
                        "rail",
                    )
                )
        length = float(np.linalg.norm(joint.link_end))
        if length > _SEGMENT_EPS:
            own.append(
                Part(
                    "box",
                    (length, dims.link_width, dims.link_height),
                    _frame_along(joint.link_end, joint.link_end / 2.0),
                    rho,
                    "link",
                )
            )
        parts[name] = own
        parent, T_parent_prev_end = name, joint.T_post_end
    if chain.tool_length > _SEGMENT_EPS:
        parts["tool"] = [
            Part(
                "box",
                (chain.tool_length, dims.link_width, dims.link_height),
                translation(x=chain.tool_length / 2.0),
                dims.density_of("tool"),
                "tool",
            )
        ]
    else:
        parts["tool"] = []
    return parts


def describe_chain(
    chain: KinematicChain,
    dims: BodyDimensions | None = None,
    name: str = "aaria_arm",
    imu_slots: tuple[ImuSlot, ...] | None = None,
) -> RobotDescription:
    """Links and joints of the robot built on a chain, on a fixed base.

    Args:
        chain: the kinematic chain
        dims: body dimensions and densities (defaults: :class:`BodyDimensions`)
        name: robot name
        imu_slots: IMU mounts (defaults: :func:`default_imu_slots`)

    Returns:
        The robot description, ready for :func:`~aaria_pin.core.urdf_emitter.emit_urdf`.
    """
    dims = dims or BodyDimensions()
    slots = imu_slots if imu_slots is not None else default_imu_slots(chain, dims)
    parts = _link_parts(chain, dims)
    links = [LinkDescription(BASE_FRAME), LinkDescription("dh0", tuple(parts["dh0"]))]
    joints = [JointDescription("dh0_joint", "fixed", BASE_FRAME, "dh0", chain.T_base_entry)]
    parent, T_parent_prev_end = "dh0", np.eye(4)
    for joint in chain.joints:
        child = link_name(joint.module)
        links.append(LinkDescription(child, tuple(parts[child])))
        joints.append(
            JointDescription(
                f"joint{joint.module}",
                joint.kind,
                parent,
                child,
                T_parent_prev_end @ joint.T_prev_joint,
                joint.lower,
                joint.upper,
            )
        )
        parent, T_parent_prev_end = child, joint.T_post_end
    links += [LinkDescription("tool", tuple(parts["tool"])), LinkDescription(TOOL_FRAME)]
    joints += [
        JointDescription("tool_joint", "fixed", parent, "tool", T_parent_prev_end),
        JointDescription(
            "tool_tip_joint", "fixed", "tool", TOOL_FRAME, translation(x=chain.tool_length)
        ),
    ]
    for slot in slots:
        if slot.parent is not None:
            links.append(LinkDescription(slot.name))
            joints.append(
                JointDescription(
                    f"{slot.name}_joint", "fixed", slot.parent, slot.name, slot.T_parent_imu
                )
            )
    comment = (
        f"{chain.convention} DH table, modules {list(chain.modules)}, "
        f"density {dims.density} kg/m^3; generated by aaria_pin"
    )
    return RobotDescription(name, tuple(links), tuple(joints), comment)


@dataclass(frozen=True)
class DHRobot:
    """A robot built from a DH table: its chain, bodies, IMU slots, description and URDF.

    Attributes:
        chain: the kinematic chain
        dims: body dimensions and densities
        imu_slots: IMU mounts in record order
        description: links and joints (fixed base)
    """

    chain: KinematicChain
    dims: BodyDimensions
    imu_slots: tuple[ImuSlot, ...]
    description: RobotDescription

    @cached_property
    def urdf(self) -> str:
        """The URDF text (fixed base), written on first use."""
        return emit_urdf(self.description)

    def model(self, moving_base: bool = False) -> RobotModel:
        """The Pinocchio model, with the IMU slots that have a parent as sensor frames.

        Built straight from the description (see
        :func:`~aaria_pin.core.model.model_from_description`); it equals the model Pinocchio
        parses from :attr:`urdf`.
        """
        from aaria_pin.core.model import model_from_description

        sensors = [slot.name for slot in self.imu_slots if slot.parent is not None]
        return model_from_description(
            self.description,
            moving_base=moving_base,
            base_frame=BASE_FRAME,
            tool_frame=TOOL_FRAME,
            sensor_frames=sensors,
        )


def mount_imu_slots(slots: tuple[ImuSlot, ...], imu_mount: ArrayLike) -> tuple[ImuSlot, ...]:
    """IMU slots moved to the given mounting poses (names and parents kept).

    Args:
        slots: the slots (their names and parents are kept; slots without a parent stay)
        imu_mount: one 4 × 4 pose per slot, in its parent frame

    Raises:
        ParameterError: wrong shape, non-finite values, or a pose that is not rigid.
    """
    poses = np.asarray(imu_mount, dtype=float)
    expected = (len(slots), 4, 4)
    if poses.shape != expected:
        raise ParameterError(
            f"imu_mount has shape {poses.shape}; allowed: {expected}",
            parameter="imu_mount",
            value=poses.shape,
            allowed=str(expected),
        )
    if not np.all(np.isfinite(poses)):
        raise ParameterError(
            "imu_mount holds NaN or inf; allowed: finite poses",
            parameter="imu_mount",
            value=poses,
            allowed="finite poses",
        )
    moved = []
    for slot, pose in zip(slots, poses, strict=True):
        if slot.parent is None:
            moved.append(slot)
            continue
        R = pose[:3, :3]
        rigid = (
            np.allclose(R.T @ R, np.eye(3), atol=1e-9)
            and np.linalg.det(R) > 0
            and np.allclose(pose[3], [0, 0, 0, 1])
        )
        if not rigid:
            raise ParameterError(
                f"imu_mount of {slot.name} is not a rigid transform; allowed: [R p; 0 0 0 1]"
                " with R a rotation",
                parameter="imu_mount",
                value=pose,
                allowed="[R p; 0 0 0 1] with R a rotation",
                element=slot.name,
            )
        moved.append(ImuSlot(slot.name, slot.parent, pose.copy()))
    return tuple(moved)


@checked
def build_dh_robot(
    table: ArrayLike,
    convention: Convention = "aaria",
    dims: BodyDimensions | None = None,
    name: str = "aaria_arm",
    imu_slots: tuple[ImuSlot, ...] | None = None,
    mass_properties: Mapping[str, Inertia] | None = None,
    imu_mount: ArrayLike | None = None,
) -> DHRobot:
    """Validate a table and build its robot.

    Args:
        table: the DH table (8 × 5 Aaria, n × 5 standard or modified)
        convention: ``"aaria"``, ``"standard"`` or ``"modified"``
        dims: body dimensions and densities
        name: robot name in the URDF
        imu_slots: IMU mounts (defaults: :func:`default_imu_slots`)
        mass_properties: measured mass properties by link name (``"link2"``, ``"base"``,
            ``"tool"``), replacing those of the link's solids; a ``"tool"`` entry of zero mass
            removes the tool's
        imu_mount: one 4 × 4 mounting pose per IMU slot, replacing the slots' poses (see
            :func:`mount_imu_slots`)

    Returns:
        The robot.
    """
    chain = chain_from_table(table, convention)
    dims = dims or BodyDimensions()
    slots = imu_slots if imu_slots is not None else default_imu_slots(chain, dims)
    if imu_mount is not None:
        slots = mount_imu_slots(slots, imu_mount)
    description = describe_chain(chain, dims, name, slots)
    if mass_properties:
        unknown = sorted(set(mass_properties) - {link.name for link in description.links})
        if unknown:
            raise ParameterError(
                f"mass properties for {unknown[0]!r}: no such link",
                parameter="mass_properties",
                value=unknown[0],
                allowed="a link of the robot ("
                + ", ".join(link.name for link in description.links)
                + ")",
            )
        links = tuple(
            replace(link, mass_properties=mass_properties[link.name])
            if link.name in mass_properties
            else link
            for link in description.links
        )
        description = replace(description, links=links)
    return DHRobot(chain, dims, slots, description)
