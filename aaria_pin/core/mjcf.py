"""MuJoCo models (MJCF) of any URDF robot with its IMUs, and the replay of a run in MuJoCo.

:func:`emit_mjcf` writes the MJCF of a URDF robot: one ``body`` per URDF link (fixed links too,
welded to their parent), its ``inertial`` (mass, centre of mass, full inertia in the link
frame), ``hinge`` and ``slide`` joints about the URDF axes with their ranges, a ``site`` at every
IMU mount with a ``gyro`` and an ``accelerometer`` on it, and the visual shapes (boxes,
cylinders, spheres, and STL or OBJ meshes; a link whose visual mesh MuJoCo cannot read, such as
a COLLADA ``.dae``, shows its collision meshes instead), none of them colliding; a mimic
joint is a joint with an ``equality`` constraint to its leader. Mesh files are named by their
absolute paths (the model is for this machine's installed meshes). On a moving
base the root link rides a prescribed 6-DOF chain: three ``slide`` joints along world x, y, z
and three ``hinge`` joints about x, the new y and the newer z (:data:`BASE_JOINTS`), the
gimbal of :func:`~aaria_pin.core.trajectory.gimbal_xyz_motion`, so a run's base motion is
replayed exactly. :func:`replay_in_mujoco` sets a run's positions, velocities and
accelerations in MuJoCo and returns MuJoCo's own sensor readings and inverse-dynamics torques.

The input is the URDF text, not the Pinocchio model nor a
:class:`~aaria_pin.core.urdf.RobotDescription`: every run record and every robot source (DH
arms, example-robot-data robots, URDF files, the wrist, the pick-place arm) has its URDF,
while a description exists only for the robots we build, and the Pinocchio model merges fixed
links into their moving parent and keeps no visual shapes. MuJoCo's own URDF import is not
used: it fuses the fixed links, so the IMU frames are lost (0 sites, 0 sensors).
"""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING
from xml.sax.saxutils import quoteattr

import numpy as np

from aaria_pin.core.model import GRAVITY
from aaria_pin.core.record import ImuMount, RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import DEFAULT_RATE, BaseMotion
from aaria_pin.core.urdf import _num, _vec
from aaria_pin.core.urdf_check import UrdfJoint, check_urdf, resolve_mesh
from aaria_pin.errors import ModelError, ParameterError

if TYPE_CHECKING:
    import mujoco

__all__ = [
    "BASE_JOINTS",
    "BASE_TABLE_NAMES",
    "MESH_SUFFIXES",
    "NEGLIGIBLE_INERTIA",
    "NEGLIGIBLE_MASS",
    "emit_mjcf",
    "gimbal_xyz_coordinates",
    "load_mjcf",
    "record_base_motion",
    "record_mjcf",
    "record_moving_base",
    "replay_in_mujoco",
    "sensor_names",
]

BASE_JOINTS = ("base_x", "base_y", "base_z", "base_rx", "base_ry", "base_rz")
"""The moving base's joints: slides along world x, y, z, then hinges about x, new y, newer z."""

BASE_TABLE_NAMES = ("base_table", "senSenB")
"""Names under which a run record keeps its base oscillation table (URDF robots, DH arms)."""

MESH_SUFFIXES = (".stl", ".obj")
"""Mesh files MuJoCo reads, written as mesh assets (others are left out)."""

NEGLIGIBLE_MASS = 1e-12
"""Mass given to a link that moves on its own joint with no mass welded to it [kg].

MuJoCo refuses a moving body without mass or without moments (below 1e-15: a "virtual" link
between the hinges of a spherical joint, a point mass); this mass and
:data:`NEGLIGIBLE_INERTIA` change torques by about 1e-11 N·m."""
NEGLIGIBLE_INERTIA = 1e-12
"""Principal moments given to such a link, or added to a point mass's [kg·m²]."""

_MJ_MINVAL = 1e-15
"""MuJoCo's ``mjMINVAL``: the smallest principal moment its ``fullinertia`` accepts."""
_NEUTRAL_GREY = (0.7, 0.7, 0.7, 1.0)
_AXES = ("1 0 0", "0 1 0", "0 0 1")


