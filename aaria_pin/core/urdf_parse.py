"""The one URDF parser: a URDF document read once into a checked tree of dataclasses.

:func:`parse_urdf` reads the XML (ElementTree) into a :class:`UrdfDocument`: its links with
their inertials, visual and collision shapes (boxes, cylinders, spheres, meshes; origins and
colours), its joints with their origins, axes, limits and mimic relations, its named materials
and every mesh file it names. The result is cached per text, so the URDF check
(:mod:`aaria_pin.core.urdf_check`), the MJCF export (:mod:`aaria_pin.core.export`), the viewer's
visuals and the record model all read one parse.

It also refuses what describes no physical robot, naming the element at fault (Pinocchio's
parser, urdfdom, accepts a negative mass or reports a bad vector in lines of C++ output that
name no element): malformed XML, missing or duplicate names, unsupported joint types, links
that do not form one tree, a negative mass, an inertia that is not positive semi-definite, bad
limits, axes, mimic leaders, and numbers urdfdom would not read.

ElementTree rather than yourdfpy: these checks need each attribute's raw text (urdfdom's number
rules, the element's name in the message), which yourdfpy does not keep (it reads leniently and
fills defaults); ElementTree is the standard library (no import cost for ``aaria --help``) and
gives every number exactly as ``float`` reads the text.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from functools import lru_cache

import numpy as np

from aaria_pin.core.urdf_tree import (
    JOINT_TYPES,
    UrdfDocument,
    UrdfGeometry,
    UrdfInertial,
    UrdfJoint,
    UrdfLink,
    UrdfOrigin,
    UrdfShape,
    Vector3,
)
from aaria_pin.errors import UrdfError

__all__ = ["parse_urdf"]

_INERTIA_FLOOR = 1e-12
"""Negative principal moments smaller than this [kg·m²] are round-off, whatever the scale."""
_INERTIA_TOLERANCE = 1e-6
"""Largest negative principal moment tolerated, relative to the largest one (round-off).

