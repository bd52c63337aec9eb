"""A small URDF emitter for links whose geometry is a mesh file.

The project's :func:`aaria_pin.core.urdf.emit_urdf` writes box and cylinder shapes and joints about
z only; the pick-and-place arm's parts are meshes and its hand has a joint about y, so it gets
this emitter: one ``<mesh filename=...>`` visual and collision per link, the inertial block from
given mass properties, and joints with any axis. Origins are written with ``rpy`` from the full
rotation (:func:`aaria_pin.core.se3.rpy_from_matrix`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np

from aaria_pin.core.inertia import Inertia
from aaria_pin.core.se3 import Array, rpy_from_matrix
from aaria_pin.errors import ModelError

__all__ = ["MeshJoint", "MeshLink", "emit_mesh_urdf"]


@dataclass(frozen=True)
class MeshLink:
    """A link: its mesh file (or none, for a frame) and mass properties.

    Attributes:
        name: link name
        mesh_file: the mesh's ``filename`` as written in the URDF, or None (massless frame)
        inertia: mass properties in the link frame, or None (massless frame)
        rgba: display colour
    """

    name: str
    mesh_file: str | None = None
    inertia: Inertia | None = None
    rgba: tuple[float, float, float, float] = (0.2, 0.35, 0.85, 1.0)


@dataclass(frozen=True)
class MeshJoint:
    """A joint.

    Attributes:
        name: joint name
        kind: ``"revolute"``, ``"prismatic"`` or ``"fixed"``
        parent: parent link
        child: child link
        T_parent_child: the joint frame in the parent link frame at q = 0 (4 × 4)
        axis: joint axis in the joint frame (unit vector)
        lower: lower limit [rad or m]
        upper: upper limit [rad or m]
        effort: effort limit [N·m or N]
        velocity: velocity limit [rad/s or m/s]
    """

    name: str
    kind: Literal["revolute", "prismatic", "fixed"]
    parent: str
    child: str
    T_parent_child: Array
    axis: tuple[float, float, float] = (0.0, 0.0, 1.0)
    lower: float = 0.0
    upper: float = 0.0
    effort: float = 100.0
    velocity: float = 1.0


def _num(value: float) -> str:
    return repr(float(value) + 0.0)


def _vec(values: Sequence[float] | Array) -> str:
    return " ".join(_num(v) for v in values)


def _origin(T: Array) -> str:
    return f'<origin xyz="{_vec(T[:3, 3])}" rpy="{_vec(rpy_from_matrix(T[:3, :3]))}"/>'


def _link_xml(link: MeshLink) -> str:
    lines = [f'  <link name="{link.name}">']
    if link.inertia is not None:
        I = link.inertia.inertia_com
        lines += [
            "    <inertial>",
            f'      <origin xyz="{_vec(link.inertia.com)}" rpy="0 0 0"/>',
            f'      <mass value="{_num(link.inertia.mass)}"/>',
            f'      <inertia ixx="{_num(I[0, 0])}" ixy="{_num(I[0, 1])}" ixz="{_num(I[0, 2])}"'
            f' iyy="{_num(I[1, 1])}" iyz="{_num(I[1, 2])}" izz="{_num(I[2, 2])}"/>',
            "    </inertial>",
        ]
    if link.mesh_file is not None:
        geometry = f'<geometry><mesh filename="{link.mesh_file}"/></geometry>'
        lines += [
            "    <visual>",
            '      <origin xyz="0 0 0" rpy="0 0 0"/>',
            f"      {geometry}",
            f'      <material name="{link.name}_colour"><color rgba="{_vec(link.rgba)}"/>'
            "</material>",
            "    </visual>",
            "    <collision>",
            '      <origin xyz="0 0 0" rpy="0 0 0"/>',
            f"      {geometry}",
            "    </collision>",
        ]
    lines.append("  </link>")
    return "\n".join(lines) + "\n"


def _joint_xml(joint: MeshJoint) -> str:
    lines = [
        f'  <joint name="{joint.name}" type="{joint.kind}">',
        f'    <parent link="{joint.parent}"/>',
        f'    <child link="{joint.child}"/>',
        f"    {_origin(joint.T_parent_child)}",
    ]
    if joint.kind != "fixed":
        lines += [
            f'    <axis xyz="{_vec(joint.axis)}"/>',
            f'    <limit lower="{_num(joint.lower)}" upper="{_num(joint.upper)}"'
            f' effort="{_num(joint.effort)}" velocity="{_num(joint.velocity)}"/>',
        ]
    lines.append("  </joint>")
    return "\n".join(lines) + "\n"


def emit_mesh_urdf(
    name: str, links: Sequence[MeshLink], joints: Sequence[MeshJoint], comment: str = ""
) -> str:
    """URDF text of a tree of mesh links, rooted at ``links[0]``.

    Args:
        name: robot name
        links: the links, root first
        joints: the joints, each naming links of ``links``
        comment: a comment written at the top

    Returns:
        The URDF document.

    Raises:
        ModelError: duplicate link names, a joint naming an unknown link, a link that is not
            the root and no joint's child, or an axis that is not a unit vector.
    """
    names = [link.name for link in links]
    if len(set(names)) != len(names):
        raise ModelError(f"robot {name!r}: duplicate link names in {names}")
    for joint in joints:
        for end in (joint.parent, joint.child):
            if end not in names:
                raise ModelError(f"joint {joint.name!r}: link {end!r} is not in the robot")
        if abs(float(np.linalg.norm(joint.axis)) - 1.0) > 1e-9:
            raise ModelError(f"joint {joint.name!r}: axis {joint.axis} is not a unit vector")
    roots = set(names) - {joint.child for joint in joints}
    if roots != {names[0]}:
        raise ModelError(f"robot {name!r}: expected one root {names[0]!r}, got {sorted(roots)}")
    text = '<?xml version="1.0"?>\n'
    if comment:
        text += f"<!-- {comment.replace('--', '- -')} -->\n"
    text += f'<robot name="{name}">\n'
    text += "".join(_link_xml(link) for link in links)
    text += "".join(_joint_xml(joint) for joint in joints)
    return text + "</robot>\n"
