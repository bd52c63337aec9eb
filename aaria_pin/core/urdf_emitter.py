"""The one URDF emitter: a robot description written as URDF by filling ``urdf_templates/``.

Origins are written as ``xyz`` and ``rpy`` (``R = Rz·Ry·Rx``) derived from the whole rotation
matrix, so any transform, not only a single axis rotation, survives the trip. Numbers are
written in their shortest exact form (:func:`exact_number`, used by the MJCF writer too).
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from functools import cache
from importlib import resources
from pathlib import Path
from string import Template
from xml.sax.saxutils import quoteattr

import numpy as np

from aaria_pin.core.arguments import checked
from aaria_pin.core.se3 import Array, rpy_from_matrix
from aaria_pin.core.urdf import (
    JOINT_KINDS,
    Box,
    Cylinder,
    Geometry,
    JointDescription,
    LinkDescription,
    Material,
    RobotDescription,
    Shape,
    Sphere,
)
from aaria_pin.errors import ModelError

__all__ = ["emit_urdf", "exact_number", "exact_numbers", "template_dir"]

_UNIT_TOLERANCE = 1e-9


def template_dir() -> Path:
    """Folder of the URDF fragments: inside the installed package, else the checkout's."""
    packaged = Path(str(resources.files("aaria_pin"))) / "urdf_templates"
    if packaged.is_dir():
        return packaged
    return Path(__file__).resolve().parents[2] / "urdf_templates"


@cache
def _template(name: str) -> Template:
    return Template((template_dir() / name).read_text(encoding="utf-8"))


def exact_number(value: float) -> str:
    """A number in its shortest exact form (``repr``; -0.0 written as 0.0)."""
    return repr(float(value) + 0.0)  # shortest exact form; + 0.0 turns -0.0 into 0.0


def exact_numbers(values: Sequence[float] | Array) -> str:
    """Numbers in their shortest exact form, separated by spaces."""
    return " ".join(exact_number(v) for v in values)


def _whole_or_num(value: float) -> str:
    """A whole number without decimals (an axis "0 0 1"), else the shortest exact form."""
    value = float(value) + 0.0
    return str(int(value)) if value.is_integer() else repr(value)


def _colour(value: float) -> str:
    """A colour component: whole as "1", else at least two decimals ("0.30"), exactly."""
    value = float(value) + 0.0
    if value.is_integer():
        return str(int(value))
    decimals = len(np.format_float_positional(value, trim="-").partition(".")[2])
    return f"{value:.{max(2, decimals)}f}"


def _origin(T: Array) -> dict[str, str]:
    return {"xyz": exact_numbers(T[:3, 3]), "rpy": exact_numbers(rpy_from_matrix(T[:3, :3]))}


def _geometry(geometry: Geometry) -> str:
    if isinstance(geometry, Box):
        return f'<box size="{exact_numbers(geometry.size)}"/>'
    if isinstance(geometry, Cylinder):
        radius, length = exact_number(geometry.radius), exact_number(geometry.length)
        return f'<cylinder radius="{radius}" length="{length}"/>'
    if isinstance(geometry, Sphere):
        return f'<sphere radius="{exact_number(geometry.radius)}"/>'
    scale = ""
    if tuple(geometry.scale) != (1.0, 1.0, 1.0):
        scale = f' scale="{exact_numbers(geometry.scale)}"'
    return f"<mesh filename={quoteattr(geometry.filename)}{scale}/>"


def _shape_xml(shape: Shape) -> str:
    fields = {"name": shape.name, "geometry": _geometry(shape.geometry)}
    fields |= _origin(shape.T_link_shape)
    text = ""
    if shape.visual:
        material = ""
        if shape.material is not None:
            material = _template("visual_material.xml").substitute(material=shape.material.name)
        text += _template("visual.xml").substitute(fields, material=material)
    if shape.collision:
        text += _template("collision.xml").substitute(fields)
    return text


def _link_xml(link: LinkDescription) -> str:
    body = ""
    inertia = link.inertia()
    if inertia is not None:
        I = inertia.inertia_com
        body += _template("inertial.xml").substitute(
            xyz=exact_numbers(inertia.com),
            mass=exact_number(inertia.mass),
            ixx=exact_number(I[0, 0]),
            ixy=exact_number(I[0, 1]),
            ixz=exact_number(I[0, 2]),
            iyy=exact_number(I[1, 1]),
            iyz=exact_number(I[1, 2]),
            izz=exact_number(I[2, 2]),
        )
    body += "".join(_shape_xml(shape) for shape in link.all_shapes())
    return _template("link.xml").substitute(name=link.name, body=body)


def _joint_xml(joint: JointDescription) -> str:
    motion = ""
    if joint.kind != "fixed":
        limits = ""
        if joint.kind != "continuous":
            limits = f' lower="{exact_number(joint.lower)}" upper="{exact_number(joint.upper)}"'
        motion = _template("joint_motion.xml").substitute(
            axis=" ".join(_whole_or_num(v) for v in joint.axis),
            limits=limits,
            effort=exact_number(joint.effort),
            velocity=exact_number(joint.velocity),
        )
    return _template("joint.xml").substitute(
        name=joint.name,
        kind=joint.kind,
        parent=joint.parent,
        child=joint.child,
        motion=motion,
        **_origin(joint.T_parent_child),
    )