def sensor_names(imu: str) -> tuple[str, str]:
    """The MJCF names of an IMU's two sensors: ``<imu>_gyro``, ``<imu>_accelerometer``."""
    return f"{imu}_gyro", f"{imu}_accelerometer"


@dataclass(frozen=True)
class _Origin:
    """A URDF ``<origin>`` as a position and a rotation matrix."""

    xyz: Array
    R: Array


def _floats(text: str | None, default: Sequence[float]) -> Array:
    if text is None:
        return np.array(default, dtype=float)
    return np.array([float(v) for v in text.split()], dtype=float)


def _origin(element: ET.Element | None) -> _Origin:
    """The pose an element's ``<origin xyz rpy>`` gives (``R = Rz·Ry·Rx``, as URDF readers)."""
    import pinocchio as pin

    origin = None if element is None else element.find("origin")
    if origin is None:
        return _Origin(np.zeros(3), np.eye(3))
    roll, pitch, yaw = _floats(origin.get("rpy"), (0.0, 0.0, 0.0))
    R = np.asarray(pin.rpy.rpyToMatrix(roll, pitch, yaw))
    return _Origin(_floats(origin.get("xyz"), (0.0, 0.0, 0.0)), R)


def _quat(R: Array) -> str:
    """A rotation matrix as MuJoCo's quaternion ``w x y z``."""
    import pinocchio as pin

    x, y, z, w = pin.Quaternion(np.asarray(R, dtype=float)).coeffs()
    return _vec((w, x, y, z))


def _placement(xyz: Array, R: Array) -> str:
    """``pos`` and ``quat`` attributes (left out where they are the identity)."""
    text = ""
    if np.any(xyz):
        text += f' pos="{_vec(xyz)}"'
    if not np.array_equal(R, np.eye(3)):
        text += f' quat="{_quat(R)}"'
    return text


def _mass_properties(link: ET.Element) -> tuple[float, Array]:
    """A link's mass [kg] and inertia about its centre of mass in the inertial frame [kg·m²]."""
    mass_element = link.find("inertial/mass")
    mass = 0.0 if mass_element is None else float(mass_element.get("value", "0"))
    tensor = link.find("inertial/inertia")
    keys = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
    ixx, ixy, ixz, iyy, iyz, izz = (
        (0.0 if tensor is None else float(tensor.get(key, "0"))) for key in keys
    )
    return mass, np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])


def _negligible(link: ET.Element) -> bool:
    """Whether MuJoCo takes a link as without mass or without moments (below 1e-15)."""
    mass, inertia = _mass_properties(link)
    return mass <= _MJ_MINVAL or float(np.abs(inertia).max()) <= _MJ_MINVAL


def _inertial(link: ET.Element, floor: bool) -> str:
    """The ``<inertial>`` of a link, its inertia in the link frame.

    A positive definite inertia is written whole (``fullinertia``, no ``quat``); MuJoCo
    refuses others there (a point mass, a flat body, moments below 1e-15 kg·m²), so theirs is
    written as principal moments (``diaginertia``, negative round-off set to 0) in its
    principal axes (``quat``).

    Args:
        link: the URDF link
        floor: the link moves on its own joint and nothing welded to it has mass and moments
            (a "virtual" link between the hinges of a spherical joint, a point mass); MuJoCo
            refuses such a body, so a massless one gets :data:`NEGLIGIBLE_MASS` and
            :data:`NEGLIGIBLE_INERTIA`, and a point mass :data:`NEGLIGIBLE_INERTIA` added to
            its moments
    """
    mass, inertia = _mass_properties(link)
    if floor and mass > _MJ_MINVAL:
        inertia = inertia + NEGLIGIBLE_INERTIA * np.eye(3)
    elif floor:
        moment = _num(NEGLIGIBLE_INERTIA)
        diagonal = f'diaginertia="{moment} {moment} {moment}"'
        return f'<inertial pos="0 0 0" mass="{_num(NEGLIGIBLE_MASS)}" {diagonal}/>'
    if mass <= 0.0 and not np.any(inertia):
        return ""  # a massless frame; a zero mass with moments (Bolt's feet) keeps its moments
    origin = _origin(link.find("inertial"))
    inertia = origin.R @ inertia @ origin.R.T
    position = f'pos="{_vec(origin.xyz)}" mass="{_num(mass)}"'
    moments, axes = np.linalg.eigh(inertia)
    if moments[0] > _MJ_MINVAL:
        full = [inertia[k] for k in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))]
        return f'<inertial {position} fullinertia="{_vec(full)}"/>'
    if np.linalg.det(axes) < 0:
        axes[:, 0] = -axes[:, 0]
    moments = np.maximum(moments, 0.0)
    return f'<inertial {position} quat="{_quat(axes)}" diaginertia="{_vec(moments)}"/>'


