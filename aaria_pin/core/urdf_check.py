"""Reading and checking a URDF before it becomes a model: structure, mass properties, meshes.

Pinocchio's URDF parser accepts some documents that describe no physical robot (a negative
mass, an inertia that is not positive definite) and reports others with messages that do not
say which element is at fault. :func:`check_urdf` reads the XML itself and raises a
:class:`~aaria_pin.errors.UrdfError` that names the link or joint, then lists what a simulation
needs: the root link, the joints with their limits and mimic relations, and the meshes, each
resolved to a file (``package://NAME/...`` from the installed packages' ``share`` folders, the
folders above the URDF and ``ROS_PACKAGE_PATH``; relative paths from the URDF's folder).
"""

from __future__ import annotations

import os
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from aaria_pin.errors import UrdfError

__all__ = ["JOINT_TYPES", "UrdfJoint", "UrdfSummary", "check_urdf", "resolve_mesh"]

JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed")
"""URDF joint types a simulation supports (``floating`` and ``planar`` are refused)."""

_INERTIA_FLOOR = 1e-12
"""Negative principal moments smaller than this [kg·m²] are round-off, whatever the scale."""
_INERTIA_TOLERANCE = 1e-6
"""Largest negative principal moment tolerated, relative to the largest one (round-off).

Zero principal moments are accepted: real URDFs use point masses and massless frames, and
Pinocchio handles them; a clearly negative one describes no physical body and is refused."""


@dataclass(frozen=True)
class UrdfJoint:
    """A joint of the URDF.

    Attributes:
        name: joint name
        kind: one of :data:`JOINT_TYPES`
        parent: parent link
        child: child link
        lower: lower position limit [rad or m] (-inf for a continuous joint)
        upper: upper position limit [rad or m] (+inf for a continuous joint)
        velocity: velocity limit [rad/s or m/s] (inf if not given)
        mimic: (leader joint, multiplier, offset) of a mimic joint, else None
        effort: effort limit [N·m or N] (inf if not given or 0)
    """

    name: str
    kind: str
    parent: str
    child: str
    lower: float
    upper: float
    velocity: float
    mimic: tuple[str, float, float] | None
    effort: float = np.inf


@dataclass(frozen=True)
class UrdfSummary:
    """What a simulation needs to know of a checked URDF.

    Attributes:
        name: the robot's name
        root_link: the one link that is no joint's child
        links: link names in document order
        joints: joints in document order
        meshes: mesh file names as written in the URDF
        missing_meshes: those that do not resolve to an existing file
    """

    name: str
    root_link: str
    links: tuple[str, ...]
    joints: tuple[UrdfJoint, ...]
    meshes: tuple[str, ...]
    missing_meshes: tuple[str, ...]

    def joint(self, name: str) -> UrdfJoint:
        """A joint by name (KeyError if absent)."""
        for joint in self.joints:
            if joint.name == name:
                return joint
        raise KeyError(name)


def _float(element: ET.Element, key: str, what: str, default: float | None = None) -> float:
    text = element.get(key)
    if text is None:
        if default is None:
            raise UrdfError(f"{what}: no '{key}' attribute; allowed: a number")
        return default
    try:
        value = float(text)
    except ValueError:
        raise UrdfError(f"{what}: {key}={text!r} is not a number") from None
    if not np.isfinite(value):
        raise UrdfError(f"{what}: {key}={text!r}; allowed: a finite number")
    return value


_DECIMAL = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")
"""A finite number as urdfdom reads one (no ``inf``, ``nan``, ``1_0`` or hexadecimal)."""


def _numbers(element: ET.Element, key: str, what: str, count: int) -> None:
    """Refuse an attribute that is not ``count`` (1 or 3) finite numbers (absent: its default).

    Pinocchio's URDF parser (urdfdom) reports such a vector in several lines of C++ output
    that name no element; this names it: ``link 'forearm' <origin xyz> is '0 0'``.
    """
    text = element.get(key)
    if text is None:
        return
    parts = text.split(" ")  # urdfdom splits at spaces only
    numbers = [part for part in parts if part]
    readable = all(_DECIMAL.fullmatch(part) for part in numbers)
    if len(numbers) != count or not readable or not all(np.isfinite(list(map(float, numbers)))):
        allowed = "three finite numbers" if count == 3 else "a finite number"
        raise UrdfError(f"{what} is {text!r}; allowed: {allowed}")


_GEOMETRY_NUMBERS = {"box": (("size", 3),), "mesh": (("scale", 3),)} | {
    shape: (("radius", 1), ("length", 1)) for shape in ("cylinder", "sphere", "capsule")
}
"""Geometry attributes checked as numbers: name and how many numbers."""