def _materials(description: RobotDescription) -> tuple[Material, ...]:
    """The declared materials, then the shapes' others, each once by name.

    Raises:
        ModelError: two materials of the same name with different colours.
    """
    used = [
        shape.material
        for link in description.links
        for shape in link.all_shapes()
        if shape.visual and shape.material is not None
    ]
    declared: dict[str, Material] = {}
    for material in (*description.materials, *used):
        known = declared.setdefault(material.name, material)
        if tuple(known.rgba) != tuple(material.rgba):
            raise ModelError(
                f"material {material.name!r} has colours {known.rgba} and {material.rgba};"
                " allowed: one colour per material name",
                parameter="description",
            )
    return tuple(declared.values())


def _material_xml(material: Material) -> str:
    return _template("material.xml").substitute(
        name=material.name, rgba=" ".join(_colour(v) for v in material.rgba)
    )


def _check_tree(description: RobotDescription) -> None:
    names = [link.name for link in description.links]
    if not names:
        raise ModelError(
            f"robot {description.name!r} has no link; allowed: at least a root link",
            parameter="description",
        )
    if len(set(names)) != len(names):
        raise ModelError(
            f"robot {description.name!r}: duplicate link names in {names}", parameter="description"
        )
    children = [joint.child for joint in description.joints]
    if len(set(children)) != len(children):
        raise ModelError(
            f"robot {description.name!r}: a link is the child of two joints in {children}",
            parameter="description",
        )
    joint_names = [joint.name for joint in description.joints]
    if len(set(joint_names)) != len(joint_names):
        raise ModelError(
            f"robot {description.name!r}: duplicate joint names in {joint_names}",
            parameter="description",
        )
    known = set(names)
    for joint in description.joints:
        for end in (joint.parent, joint.child):
            if end not in known:
                raise ModelError(
                    f"joint {joint.name!r}: link {end!r} is not in the robot",
                    parameter="description",
                )
    roots = known - set(children)
    if roots != {names[0]}:
        raise ModelError(
            f"robot {description.name!r}: expected one root {names[0]!r}, got {sorted(roots)}",
            parameter="description",
        )


def _check_joints(description: RobotDescription) -> None:
    for joint in description.joints:
        if joint.kind not in JOINT_KINDS:
            raise ModelError(
                f"joint {joint.name!r} kind is {joint.kind!r}; allowed: {', '.join(JOINT_KINDS)}",
                parameter="description",
            )
        T = np.asarray(joint.T_parent_child, dtype=float)
        if T.shape != (4, 4) or not np.all(np.isfinite(T)):
            raise ModelError(
                f"joint {joint.name!r} T_parent_child is not a finite 4 × 4 transform;"
                " allowed: [R p; 0 0 0 1]",
                parameter="description",
            )
        if joint.kind == "fixed":
            continue
        axis = np.asarray(joint.axis, dtype=float)
        if axis.shape != (3,) or abs(float(np.linalg.norm(axis)) - 1.0) > _UNIT_TOLERANCE:
            raise ModelError(
                f"joint {joint.name!r} axis is {joint.axis}; allowed: a unit vector of 3 numbers",
                parameter="description",
            )
        limits: tuple[float, ...] = (joint.effort, joint.velocity)
        if joint.kind != "continuous":
            limits += (joint.lower, joint.upper)
        if not np.all(np.isfinite(limits)):
            raise ModelError(
                f"joint {joint.name!r} limits are {limits}; allowed: finite numbers",
                parameter="description",
            )
        if joint.kind != "continuous" and joint.lower > joint.upper:
            raise ModelError(
                f"joint {joint.name!r} lower limit is {joint.lower}; allowed: <= upper limit"
                f" {joint.upper}",
                parameter="description",
            )


_XML_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_.-]*")


def _check_names(description: RobotDescription, materials: Sequence[Material]) -> None:
    names = [description.name, *(link.name for link in description.links)]
    names += [joint.name for joint in description.joints]
    names += [material.name for material in materials]
    names += [shape.name for link in description.links for shape in link.all_shapes()]
    for name in names:
        if not _XML_NAME.fullmatch(name):
            raise ModelError(
                f"name {name!r} is not allowed in a URDF; allowed: letters, digits, '_', '.', '-'"
                " (not first)",
                parameter="description",
            )
    for material in materials:
        rgba = np.asarray(material.rgba, dtype=float)
        if rgba.shape != (4,) or not np.all((rgba >= 0.0) & (rgba <= 1.0)):
            raise ModelError(
                f"material {material.name!r} rgba is {material.rgba}; allowed: 4 numbers in [0, 1]",
                parameter="description",
            )


@checked
def emit_urdf(description: RobotDescription) -> str:
    """Write a robot description as URDF text.

    Args:
        description: links and joints; the first link is the root

    Returns:
        The URDF document.

    Raises:
        ModelError: duplicate link or joint names, a joint naming an unknown link, not one root,
            a name that is not an XML name, an unknown joint kind, an axis that is not a unit
            vector, limits that are not finite or a lower limit above the upper, a colour out
            of [0, 1], or one material name with two colours.
    """
    _check_tree(description)
    _check_joints(description)
    materials = _materials(description)
    _check_names(description, materials)
    return _template("robot.urdf").substitute(
        name=description.name,
        comment=description.comment.replace("--", "- -"),
        materials="".join(_material_xml(material) for material in materials),
        links="".join(_link_xml(link) for link in description.links),
        joints="".join(_joint_xml(joint) for joint in description.joints),
    )