def _rgba(visual: ET.Element, materials: dict[str, Array]) -> Array:
    material = visual.find("material")
    if material is None:
        return np.array(_NEUTRAL_GREY)
    colour = material.find("color")
    if colour is not None and colour.get("rgba"):
        return _floats(colour.get("rgba"), _NEUTRAL_GREY)
    return materials.get(material.get("name", ""), np.array(_NEUTRAL_GREY))


class _Meshes:
    """The mesh assets of a model: one per mesh file and scale, by absolute path.

    Meshes only draw (masses come from the URDF's inertials): each is declared
    ``inertia="shell"``, which MuJoCo accepts for open or thin meshes too, where a volume
    would be refused ("mesh volume is too small").
    """

    def __init__(self, urdf_dir: Path | None) -> None:
        self.urdf_dir = urdf_dir
        self.assets: dict[tuple[str, str], str] = {}
        self.skipped: list[str] = []

    def asset(self, mesh: ET.Element) -> str | None:
        """The asset name of a ``<mesh>``, or None when MuJoCo cannot read it or it is missing."""
        filename = mesh.get("filename", "")
        path = resolve_mesh(filename, self.urdf_dir)
        if path is None or path.suffix.lower() not in MESH_SUFFIXES:
            self.skipped.append(filename)
            return None
        factors = _floats(mesh.get("scale"), (1.0, 1.0, 1.0))
        scale = "" if np.all(factors == 1.0) else f' scale="{_vec(factors)}"'
        key = (str(path.resolve()), scale)
        return self.assets.setdefault(key, f"mesh_{len(self.assets)}")

    def xml(self) -> str:
        return "".join(
            f'    <mesh name="{name}" file={quoteattr(path)}{scale} inertia="shell"/>\n'
            for (path, scale), name in self.assets.items()
        )


def _geom(element: ET.Element, rgba: Array, meshes: _Meshes) -> str | None:
    """A ``<geom>`` of a URDF ``<visual>`` or ``<collision>``, or None if MuJoCo cannot draw it."""
    geometry = element.find("geometry")
    if geometry is None or len(geometry) == 0:
        return None
    shape = geometry[0]
    origin = _origin(element)
    if shape.tag == "box":
        size = f'type="box" size="{_vec(_floats(shape.get("size"), (0, 0, 0)) / 2)}"'
    elif shape.tag == "cylinder":
        radius, length = float(shape.get("radius", "0")), float(shape.get("length", "0"))
        size = f'type="cylinder" size="{_vec((radius, length / 2))}"'
    elif shape.tag == "sphere":
        size = f'type="sphere" size="{_num(float(shape.get("radius", "0")))}"'
    elif shape.tag == "mesh":
        name = meshes.asset(shape)
        if name is None:
            return None
        size = f'type="mesh" mesh="{name}"'
    else:
        return None
    return f'<geom {size}{_placement(origin.xyz, origin.R)} rgba="{_vec(rgba)}"/>'


def _geoms(link: ET.Element, materials: dict[str, Array], meshes: _Meshes) -> list[str]:
    """A link's visual geoms; its collision meshes where a visual mesh cannot be read."""
    geoms: list[str] = []
    unreadable: list[Array] = []
    for visual in link.findall("visual"):
        rgba = _rgba(visual, materials)
        geom = _geom(visual, rgba, meshes)
        if geom is not None:
            geoms.append(geom)
        elif visual.find("geometry/mesh") is not None:
            unreadable.append(rgba)
    if unreadable:
        for collision in link.findall("collision"):
            if collision.find("geometry/mesh") is not None:
                geom = _geom(collision, unreadable[0], meshes)
                if geom is not None:
                    geoms.append(geom)
    return geoms


