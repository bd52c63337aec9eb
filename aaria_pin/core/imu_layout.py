"""Where the IMUs of a URDF robot sit: the default layout, layout files, model frames.

Default layout (:func:`default_imu_layout`), in this order:

- ``imu_base`` on the base (root) link, at its origin, axes aligned with it;
- ``imu_tool`` on the tool frame, at its origin, axes aligned with it;
- for every moving link, in model order (the child link of each actuated joint, with
  everything fixed to it), two IMUs with the link's axes: ``imu_<link>_a`` at the link's origin
  and ``imu_<link>_b`` at the body's centre of mass. When that centre lies closer than
  ``min_offset`` (default 5 cm) to the joint's axis line (for a revolute joint the line the
  link turns about, for a prismatic joint the line through the origin it slides along),
  ``_b`` moves away from the line, perpendicular to it, until it is ``min_offset`` from it: so
  the two IMUs of a link never share an axis and together see its angular acceleration.

A URDF that carries its IMUs (the URDFs :mod:`aaria_pin.core.urdf` writes of a DH arm) has a
bare frame link (no mass, no shape, no child, on a fixed joint) named as an IMU: that IMU is
the link (:func:`carried_imu_mounts`), mounted where the URDF puts it, and no frame is added for
it; the default layout takes it in place of its own mount of that name.

A layout file (TOML) replaces the default, one ``[[imu]]`` table per IMU in record order::

    [[imu]]
    name = "imu_wrist"           # unique, not already a frame of the robot
    parent = "wrist_3_link"      # a link, joint or frame of the URDF
    xyz = [0.0, 0.0, 0.05]       # position in the parent frame [m] (default zeros)
    rpy = [0.0, 0.0, 1.5708]     # orientation, URDF fixed-axis roll-pitch-yaw [rad] (default zeros)
"""

from __future__ import annotations

import os
import tomllib
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin

from aaria_pin.core.model import frame_index
from aaria_pin.core.record import ImuMount
from aaria_pin.core.se3 import Array
from aaria_pin.core.urdf_tree import UrdfJoint
from aaria_pin.errors import InputFileError, ModelError, ParameterError

__all__ = [
    "DEFAULT_MIN_OFFSET",
    "add_imu_frames",
    "carried_imu_mounts",
    "check_slot_mounts",
    "default_imu_layout",
    "moving_links",
    "read_imu_layout",
]

DEFAULT_MIN_OFFSET = 0.05
"""Smallest distance of a link's second IMU from the joint axis [m]."""


def _rpy_matrix(rpy: Sequence[float]) -> Array:
    roll, pitch, yaw = rpy
    return np.asarray(pin.rpy.rpyToMatrix(roll, pitch, yaw))


def _pose(xyz: Sequence[float], rpy: Sequence[float] = (0.0, 0.0, 0.0)) -> Array:
    T = np.eye(4)
    T[:3, :3] = _rpy_matrix(rpy)
    T[:3, 3] = xyz
    return T


def moving_links(model: pin.Model) -> list[tuple[int, int, str]]:
    """(joint index, frame index, link name) of each actuated joint's child link, model order.

    The child link is the body frame the URDF parser attaches to the joint first.
    """
    links = []
    for joint_id in range(1, model.njoints):
        if model.joints[joint_id].shortname() == "JointModelFreeFlyer":
            continue
        frame_id = next(
            index
            for index, frame in enumerate(model.frames)
            if frame.type == pin.FrameType.BODY and frame.parentJoint == joint_id
        )
        links.append((joint_id, frame_id, model.frames[frame_id].name))
    return links


def _joint_axis(joint: pin.JointModel) -> Array:
    from aaria_pin.core.kinematics import joint_kind

    return joint_kind(joint)[1]


def _offset_from_axis(com: Array, axis: Array, min_offset: float) -> Array:
    """``com`` moved perpendicular to the line through the origin along ``axis``, if needed."""
    axis = axis / np.linalg.norm(axis)
    radial = com - axis * (axis @ com)
    distance = float(np.linalg.norm(radial))
    if distance >= min_offset:
        return com
    if distance > 1e-9:
        direction = radial / distance
    else:  # on the axis: any perpendicular, chosen from the axis least aligned with it
        helper = np.eye(3)[int(np.argmin(np.abs(axis)))]
        direction = np.cross(axis, helper)
        direction /= np.linalg.norm(direction)
    return com - radial + direction * min_offset  # the point on the axis, moved out