def _check_vectors(owner: ET.Element, what: str) -> None:
    """Check the origins of a link or joint and of its parts, and their geometry's numbers.

    The ``<origin xyz rpy>`` of ``owner`` and of its inertial, visual and collision parts; the
    box size, mesh scale, radius and length of their geometry.
    """
    places = [(owner, what)]
    for tag in ("inertial", "visual", "collision"):
        places += [(part, f"{what} <{tag}>") for part in owner.findall(tag)]
    for place, where in places:
        origin = place.find("origin")
        if origin is not None:
            for key in ("xyz", "rpy"):
                _numbers(origin, key, f"{where} <origin {key}>", 3)
        for shape in place.findall("geometry/*"):
            for key, count in _GEOMETRY_NUMBERS.get(shape.tag, ()):
                _numbers(shape, key, f"{where} <{shape.tag} {key}>", count)


def _check_inertial(link: ET.Element, name: str) -> None:
    inertial = link.find("inertial")
    if inertial is None:
        return
    mass_element = inertial.find("mass")
    what = f"link {name!r}"
    mass = 0.0 if mass_element is None else _float(mass_element, "value", f"{what} <mass>")
    if mass < 0:
        raise UrdfError(f"{what}: mass {mass:g} kg; allowed: >= 0")
    inertia = inertial.find("inertia")
    if inertia is None:
        return
    keys = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
    ixx, ixy, ixz, iyy, iyz, izz = (_float(inertia, k, f"{what} <inertia>", 0.0) for k in keys)
    matrix = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
    moments = np.linalg.eigvalsh(matrix)
    scale = max(float(np.abs(moments).max()), 1e-300)
    if moments[0] < -max(_INERTIA_TOLERANCE * scale, _INERTIA_FLOOR):
        raise UrdfError(
            f"{what}: inertia [ixx ixy ixz iyy iyz izz] = {[ixx, ixy, ixz, iyy, iyz, izz]} is "
            f"not positive definite (principal moments {np.round(moments, 9).tolist()} kg*m^2); "
            "allowed: a symmetric matrix without negative principal moments"
        )


def _joint(element: ET.Element, links: set[str]) -> UrdfJoint:
    name = element.get("name")
    if not name:
        raise UrdfError("a <joint> has no name; allowed: a non-empty name attribute")
    what = f"joint {name!r}"
    _check_vectors(element, what)
    kind = element.get("type", "")
    if kind not in JOINT_TYPES:
        raise UrdfError(
            f"{what}: type {kind!r} is not supported; allowed: {', '.join(JOINT_TYPES)}"
        )
    ends = {}
    for end in ("parent", "child"):
        tag = element.find(end)
        link = None if tag is None else tag.get("link")
        if not link:
            raise UrdfError(f"{what}: no <{end} link=...>; a joint needs a parent and a child")
        if link not in links:
            raise UrdfError(f"{what}: {end} link {link!r} is not a link of the robot")
        ends[end] = link
    lower, upper, velocity, effort = -np.inf, np.inf, np.inf, np.inf
    limit = element.find("limit")
    if kind in ("revolute", "prismatic"):
        if limit is None:
            raise UrdfError(f"{what}: a {kind} joint needs <limit lower upper effort velocity>")
        lower = _float(limit, "lower", f"{what} <limit>", 0.0)
        upper = _float(limit, "upper", f"{what} <limit>", 0.0)
        if lower > upper:
            raise UrdfError(
                f"{what}: limit lower {lower:g} > upper {upper:g}; allowed: lower <= upper"
            )
    if limit is not None and kind != "fixed":
        velocity = _float(limit, "velocity", f"{what} <limit>", np.inf)
        if velocity < 0:
            raise UrdfError(f"{what}: velocity limit {velocity:g}; allowed: >= 0")
        velocity = velocity or np.inf  # 0 is how many URDFs say "not given"
        effort = abs(_float(limit, "effort", f"{what} <limit>", np.inf)) or np.inf
    axis = element.find("axis")
    if axis is not None and kind != "fixed":
        values = (axis.get("xyz") or "1 0 0").split()
        try:
            vector = np.array([float(v) for v in values])
        except ValueError:
            raise UrdfError(f"{what}: axis xyz={axis.get('xyz')!r} is not three numbers") from None
        if vector.shape != (3,) or not np.all(np.isfinite(vector)) or not np.any(vector):
            raise UrdfError(f"{what}: axis xyz={axis.get('xyz')!r}; allowed: a non-zero 3-vector")
    mimic = None
    mimic_element = element.find("mimic")
    if mimic_element is not None and kind != "fixed":
        leader = mimic_element.get("joint")
        if not leader:
            raise UrdfError(f"{what}: <mimic> without a joint attribute")
        mimic = (
            leader,
            _float(mimic_element, "multiplier", f"{what} <mimic>", 1.0),
            _float(mimic_element, "offset", f"{what} <mimic>", 0.0),
        )
    return UrdfJoint(
        name, kind, ends["parent"], ends["child"], lower, upper, velocity, mimic, effort
    )


def _package_roots() -> list[Path]:
    """Folders where ``package://NAME`` may live: ``share`` folders of installed packages."""
    import sys

    roots = [Path(p) for p in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if p]
    for entry in sys.path:
        share = Path(entry or ".") / "cmeel.prefix" / "share"
        if share.is_dir():
            roots.append(share)
    return roots