def _body_name(link: str) -> str:
    """The body of a link: its name, but ``world`` (MuJoCo's world body) becomes ``world_link``."""
    return "world_link" if link == "world" else link


def _frame_links(root: ET.Element) -> dict[str, str]:
    """Frame name → the link it is fixed to: every link, and every joint's child link."""
    links = {link.get("name", ""): link.get("name", "") for link in root.findall("link")}
    for joint in root.findall("joint"):
        child = joint.find("child")
        if child is not None and joint.get("name", "") not in links:
            links[joint.get("name", "")] = child.get("link", "")
    return links


def _sites(
    root: ET.Element, imu_mounts: Sequence[ImuMount], tool_frame: str | None
) -> dict[str, list[str]]:
    """Link name → its ``<site>`` elements: one per IMU, at its mount, and the tool's."""
    frame_links = _frame_links(root)
    sites: dict[str, list[str]] = {}
    for mount in imu_mounts:
        if not mount.parent:
            continue  # an empty slot: no IMU
        if mount.parent not in frame_links:
            raise ModelError(
                f"IMU {mount.name!r}: parent frame {mount.parent!r} is not in the URDF; "
                "allowed: a link or joint of the URDF",
                parameter="imu_mounts",
                value=mount.parent,
                element=mount.name,
            )
        T = np.asarray(mount.T_parent_imu, dtype=float)
        sites.setdefault(frame_links[mount.parent], []).append(
            f"<site name={quoteattr(mount.name)}{_placement(T[:3, 3], T[:3, :3])}"
            ' size="0.01" rgba="1 0.5 0 1"/>'
        )
    if tool_frame:
        if tool_frame not in frame_links:
            raise ModelError(
                f"tool frame {tool_frame!r} is not in the URDF; allowed: a link or joint",
                parameter="tool_frame",
                value=tool_frame,
            )
        sites.setdefault(frame_links[tool_frame], []).append(
            f'<site name={quoteattr(tool_frame)} size="0.005" rgba="1 0 0 1"/>'
        )
    return sites


def _floored_links(
    joints: Sequence[UrdfJoint], links: dict[str, ET.Element], base: str | None
) -> set[str]:
    """Moving links without mass or moments: :func:`_inertial`'s ``floor``.

    A link on its own joint (or ``base`` on the base chain) none of whose welded links (itself
    and those on fixed joints below it) has both mass and moments.
    """
    fixed_children: dict[str, list[str]] = {}
    moving = set() if base is None else {base}
    for joint in joints:
        if joint.kind == "fixed":
            fixed_children.setdefault(joint.parent, []).append(joint.child)
        else:
            moving.add(joint.child)

    def negligible(link: str) -> bool:
        welded = fixed_children.get(link, [])
        return _negligible(links[link]) and all(negligible(child) for child in welded)

    return {link for link in moving if negligible(link)}


def _joint(joint: ET.Element) -> str:
    """The MJCF joint of a URDF revolute, continuous or prismatic joint."""
    kind = joint.get("type", "")
    axis_element = joint.find("axis")
    axis = _floats(None if axis_element is None else axis_element.get("xyz"), (1.0, 0.0, 0.0))
    axis = axis / np.linalg.norm(axis)
    limit = joint.find("limit")
    limits = ' limited="false"'
    if kind != "continuous" and limit is not None:
        lower, upper = float(limit.get("lower", "0")), float(limit.get("upper", "0"))
        if lower < upper:  # MuJoCo refuses an empty range: such a joint is left unlimited
            limits = f' limited="true" range="{_vec((lower, upper))}"'
    mjcf_kind = "slide" if kind == "prismatic" else "hinge"
    name = quoteattr(joint.get("name", ""))
    return f'<joint name={name} type="{mjcf_kind}" axis="{_vec(axis)}"{limits}/>'