def default_imu_layout(
    model: pin.Model,
    base_frame: str,
    tool_frame: str,
    min_offset: float = DEFAULT_MIN_OFFSET,
) -> tuple[ImuMount, ...]:
    """The default IMU layout of a model (see the module docstring).

    Args:
        model: the Pinocchio model built from the URDF
        base_frame: the base (root) link
        tool_frame: the tool frame
        min_offset: smallest distance of a link's second IMU from its joint's axis [m]

    Returns:
        The IMU mounts, in record order.
    """
    mounts = [
        ImuMount("imu_base", base_frame, np.eye(4)),
        ImuMount("imu_tool", tool_frame, np.eye(4)),
    ]
    for joint_id, frame_id, link in moving_links(model):
        frame = model.frames[frame_id]
        T_joint_link = frame.placement.homogeneous
        com_joint = np.asarray(model.inertias[joint_id].lever, dtype=float)
        com_joint = _offset_from_axis(com_joint, _joint_axis(model.joints[joint_id]), min_offset)
        com_link = T_joint_link[:3, :3].T @ (com_joint - T_joint_link[:3, 3])
        mounts.append(ImuMount(f"imu_{link}_a", link, np.eye(4)))
        mounts.append(ImuMount(f"imu_{link}_b", link, _pose(com_link)))
    return tuple(mounts)


def carried_imu_mounts(frame_links: Sequence[UrdfJoint]) -> dict[str, ImuMount]:
    """The IMUs a URDF carries as links: each bare frame link, mounted by its fixed joint.

    Args:
        frame_links: the fixed joints of bare frame links
            (:attr:`~aaria_pin.core.urdf_check.UrdfSummary.frame_links`)

    Returns:
        Link name → its mount (parent link, the joint's origin), document order.
    """
    return {
        joint.child: ImuMount(joint.child, joint.parent, joint.origin.transform())
        for joint in frame_links
    }


_NEW_NAME = "a name that is not a frame of the robot, or an IMU link of the URDF where it is"


def _is_carried(mount: ImuMount, carried: Mapping[str, ImuMount]) -> bool:
    """Whether ``mount`` is the URDF's own IMU link of its name (same parent and pose)."""
    link = carried.get(mount.name)
    return (
        link is not None
        and link.parent == mount.parent
        and np.allclose(link.T_parent_imu, mount.T_parent_imu, rtol=0.0, atol=1e-12)
    )


def check_slot_mounts(
    mounts: Sequence[ImuMount], slots: Sequence[tuple[str, str]], source: str
) -> None:
    """Refuse IMU mounts read from a file that are not a robot's IMU slots.

    A robot with fixed slots (a DH arm) takes only the poses of a file's mounts; each pose is
    in its parent's frame, so mount k must be slot k: the slot's name, on the slot's link (or
    an empty slot, parent ``""``, whose pose is zero). The number of mounts is checked where
    the poses are used.

    Args:
        mounts: the file's mounts, in record order
        slots: (name, parent link) of each of the robot's slots, in record order
        source: the file, as the message names it

    Raises:
        ParameterError: a mount of another name, or on another link (``imu_mount``).
    """
    for number, (mount, (name, parent)) in enumerate(zip(mounts, slots, strict=False), 1):
        if mount.name != name:
            allowed = f"{name} (slot {number} of the robot)"
            element, value = f"IMU {number} of {source}", mount.name
        elif mount.parent not in (parent, ""):
            allowed = f"{parent} (the link of slot {name})"
            element, value = f"parent of {name} in {source}", mount.parent
        else:
            continue
        raise ParameterError(
            f"{element} is {value!r}; allowed: {allowed}",
            parameter="imu_mount",
            value=value,
            allowed=allowed,
            element=element,
        )