def resolve_mesh(filename: str, urdf_dir: Path | None) -> Path | None:
    """The file a URDF mesh reference points to, or None when it cannot be found.

    Args:
        filename: as written, ``package://NAME/rest``, ``file:///abs`` or a path
        urdf_dir: the URDF's folder (None for URDF text without a file)
    """
    if filename.startswith("package://"):
        package, _, rest = filename[len("package://") :].partition("/")
        candidates = [root / package / rest for root in _package_roots()]
        if urdf_dir is not None:
            folder = urdf_dir.resolve()
            candidates += [a / rest for a in (folder, *folder.parents) if a.name == package]
        return next((c for c in candidates if c.is_file()), None)
    path = Path(filename[len("file://") :] if filename.startswith("file://") else filename)
    if not path.is_absolute():
        if urdf_dir is None:
            return None
        path = urdf_dir / path
    return path if path.is_file() else None


def check_urdf(text: str, urdf_dir: Path | None = None) -> UrdfSummary:
    """Check a URDF document and summarise it.

    Args:
        text: the URDF XML
        urdf_dir: the folder of the URDF file, for relative mesh paths (None: text only)

    Returns:
        The summary (mesh references that do not resolve are listed, not refused).

    Raises:
        UrdfError: malformed XML (with line and column), no ``<robot>`` root, a link or joint
            without a name or with a duplicate one, a joint of an unsupported type or whose
            parent or child is missing or unknown, a link with two parent joints, not exactly
            one root link, a negative mass, an inertia that is not positive definite, a bad
            limit or axis, an ``<origin xyz|rpy>`` that is not three finite numbers (the link or
            joint, and the part, named), a box size or mesh scale that is not three numbers.
    """
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        line, column = exc.position
        raise UrdfError(f"URDF is not well-formed XML: line {line}, column {column + 1}") from None
    if root.tag != "robot":
        raise UrdfError(f"URDF root element is <{root.tag}>; allowed: <robot>")
    links: list[str] = []
    for link in root.findall("link"):
        name = link.get("name")
        if not name:
            raise UrdfError("a <link> has no name; allowed: a non-empty name attribute")
        if name in links:
            raise UrdfError(f"link {name!r} is defined twice")
        _check_vectors(link, f"link {name!r}")
        _check_inertial(link, name)
        links.append(name)
    if not links:
        raise UrdfError("URDF has no <link>; a robot needs at least one")
    joints: list[UrdfJoint] = []
    parent_of: dict[str, str] = {}
    for element in root.findall("joint"):
        joint = _joint(element, set(links))
        if any(j.name == joint.name for j in joints):
            raise UrdfError(f"joint {joint.name!r} is defined twice")
        if joint.child in parent_of:
            raise UrdfError(
                f"joint {joint.name!r}: link {joint.child!r} already has parent joint "
                f"{parent_of[joint.child]!r}; a link has at most one parent"
            )
        parent_of[joint.child] = joint.name
        joints.append(joint)
    by_name = {joint.name: joint for joint in joints}
    for joint in joints:
        if joint.mimic is None:
            continue
        leader = by_name.get(joint.mimic[0])
        if leader is None:
            raise UrdfError(f"joint {joint.name!r}: mimics unknown joint {joint.mimic[0]!r}")
        if leader is joint or leader.mimic is not None or leader.kind == "fixed":
            raise UrdfError(
                f"joint {joint.name!r}: mimics {leader.name!r}, which is itself, a mimic joint or "
                "fixed; allowed: a leader that moves on its own"
            )
        if (leader.kind == "prismatic") != (joint.kind == "prismatic"):
            raise UrdfError(
                f"joint {joint.name!r} ({joint.kind}) mimics {leader.name!r} ({leader.kind}); "
                "allowed: a leader of the same kind (both prismatic or both revolute)"
            )
    roots = [link for link in links if link not in parent_of]
    if len(roots) != 1:
        raise UrdfError(
            f"URDF has {len(roots)} root links {roots[:5]}; allowed: exactly one link that is "
            "no joint's child (the joints must form a tree)"
        )
    children: dict[str, list[str]] = {}
    for joint in joints:
        children.setdefault(joint.parent, []).append(joint.child)
    reached, stack = {roots[0]}, [roots[0]]
    while stack:
        for child in children.get(stack.pop(), []):
            reached.add(child)
            stack.append(child)
    if len(reached) != len(links):
        loose = [link for link in links if link not in reached]
        raise UrdfError(f"links {loose[:5]} are not connected to root link {roots[0]!r}")
    meshes = tuple(m.get("filename", "") for m in root.iter("mesh"))
    missing = tuple(dict.fromkeys(m for m in meshes if resolve_mesh(m, urdf_dir) is None))
    return UrdfSummary(
        root.get("name", "robot"), roots[0], tuple(links), tuple(joints), meshes, missing
    )