def emit_mjcf(
    urdf: str,
    imu_mounts: Sequence[ImuMount],
    *,
    moving_base: bool = True,
    gravity: Sequence[float] | Array = GRAVITY,
    rate: float = DEFAULT_RATE,
    urdf_dir: str | os.PathLike[str] | None = None,
    tool_frame: str | None = None,
    balance_inertia: bool = False,
) -> tuple[str, tuple[str, ...]]:
    """The MJCF of a URDF robot with a site, a gyro and an accelerometer per IMU.

    Args:
        urdf: the URDF text (checked as :func:`~aaria_pin.core.urdf_check.check_urdf` does)
        imu_mounts: the IMUs, in record order (an empty slot, parent ``""``, gets none)
        moving_base: the root link on the 6-DOF chain :data:`BASE_JOINTS`; else fixed at the
            world origin
        gravity: gravity in the world [m/s²]
        rate: sample rate [Hz]; the timestep is ``1/rate`` [s]
        urdf_dir: the URDF's folder, for relative mesh paths
        tool_frame: a link or joint to mark with a site of its name (no sensor), or None
        balance_inertia: let MuJoCo raise principal moments that break ``A + B >= C``
            (compiler ``balanceinertia``), which it otherwise refuses for some links (PR2's
            ``sensor_mount_link``); those links' dynamics then differ from the URDF's

    Returns:
        The MJCF text, and the mesh files that were left out (not STL or OBJ, or not found).

    Raises:
        UrdfError: the URDF check fails.
        ModelError: an IMU's parent or the tool frame is not in the URDF, or a name of
            :data:`BASE_JOINTS` is a joint of the URDF.
        ParameterError: a rate that is not positive and finite, or gravity not 3 numbers.
    """
    if not (np.isfinite(rate) and rate > 0):
        raise ParameterError(parameter="rate", value=rate, allowed="a finite rate > 0 Hz")
    gravity_vector = np.asarray(gravity, dtype=float)
    if gravity_vector.shape != (3,) or not np.all(np.isfinite(gravity_vector)):
        raise ParameterError(parameter="gravity", value=gravity, allowed="3 finite numbers")
    folder = None if urdf_dir is None else Path(urdf_dir)
    summary = check_urdf(urdf, folder)
    root = ET.fromstring(urdf)
    clash = sorted({joint.name for joint in summary.joints} & set(BASE_JOINTS))
    if moving_base and clash:
        raise ModelError(
            f"URDF joint {clash[0]!r} has the name of a base joint; allowed: names other than "
            + ", ".join(BASE_JOINTS),
            element=clash[0],
        )
    materials: dict[str, Array] = {}
    for material in root.iter("material"):  # top-level, or defined inside a visual and reused
        colour = material.find("color")
        if colour is not None:
            materials.setdefault(
                material.get("name", ""), _floats(colour.get("rgba"), _NEUTRAL_GREY)
            )
    links = {link.get("name", ""): link for link in root.findall("link")}
    elements = {joint.get("name", ""): joint for joint in root.findall("joint")}
    children: dict[str, list[tuple[str, ET.Element]]] = {}
    for joint in summary.joints:  # document order
        children.setdefault(joint.parent, []).append((joint.child, elements[joint.name]))
    sites = _sites(root, imu_mounts, tool_frame)
    base = summary.root_link if moving_base else None
    floored = _floored_links(summary.joints, links, base)
    meshes = _Meshes(folder)

    def body(name: str, depth: int, joint: ET.Element | None) -> str:
        pad = "  " * depth
        head = f"{pad}<body name={quoteattr(_body_name(name))}"
        lines: list[str] = []
        if joint is None:
            if moving_base:
                lines += [
                    f'<joint name="{BASE_JOINTS[k]}" type="{kind}" axis="{axis}"/>'
                    for k, (kind, axis) in enumerate(
                        [*(("slide", axis) for axis in _AXES), *(("hinge", axis) for axis in _AXES)]
                    )
                ]
        else:
            origin = _origin(joint)
            head += _placement(origin.xyz, origin.R)
            if joint.get("type") != "fixed":
                lines.append(_joint(joint))
        link = links[name]
        inertial = _inertial(link, name in floored)
        lines += [inertial] if inertial else []
        lines += _geoms(link, materials, meshes)
        lines += sites.get(name, [])
        text = f"{head}>\n" + "".join(f"{pad}  {line}\n" for line in lines)
        for child, child_joint in children.get(name, []):
            text += body(child, depth + 1, child_joint)
        return text + f"{pad}</body>\n"

    tree = body(summary.root_link, 2, None)
    sensors = "".join(
        f'    <gyro name="{gyro}" site={quoteattr(mount.name)}/>\n'
        f'    <accelerometer name="{accelerometer}" site={quoteattr(mount.name)}/>\n'
        for mount in imu_mounts
        if mount.parent
        for gyro, accelerometer in [sensor_names(mount.name)]
    )
    assets = meshes.xml()
    equalities = "".join(
        f"    <joint joint1={quoteattr(joint.name)} joint2={quoteattr(joint.mimic[0])}"
        f' polycoef="{_num(joint.mimic[2])} {_num(joint.mimic[1])} 0 0 0"/>\n'
        for joint in summary.joints
        if joint.mimic is not None
    )
    text = (
        f"<mujoco model={quoteattr(summary.name)}>\n"
        "  <!-- written by aaria_pin from the URDF; a body per link, a site, a gyro and an"
        " accelerometer per IMU -->\n"
        '  <compiler angle="radian" inertiafromgeom="false" autolimits="true"'
        f' balanceinertia="{str(balance_inertia).lower()}"/>\n'
        f'  <option timestep="{_num(1.0 / rate)}" gravity="{_vec(gravity_vector)}"/>\n'
        "  <default>\n"
        '    <joint armature="0" damping="0" frictionloss="0" stiffness="0"/>\n'
        '    <geom contype="0" conaffinity="0" group="1"/>\n'
        "  </default>\n"
        + (f"  <asset>\n{assets}  </asset>\n" if assets else "")
        + f"  <worldbody>\n{tree}  </worldbody>\n"
        + (f"  <equality>\n{equalities}  </equality>\n" if equalities else "")
        + (f"  <sensor>\n{sensors}  </sensor>\n" if sensors else "")
        + "</mujoco>\n"
    )
    return text, tuple(dict.fromkeys(meshes.skipped))