Zero principal moments are accepted: real URDFs use point masses and massless frames, and
Pinocchio handles them; a clearly negative one describes no physical body and is refused."""
_DECIMAL = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")
"""A finite number as urdfdom reads one (no ``inf``, ``nan``, ``1_0`` or hexadecimal)."""
_GEOMETRY_NUMBERS = {"box": (("size", 3),), "mesh": (("scale", 3),)} | {
    shape: (("radius", 1), ("length", 1)) for shape in ("cylinder", "sphere", "capsule")
}
"""Geometry attributes checked as numbers: name and how many numbers."""
_REQUIRED = {
    "box": ("size",),
    "cylinder": ("radius", "length"),
    "sphere": ("radius",),
    "mesh": ("filename",),
}
"""The attributes urdfdom requires of each shape."""


def _error(message: str) -> UrdfError:
    return UrdfError(message, parameter="urdf")


def _float(element: ET.Element, key: str, what: str, default: float | None = None) -> float:
    text = element.get(key)
    if text is None:
        if default is None:
            raise _error(f"{what}: no '{key}' attribute; allowed: a number")
        return default
    try:
        value = float(text)
    except ValueError:
        raise _error(f"{what}: {key}={text!r} is not a number") from None
    if not np.isfinite(value):
        raise _error(f"{what}: {key}={text!r}; allowed: a finite number")
    return value


def _numbers(element: ET.Element, key: str, what: str, count: int) -> tuple[float, ...] | None:
    """An attribute of ``count`` (1 or 3) finite numbers as urdfdom reads them; None if absent.

    Pinocchio's URDF parser (urdfdom) reports a bad vector in several lines of C++ output that
    name no element; this names it: ``link 'forearm' <origin xyz> is '0 0'``.
    """
    text = element.get(key)
    if text is None:
        return None
    numbers = [part for part in text.split(" ") if part]  # urdfdom splits at spaces only
    readable = all(_DECIMAL.fullmatch(part) for part in numbers)
    if len(numbers) != count or not readable or not all(np.isfinite(list(map(float, numbers)))):
        allowed = "three finite numbers" if count == 3 else "a finite number"
        raise _error(f"{what} is {text!r}; allowed: {allowed}")
    return tuple(float(part) for part in numbers)


def _vector(element: ET.Element, key: str, what: str, default: Vector3) -> Vector3:
    values = _numbers(element, key, what, 3)
    return default if values is None else (values[0], values[1], values[2])


def _origin(owner: ET.Element, what: str) -> UrdfOrigin:
    """The checked ``<origin xyz rpy>`` of an element (identity without one)."""
    origin = owner.find("origin")
    if origin is None:
        return UrdfOrigin()
    zero = (0.0, 0.0, 0.0)
    xyz = _vector(origin, "xyz", f"{what} <origin xyz>", zero)
    return UrdfOrigin(xyz, _vector(origin, "rpy", f"{what} <origin rpy>", zero))


def _rgba(colour: ET.Element | None) -> tuple[float, ...] | None:
    text = None if colour is None else colour.get("rgba")
    if not text:
        return None
    try:
        return tuple(float(v) for v in text.split())
    except ValueError:
        raise _error(f"<color rgba> is {text!r}; allowed: four numbers in [0, 1]") from None


def _geometry(owner: ET.Element, what: str, whole: bool = True) -> UrdfGeometry | None:
    """The first shape of a part's ``<geometry>``, its numbers checked (all shapes' are).

    With ``whole`` (a link's part, which urdfdom reads; a joint's are checked, then ignored), a
    part without a ``<geometry>`` shape, or a shape without an attribute urdfdom requires
    (:data:`_REQUIRED`), is refused: urdfdom prints its complaint and drops the part.
    """
    shapes = owner.findall("geometry/*")
    for shape in shapes:
        for key in _REQUIRED.get(shape.tag, ()) if whole else ():
            if shape.get(key) is None:
                raise _error(f"{what} <{shape.tag}> has no '{key}' attribute; allowed: a {key}")
        for key, count in _GEOMETRY_NUMBERS.get(shape.tag, ()):
            _numbers(shape, key, f"{what} <{shape.tag} {key}>", count)
    if not whole:
        return None
    if not shapes:
        raise _error(
            f"{what} has no <geometry> shape; allowed: a <geometry> of a box, cylinder, sphere"
            " or mesh"
        )
    shape = shapes[0]
    one = f"{what} <{shape.tag}"
    radius = _numbers(shape, "radius", f"{one} radius>", 1) if shape.tag != "box" else None
    length = _numbers(shape, "length", f"{one} length>", 1) if shape.tag != "box" else None
    return UrdfGeometry(
        shape.tag,
        size=_vector(shape, "size", f"{one} size>", (0.0, 0.0, 0.0)),
        radius=0.0 if radius is None else radius[0],
        length=0.0 if length is None else length[0],
        filename=shape.get("filename", ""),
        scale=_vector(shape, "scale", f"{one} scale>", (1.0, 1.0, 1.0)),
    )


def _shape(part: ET.Element, what: str) -> UrdfShape:
    material = part.find("material")
    return UrdfShape(
        _geometry(part, what),
        _origin(part, what),
        None if material is None else material.get("name", ""),
        None if material is None else _rgba(material.find("color")),
    )


def _inertial(link: ET.Element, what: str) -> UrdfInertial | None:
    inertial = link.find("inertial")
    if inertial is None:
        return None
    origin = _origin(inertial, f"{what} <inertial>")
    mass_element = inertial.find("mass")
    mass = 0.0 if mass_element is None else _float(mass_element, "value", f"{what} <mass>")
    if mass < 0:
        raise _error(f"{what}: mass {mass:g} kg; allowed: >= 0")
    element = inertial.find("inertia")
    keys = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
    if element is None:
        return UrdfInertial(origin, mass, (0.0, 0.0, 0.0, 0.0, 0.0, 0.0))
    ixx, ixy, ixz, iyy, iyz, izz = (_float(element, k, f"{what} <inertia>", 0.0) for k in keys)
    result = UrdfInertial(origin, mass, (ixx, ixy, ixz, iyy, iyz, izz))
    moments = np.linalg.eigvalsh(result.matrix())
    scale = max(float(np.abs(moments).max()), 1e-300)
    if moments[0] < -max(_INERTIA_TOLERANCE * scale, _INERTIA_FLOOR):
        raise _error(
            f"{what}: inertia [ixx ixy ixz iyy iyz izz] = {[ixx, ixy, ixz, iyy, iyz, izz]} is "
            f"not positive definite (principal moments {np.round(moments, 9).tolist()} kg*m^2); "
            "allowed: a symmetric matrix without negative principal moments"
        )
    return result


def _link(element: ET.Element, name: str) -> UrdfLink:
    what = f"link {name!r}"
    _origin(element, what)  # checked, not used: a link has no pose of its own
    inertial = _inertial(element, what)
    return UrdfLink(
        name,
        inertial,
        tuple(_shape(part, f"{what} <visual>") for part in element.findall("visual")),
        tuple(_shape(part, f"{what} <collision>") for part in element.findall("collision")),
    )


def _limits(element: ET.Element, kind: str, what: str) -> tuple[float, float, float, float]:
    """(lower, upper, velocity, effort) of a joint's ``<limit>``."""
    lower, upper, velocity, effort = -np.inf, np.inf, np.inf, np.inf
    limit = element.find("limit")
    if kind in ("revolute", "prismatic"):
        if limit is None:
            raise _error(f"{what}: a {kind} joint needs <limit lower upper effort velocity>")
        lower = _float(limit, "lower", f"{what} <limit>", 0.0)
        upper = _float(limit, "upper", f"{what} <limit>", 0.0)
        if lower > upper:
            raise _error(
                f"{what}: limit lower {lower:g} > upper {upper:g}; allowed: lower <= upper"
            )
    if limit is not None and kind != "fixed":
        velocity = _float(limit, "velocity", f"{what} <limit>", np.inf)
        if velocity < 0:
            raise _error(f"{what}: velocity limit {velocity:g}; allowed: >= 0")
        velocity = velocity or np.inf  # 0 is how many URDFs say "not given"
        effort = abs(_float(limit, "effort", f"{what} <limit>", np.inf)) or np.inf
    return lower, upper, velocity, effort