def _refused(file: Path, text: str, element: str | None = None) -> InputFileError:
    """The error of layout ``file``: ``"<file>: [<element>: ]<text>"``, ``file`` at fault.

    No ``allowed`` field: the CLI prints the message as written (it names the file).
    """
    where = f"{file}: {element}" if element else str(file)
    return InputFileError(f"{where}: {text}", parameter="file", value=str(file), element=element)


def _vector(entry: dict[str, Any], key: str, file: Path, element: str) -> list[float]:
    value = entry.get(key, [0.0, 0.0, 0.0])
    if (
        not isinstance(value, list)
        or len(value) != 3
        or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
        or not np.all(np.isfinite(value))
    ):
        raise _refused(file, f"{key} = {value!r}; allowed: three finite numbers", element)
    return [float(v) for v in value]


def read_imu_layout(path: str | os.PathLike[str]) -> tuple[ImuMount, ...]:
    """Read an IMU layout file (TOML, see the module docstring).

    Raises:
        InputFileError: missing or malformed file, an entry without a name or parent, a bad
            vector, a duplicate name, or no IMU at all.
    """
    file = Path(path)
    try:
        data = tomllib.loads(file.read_text(encoding="utf-8"))
    except OSError as exc:
        raise _refused(file, f"cannot be read ({exc.strerror})") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise _refused(file, f"not a TOML file ({exc})") from None
    entries = data.get("imu")
    if not isinstance(entries, list) or not entries:
        raise _refused(file, "no [[imu]] tables; allowed: one [[imu]] table per IMU")
    mounts: list[ImuMount] = []
    for number, entry in enumerate(entries, start=1):
        where = f"[[imu]] number {number}"
        if not isinstance(entry, dict):
            raise _refused(file, f"{entry!r} is not a table; allowed: [[imu]] tables", where)
        unknown = set(entry) - {"name", "parent", "xyz", "rpy"}
        if unknown:
            raise _refused(
                file,
                f"unknown key {sorted(unknown)[0]!r}; allowed: name, parent, xyz, rpy",
                where,
            )
        for key in ("name", "parent"):
            if not isinstance(entry.get(key), str) or not entry[key]:
                raise _refused(file, f"no {key}; allowed: a non-empty string", where)
        if any(mount.name == entry["name"] for mount in mounts):
            raise _refused(file, f"name {entry['name']!r} is used twice", where)
        pose = _pose(_vector(entry, "xyz", file, where), _vector(entry, "rpy", file, where))
        mounts.append(ImuMount(entry["name"], entry["parent"], pose))
    return tuple(mounts)


def add_imu_frames(
    model: pin.Model, mounts: Sequence[ImuMount], carried: Mapping[str, ImuMount] | None = None
) -> None:
    """Add one operational frame per IMU to a model, named after the IMU.

    An IMU the URDF carries (in ``carried``, with the same parent and pose) is its link's frame,
    already in the model: no frame is added for it.

    Args:
        model: the model (frames are added to it)
        mounts: the IMUs, in record order
        carried: the IMUs the URDF carries (:func:`carried_imu_mounts`)

    Raises:
        ModelError: a parent frame that is not in the model, or an IMU name that already is
            (but for a carried IMU).
    """
    carried = {} if carried is None else carried
    for mount in mounts:
        if _is_carried(mount, carried):
            continue
        if not model.existFrame(mount.parent):
            raise ModelError(
                f"IMU {mount.name!r}: parent frame {mount.parent!r} is not in model "
                f"{model.name!r}; allowed: a link, joint or frame of the URDF",
                parameter="imu_layout",
                value=mount.parent,
                allowed="a link, joint or frame of the URDF",
                element=f"parent of IMU {mount.name!r}",
            )
        if model.existFrame(mount.name):
            raise ModelError(
                f"IMU name {mount.name!r} is already a frame of the robot; allowed: {_NEW_NAME}",
                parameter="imu_layout",
                value=mount.name,
                allowed=_NEW_NAME,
                element="IMU name",
            )
        parent_id = frame_index(model, mount.parent)
        parent = model.frames[parent_id]
        placement = parent.placement * pin.SE3(mount.T_parent_imu)
        model.addFrame(
            pin.Frame(mount.name, parent.parentJoint, parent_id, placement, pin.FrameType.OP_FRAME)
        )