def record_moving_base(record: RunRecord) -> bool:
    """Whether a run's base moved.

    Its ``moving_base`` attribute; without one, a DH run moves, another if its base leaves the
    identity pose.
    """
    if "moving_base" in record.attributes:
        return bool(record.attributes["moving_base"])
    if record.attributes.get("kind") == "dh":
        return True
    return not np.array_equal(record.base_pose, np.broadcast_to(np.eye(4), record.base_pose.shape))


def record_mjcf(
    record: RunRecord,
    *,
    moving_base: bool | None = None,
    rate: float | None = None,
    balance_inertia: bool = False,
) -> tuple[str, tuple[str, ...]]:
    """The MJCF of a run's robot: its stored URDF, IMU mounts, gravity, rate and tool frame.

    Args:
        record: the run (any kind; its ``urdf`` text must be stored)
        moving_base: the base chain or a fixed base (default :func:`record_moving_base`)
        rate: sample rate [Hz] (default the run's)
        balance_inertia: as :func:`emit_mjcf`

    Returns:
        As :func:`emit_mjcf`.

    Raises:
        ModelError: the run stores no URDF; else as :func:`emit_mjcf`.
    """
    if not record.urdf:
        raise ModelError(
            "run stores no URDF text; allowed: a run file with its robot's URDF",
            parameter="urdf",
            value="",
        )
    attributes = record.attributes
    return emit_mjcf(
        record.urdf,
        record.imu_mounts,
        moving_base=record_moving_base(record) if moving_base is None else moving_base,
        gravity=attributes.get("gravity", GRAVITY),
        rate=float(attributes.get("rate", DEFAULT_RATE)) if rate is None else rate,
        urdf_dir=attributes.get("urdf_dir") or None,
        tool_frame=attributes.get("tool_frame") or None,
        balance_inertia=balance_inertia,
    )