def _axis(element: ET.Element, kind: str, what: str) -> Vector3:
    axis = element.find("axis")
    if axis is None or kind == "fixed":
        return (1.0, 0.0, 0.0)
    values = (axis.get("xyz") or "1 0 0").split()
    try:
        vector = np.array([float(v) for v in values])
    except ValueError:
        raise _error(f"{what}: axis xyz={axis.get('xyz')!r} is not three numbers") from None
    if vector.shape != (3,) or not np.all(np.isfinite(vector)) or not np.any(vector):
        raise _error(f"{what}: axis xyz={axis.get('xyz')!r}; allowed: a non-zero 3-vector")
    return (float(vector[0]), float(vector[1]), float(vector[2]))


def _joint(element: ET.Element, links: set[str]) -> UrdfJoint:
    name = element.get("name")
    if not name:
        raise _error("a <joint> has no name; allowed: a non-empty name attribute")
    what = f"joint {name!r}"
    origin = _origin(element, what)
    for tag in ("inertial", "visual", "collision"):  # checked as a link's parts are
        for part in element.findall(tag):
            _origin(part, f"{what} <{tag}>")
            _geometry(part, f"{what} <{tag}>", whole=False)
    kind = element.get("type", "")
    if kind not in JOINT_TYPES:
        raise _error(f"{what}: type {kind!r} is not supported; allowed: {', '.join(JOINT_TYPES)}")
    ends = {}
    for end in ("parent", "child"):
        end_element = element.find(end)
        link = None if end_element is None else end_element.get("link")
        if not link:
            raise _error(f"{what}: no <{end} link=...>; a joint needs a parent and a child")
        if link not in links:
            raise _error(f"{what}: {end} link {link!r} is not a link of the robot")
        ends[end] = link
    lower, upper, velocity, effort = _limits(element, kind, what)
    axis = _axis(element, kind, what)
    mimic = None
    mimic_element = element.find("mimic")
    if mimic_element is not None and kind != "fixed":
        leader = mimic_element.get("joint")
        if not leader:
            raise _error(f"{what}: <mimic> without a joint attribute")
        mimic = (
            leader,
            _float(mimic_element, "multiplier", f"{what} <mimic>", 1.0),
            _float(mimic_element, "offset", f"{what} <mimic>", 0.0),
        )
    parent, child = ends["parent"], ends["child"]
    return UrdfJoint(name, kind, parent, child, lower, upper, velocity, mimic, effort, origin, axis)