def gimbal_xyz_coordinates(
    rotation: Array, omega: Array, omega_dot: Array
) -> tuple[Array, Array, Array]:
    """The X-Y-Z gimbal angles, rates and accelerations of a rotation and its body motion.

    The inverse of :func:`~aaria_pin.core.trajectory.gimbal_xyz_motion`: with
    ``R = Rx(a)·Ry(b)·Rz(c)`` the body angular velocity is ``ω = E(b, c)·[ȧ ḃ ċ]`` with
    ``E = [[cos b cos c, sin c, 0], [-cos b sin c, cos c, 0], [sin b, 0, 1]]``, and
    ``ω̇ = E·[ä b̈ c̈] + Ė·[ȧ ḃ ċ]``; both are solved for the gimbal's rates and accelerations
    (the coordinates of a chain of hinges about x, the new y and the newer z). The angles are
    :func:`~aaria_pin.core.rotations.angles_from_matrix` ``"XYZ"``: in ``(-π, π]``, the middle
    one in ``[-π/2, π/2]``; the rates are singular at ``cos b = 0``.

    Args:
        rotation: ``R_world_base``, T × 3 × 3
        omega: angular velocity in base axes, T × 3 [rad/s]
        omega_dot: its derivative in base axes, T × 3 [rad/s²]

    Returns:
        Angles (a, b, c) [rad], rates [rad/s] and accelerations [rad/s²], each T × 3.
    """
    from aaria_pin.core.rotations import angles_from_matrix

    angles = angles_from_matrix(rotation, "XYZ").angles
    b, c = angles[:, 1], angles[:, 2]
    cb, sb, cc, sc = np.cos(b), np.sin(b), np.cos(c), np.sin(c)

    def solve(w: Array) -> Array:  # E(b, c)⁻¹ · w, row by row
        first = (cc * w[:, 0] - sc * w[:, 1]) / cb
        return np.stack([first, sc * w[:, 0] + cc * w[:, 1], w[:, 2] - sb * first], axis=1)

    rates = solve(np.asarray(omega, dtype=float))
    da, db, dc = rates.T
    E_dot_rates = np.stack(
        [
            (-sb * cc * db - cb * sc * dc) * da + cc * dc * db,
            (sb * sc * db - cb * cc * dc) * da - sc * dc * db,
            cb * db * da,
        ],
        axis=1,
    )
    accelerations = solve(np.asarray(omega_dot, dtype=float) - E_dot_rates)
    return angles, rates, accelerations


def record_base_motion(record: RunRecord) -> BaseMotion:
    """The base motion of a run from its base oscillation table (:data:`BASE_TABLE_NAMES`).

    Raises:
        ParameterError: the record has no base table, or its table does not give the stored
            ``base_pose`` (to 1e-9 m and 1e-9 of a rotation matrix entry).
    """
    from aaria_pin.core.oscillation import base_motion

    name = next((name for name in BASE_TABLE_NAMES if name in record.tables), None)
    if name is None:
        raise ParameterError(
            "run has no base oscillation table; allowed: a run with one of "
            + ", ".join(BASE_TABLE_NAMES)
            + ", or a base motion given",
            parameter="base",
            value=None,
        )
    base = base_motion(record.tables[name], record.time)
    if not np.allclose(base.T_world_base(), record.base_pose, rtol=0.0, atol=1e-9):
        raise ParameterError(
            f"run's {name} does not give its stored base_pose; allowed: the run's own table",
            parameter="base",
            value=name,
        )
    return base


def load_mjcf(xml: str) -> mujoco.MjModel:
    """Compile MJCF text with MuJoCo (imported here: the optional ``mujoco`` extra).

    Raises:
        ModelError: MuJoCo cannot compile it (its message, on one line).
    """
    import mujoco

    try:
        return mujoco.MjModel.from_xml_string(xml)
    except ValueError as exc:
        raise ModelError(f"MuJoCo cannot compile the MJCF: {' '.join(str(exc).split())}") from None


def _joint_address(model: mujoco.MjModel, name: str) -> tuple[int, int]:
    """(qpos address, dof address) of a 1-DOF joint by name."""
    import mujoco

    joint_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)
    if joint_id < 0:
        raise ModelError(
            f"joint {name!r} is not in the MJCF; allowed: a model of the run's robot",
            element=name,
        )
    return int(model.jnt_qposadr[joint_id]), int(model.jnt_dofadr[joint_id])


def replay_in_mujoco(
    record: RunRecord, xml: str, base: BaseMotion | None = None
) -> tuple[Array, Array]:
    """MuJoCo's IMU readings and joint torques along a run's motion.

    For each sample the run's joint values, velocities and accelerations and its base motion
    (on the chain :data:`BASE_JOINTS`: positions and world-axis velocities and accelerations on
    the slides, :func:`gimbal_xyz_coordinates` of the body angular motion on the hinges) are
    set; ``mj_inverse`` gives the generalised forces ``qfrc_inverse`` (the joints' are the
    torques); with those applied (``qfrc_applied``) ``mj_forward`` reproduces the accelerations
    and its ``sensordata`` are MuJoCo's gyro (angular velocity) and accelerometer (specific
    force: acceleration less gravity) readings in each site's axes. Constraints are disabled
    (no contacts or limits act). One call into MuJoCo per sample (MuJoCo has no batched
    inverse dynamics): a check of a run, not a data path.

    Args:
        record: the run (its joints must be joints of the MJCF, its IMUs sites with sensors)
        xml: the MJCF of the run's robot (:func:`emit_mjcf`)
        base: the base motion on a moving base (default :func:`record_base_motion`)

    Returns:
        IMU signals ``[wx wy wz fx fy fz]``, T × S × 6 in the record's IMU order (zeros in
        empty slots) [rad/s, m/s²], and joint torques, T × n in the record's joint order
        [N·m or N] (zeros in the all-zero column of an empty DH module, which has no joint).

    Raises:
        ModelError: the MJCF lacks a joint or a sensor of the run.
        ParameterError: a moving base without a base motion.
    """
    import mujoco

    model = load_mjcf(xml)
    model.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)
    data = mujoco.MjData(model)
    samples = record.n_samples
    qpos = np.zeros((samples, model.nq))
    qvel, qacc = np.zeros((samples, model.nv)), np.zeros((samples, model.nv))
    columns, dofs = [], []
    for j, name in enumerate(record.joint_names):
        empty = not any(np.any(a[:, j]) for a in (record.q, record.qd, record.qdd, record.tau))
        if empty and mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name) < 0:
            continue  # an empty module of a DH arm: a zero column, no joint
        position, dof = _joint_address(model, name)
        qpos[:, position], qvel[:, dof], qacc[:, dof] = (
            record.q[:, j],
            record.qd[:, j],
            record.qdd[:, j],
        )
        columns.append(j)
        dofs.append(dof)
    if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, BASE_JOINTS[0]) >= 0:
        motion = record_base_motion(record) if base is None else base
        angles, rates, accelerations = gimbal_xyz_coordinates(
            motion.rotation, motion.omega, motion.omega_dot
        )
        base_values = (
            (motion.position, motion.velocity, motion.acceleration),
            (angles, rates, accelerations),
        )
        for k, name in enumerate(BASE_JOINTS):
            position, dof = _joint_address(model, name)
            values = base_values[k // 3]
            qpos[:, position], qvel[:, dof], qacc[:, dof] = (v[:, k % 3] for v in values)
    sensors: list[tuple[int, int, int]] = []
    for s, mount in enumerate(record.imu_mounts):
        if not mount.parent:
            continue
        addresses = []
        for sensor in sensor_names(mount.name):
            sensor_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SENSOR, sensor)
            if sensor_id < 0:
                raise ModelError(
                    f"sensor {sensor!r} is not in the MJCF; allowed: a model with the run's IMUs",
                    element=sensor,
                )
            addresses.append(int(model.sensor_adr[sensor_id]))
        sensors.append((s, addresses[0], addresses[1]))
    imu = np.zeros((samples, len(record.imu_mounts), 6))
    tau = np.zeros((samples, len(record.joint_names)))
    for t in range(samples):
        data.qpos[:], data.qvel[:], data.qacc[:] = qpos[t], qvel[t], qacc[t]
        data.qfrc_applied[:] = 0.0
        mujoco.mj_inverse(model, data)
        tau[t, columns] = data.qfrc_inverse[dofs]
        data.qfrc_applied[:] = data.qfrc_inverse
        mujoco.mj_forward(model, data)
        for s, gyro, accelerometer in sensors:
            imu[t, s, :3] = data.sensordata[gyro : gyro + 3]
            imu[t, s, 3:] = data.sensordata[accelerometer : accelerometer + 3]
    return imu, tau