def _check_mimics(joints: list[UrdfJoint]) -> None:
    by_name = {joint.name: joint for joint in joints}
    for joint in joints:
        if joint.mimic is None:
            continue
        leader = by_name.get(joint.mimic[0])
        if leader is None:
            raise _error(f"joint {joint.name!r}: mimics unknown joint {joint.mimic[0]!r}")
        if leader is joint or leader.mimic is not None or leader.kind == "fixed":
            raise _error(
                f"joint {joint.name!r}: mimics {leader.name!r}, which is itself, a mimic joint or "
                "fixed; allowed: a leader that moves on its own"
            )
        if (leader.kind == "prismatic") != (joint.kind == "prismatic"):
            raise _error(
                f"joint {joint.name!r} ({joint.kind}) mimics {leader.name!r} ({leader.kind}); "
                "allowed: a leader of the same kind (both prismatic or both revolute)"
            )


def _root(links: list[str], joints: list[UrdfJoint]) -> str:
    """The one root link of a tree that reaches every link."""
    children = {joint.child for joint in joints}
    roots = [link for link in links if link not in children]
    if len(roots) != 1:
        raise _error(
            f"URDF has {len(roots)} root links {roots[:5]}; allowed: exactly one link that is "
            "no joint's child (the joints must form a tree)"
        )
    below: dict[str, list[str]] = {}
    for joint in joints:
        below.setdefault(joint.parent, []).append(joint.child)
    reached, stack = {roots[0]}, [roots[0]]
    while stack:
        for child in below.get(stack.pop(), []):
            reached.add(child)
            stack.append(child)
    if len(reached) != len(links):
        loose = [link for link in links if link not in reached]
        raise _error(f"links {loose[:5]} are not connected to root link {roots[0]!r}")
    return roots[0]


@lru_cache(maxsize=32)
def parse_urdf(text: str) -> UrdfDocument:
    """Parse and check a URDF document (cached per text).

    Args:
        text: the URDF XML

    Returns:
        The document's tree.

    Raises:
        UrdfError: malformed XML (with line and column), no ``<robot>`` root, a link or joint
            without a name or with a duplicate one, a joint of an unsupported type or whose
            parent or child is missing or unknown, a link with two parent joints, not exactly
            one root link, a negative mass, an inertia that is not positive definite, a bad
            limit, axis or mimic, an ``<origin xyz|rpy>`` that is not three finite numbers (the
            link or joint, and the part, named), a box size or mesh scale that is not three
            numbers.
    """
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        line, column = exc.position
        raise _error(f"URDF is not well-formed XML: line {line}, column {column + 1}") from None
    if root.tag != "robot":
        raise _error(f"URDF root element is <{root.tag}>; allowed: <robot>")
    links: list[UrdfLink] = []
    for element in root.findall("link"):
        name = element.get("name")
        if not name:
            raise _error("a <link> has no name; allowed: a non-empty name attribute")
        if any(link.name == name for link in links):
            raise _error(f"link {name!r} is defined twice")
        links.append(_link(element, name))
    if not links:
        raise _error("URDF has no <link>; a robot needs at least one")
    names = [link.name for link in links]
    joints: list[UrdfJoint] = []
    parent_of: dict[str, str] = {}
    for element in root.findall("joint"):
        joint = _joint(element, set(names))
        if any(j.name == joint.name for j in joints):
            raise _error(f"joint {joint.name!r} is defined twice")
        if joint.child in parent_of:
            raise _error(
                f"joint {joint.name!r}: link {joint.child!r} already has parent joint "
                f"{parent_of[joint.child]!r}; a link has at most one parent"
            )
        parent_of[joint.child] = joint.name
        joints.append(joint)
    _check_mimics(joints)
    materials: dict[str, tuple[float, ...]] = {}
    for material in root.iter("material"):
        colour = material.find("color")
        if colour is not None:
            rgba = _rgba(colour)
            materials.setdefault(material.get("name", ""), rgba or (0.7, 0.7, 0.7, 1.0))
    return UrdfDocument(
        root.get("name", "robot"),
        _root(names, joints),
        tuple(links),
        tuple(joints),
        tuple(materials.items()),
        tuple(mesh.get("filename", "") for mesh in root.iter("mesh")),
    )
