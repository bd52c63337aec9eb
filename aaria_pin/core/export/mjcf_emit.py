"""MuJoCo models (MJCF) of any URDF robot with its IMUs: the document, compiled, balanced.

:func:`emit_mjcf` writes the MJCF of a URDF robot: the body tree of
:mod:`~aaria_pin.core.export.mjcf_bodies` (a body per URDF link with its inertial, joint,
shapes and IMU sites), a ``gyro`` and an ``accelerometer`` on every IMU site, a mimic joint as
a joint ``equality`` to its leader, and on a moving base the root link on a prescribed 6-DOF
chain: three ``slide`` joints along world x, y, z and three ``hinge`` joints about x, the new y
and the newer z (:data:`BASE_JOINTS`), the gimbal of
:func:`~aaria_pin.core.oscillation.base_motion`, so a run's base motion is replayed
exactly (:mod:`~aaria_pin.core.export.mjcf_replay`).

The input is the URDF text, not the Pinocchio model: every run record and every robot source
has its URDF, while the Pinocchio model merges fixed links into their moving parent and keeps
no visual shapes. MuJoCo's own URDF import is not used: it fuses the fixed links, so the IMU
frames are lost (0 sites, 0 sensors).

The document is written as text, not built with MuJoCo's ``MjSpec``, for two measured reasons
(MuJoCo 4.0, the UR5 on a moving base, 1 s at 100 Hz): ``MjSpec.to_xml`` writes numbers to
6 significant digits (an inertia 0.22689067591 becomes 0.226891), so a model written by it
replays the run's torques to 5e-8 and its IMU signals to 1e-11 of their largest value, where
the text written here replays both to 2e-15 (the tests require 1e-9); and ``mujoco`` is an
optional extra, while ``aaria mjcf`` writes a model without it. ``MjSpec`` keeps the sites,
sensors, materials and the base chain; compiled directly (no XML), it holds the exact numbers.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Literal, TypedDict, Unpack
from xml.sax.saxutils import quoteattr

import numpy as np

from aaria_pin.core.arguments import checked
from aaria_pin.core.export.mjcf_actuators import actuator_comment, joint_actuator_attributes
from aaria_pin.core.export.mjcf_bodies import (
    MeshAssets,
    body_name,
    floored_links,
    link_geoms,
    link_inertial,
    link_sites,
    mjcf_joint,
    placement,
)
from aaria_pin.core.joint_sensors import ActuatorModel
from aaria_pin.core.model import GRAVITY
from aaria_pin.core.record import ImuMount
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import DEFAULT_RATE, check_rate
from aaria_pin.core.urdf_emitter import exact_number, exact_numbers
from aaria_pin.core.urdf_parse import parse_urdf
from aaria_pin.core.urdf_tree import UrdfDocument, UrdfJoint
from aaria_pin.errors import ModelError, ParameterError

if TYPE_CHECKING:
    import mujoco

__all__ = [
    "BASE_JOINTS",
    "BalanceInertia",
    "MjcfOptions",
    "emit_mjcf",
    "load_mjcf",
    "sensor_names",
]

BASE_JOINTS = ("base_x", "base_y", "base_z", "base_rx", "base_ry", "base_rz")
"""The moving base's joints: slides along world x, y, z, then hinges about x, new y, newer z."""

BalanceInertia = bool | Literal["auto"]
"""``balance_inertia`` of :func:`emit_mjcf`: never, always, or ``"auto"``: when MuJoCo asks."""

_AXES = ("1 0 0", "0 1 0", "0 0 1")
_UNBALANCED = "A + B >= C"
"""MuJoCo's compiler error for principal moments that break the triangle inequality."""


def sensor_names(imu: str) -> tuple[str, str]:
    """The MJCF names of an IMU's two sensors: ``<imu>_gyro``, ``<imu>_accelerometer``."""
    return f"{imu}_gyro", f"{imu}_accelerometer"


def _base_chain() -> list[str]:
    kinds = [*(("slide", axis) for axis in _AXES), *(("hinge", axis) for axis in _AXES)]
    return [
        f'<joint name="{BASE_JOINTS[k]}" type="{kind}" axis="{axis}"/>'
        for k, (kind, axis) in enumerate(kinds)
    ]


def _worldbody(
    document: UrdfDocument,
    sites: dict[str, list[str]],
    settings: _Settings,
    meshes: MeshAssets,
) -> str:
    """The ``<body>`` tree from the root link, indented inside ``<worldbody>``."""
    children: dict[str, list[UrdfJoint]] = {}
    for joint in document.joints:  # document order
        children.setdefault(joint.parent, []).append(joint)
    moving_base = settings.moving_base
    floored = floored_links(document, document.root_link if moving_base else None)

    def body(name: str, depth: int, joint: UrdfJoint | None) -> str:
        pad = "  " * depth
        head = f"{pad}<body name={quoteattr(body_name(name))}"
        lines: list[str] = []
        if joint is None:
            lines += _base_chain() if moving_base else []
        else:
            head += placement(joint.origin.xyz, joint.origin.rotation())
            if joint.kind != "fixed":
                lines.append(mjcf_joint(joint, settings.joints.get(joint.name, "")))
        link = document.link(name)
        inertial = link_inertial(link, name in floored)
        lines += [inertial] if inertial else []
        lines += link_geoms(link, document, meshes)
        lines += sites.get(name, [])
        text = f"{head}>\n" + "".join(f"{pad}  {line}\n" for line in lines)
        for child in children.get(name, []):
            text += body(child.child, depth + 1, child)
        return text + f"{pad}</body>\n"

    return body(document.root_link, 2, None)


@dataclass(frozen=True)
class _Settings:
    """:func:`emit_mjcf`'s options, checked (``balance``: the compiler's ``balanceinertia``)."""

    moving_base: bool
    gravity: Array
    rate: float
    folder: Path | None
    tool_frame: str | None
    balance: bool
    joints: dict[str, str]
    comment: str


def _write(
    document: UrdfDocument, imu_mounts: Sequence[ImuMount], settings: _Settings
) -> tuple[str, tuple[str, ...]]:
    """The MJCF text and the mesh files left out."""
    meshes = MeshAssets(settings.folder)
    sites = link_sites(document, imu_mounts, settings.tool_frame)
    tree = _worldbody(document, sites, settings, meshes)
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
        f' polycoef="{exact_number(joint.mimic[2])} {exact_number(joint.mimic[1])} 0 0 0"/>\n'
        for joint in document.joints
        if joint.mimic is not None
    )
    text = (
        f"<mujoco model={quoteattr(document.name)}>\n"
        "  <!-- written by aaria_pin from the URDF; a body per link, a site, a gyro and an"
        " accelerometer per IMU -->\n"
        + settings.comment
        + '  <compiler angle="radian" inertiafromgeom="false" autolimits="true"'
        f' balanceinertia="{str(settings.balance).lower()}"/>\n'
        f'  <option timestep="{exact_number(1.0 / settings.rate)}"'
        f' gravity="{exact_numbers(settings.gravity)}"/>\n'
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


def _mujoco_installed() -> bool:
    from importlib.util import find_spec

    return find_spec("mujoco") is not None


class MjcfOptions(TypedDict, total=False):
    """The options of :func:`emit_mjcf` (every key optional; defaults below).

    Attributes:
        moving_base: the root link on the 6-DOF chain :data:`BASE_JOINTS`; else fixed at the
            world origin (default True)
        gravity: gravity in the world [m/s²] (default :data:`~aaria_pin.core.model.GRAVITY`)
        rate: sample rate [Hz]; the timestep is ``1/rate`` [s] (default
            :data:`~aaria_pin.core.trajectory.DEFAULT_RATE`)
        urdf_dir: the URDF's folder, for relative mesh paths
        tool_frame: a link or joint to mark with a site of its name (no sensor), or None
        balance_inertia: let MuJoCo raise principal moments that break ``A + B >= C``
            (compiler ``balanceinertia``), which it otherwise refuses for some links (PR2's
            ``sensor_mount_link``); those links' dynamics then differ from the URDF's.
            ``"auto"``: compile the model (when ``mujoco`` is installed) and only if MuJoCo
            refuses such an inertia write it balanced, with a warning naming the link
            (default False)
        actuator: the joints' motors (:mod:`~aaria_pin.core.export.mjcf_actuators`: each
            joint's ``armature``, ``damping``, ``frictionloss`` and force range, and a comment
            naming the terms MuJoCo has none for); None (default): none, the joints'
            ``<default>`` zeros
        joint_names: the joints ``actuator``'s per-joint values belong to, in their order (a
            run's record columns; default the URDF's joints that are not fixed, in document
            order)
    """

    moving_base: bool
    gravity: Sequence[float] | Array
    rate: float
    urdf_dir: str | os.PathLike[str] | None
    tool_frame: str | None
    balance_inertia: BalanceInertia
    actuator: ActuatorModel | None
    joint_names: Sequence[str] | None


@checked
def emit_mjcf(
    urdf: str, imu_mounts: Sequence[ImuMount], **options: Unpack[MjcfOptions]
) -> tuple[str, tuple[str, ...]]:
    """The MJCF of a URDF robot with a site, a gyro and an accelerometer per IMU.

    Args:
        urdf: the URDF text (parsed and checked by :func:`~aaria_pin.core.urdf_parse.parse_urdf`)
        imu_mounts: the IMUs, in record order (an empty slot, parent ``""``, gets none)
        **options: the base, gravity, rate, mesh folder, tool frame, inertia balancing and
            actuators (:class:`MjcfOptions`)

    Returns:
        The MJCF text, and the mesh files that were left out (not STL or OBJ, or not found).

    Raises:
        UrdfError: the URDF check fails.
        ModelError: an IMU's parent or the tool frame is not in the URDF, or a name of
            :data:`BASE_JOINTS` is a joint of the URDF; with ``"auto"``, MuJoCo cannot compile
            the model for another reason.
        ParameterError: a rate outside ``(0, MAX_RATE]``
            (:func:`~aaria_pin.core.trajectory.check_rate`), gravity not 3 numbers, or an
            actuator's per-joint values not one per joint of ``joint_names``.
    """
    moving_base = options.get("moving_base", True)
    gravity = options.get("gravity", GRAVITY)
    rate = options.get("rate", DEFAULT_RATE)
    urdf_dir, tool_frame = options.get("urdf_dir"), options.get("tool_frame")
    balance_inertia = options.get("balance_inertia", False)
    check_rate(rate)
    gravity_vector = np.asarray(gravity, dtype=float)
    if gravity_vector.shape != (3,) or not np.all(np.isfinite(gravity_vector)):
        raise ParameterError(parameter="gravity", value=gravity, allowed="3 finite numbers")
    if balance_inertia not in (True, False, "auto"):
        raise ParameterError(
            parameter="balance_inertia", value=balance_inertia, allowed='True, False or "auto"'
        )
    document = parse_urdf(urdf)
    clash = sorted({joint.name for joint in document.joints} & set(BASE_JOINTS))
    if moving_base and clash:
        raise ModelError(
            f"URDF joint {clash[0]!r} has the name of a base joint; allowed: names other than "
            + ", ".join(BASE_JOINTS),
            parameter="urdf",
            element=clash[0],
        )
    folder = None if urdf_dir is None else Path(urdf_dir)
    actuator = options.get("actuator")
    joints: dict[str, str] = {}
    comment = ""
    if actuator is not None:
        names = options.get("joint_names")
        if names is None:
            names = [joint.name for joint in document.joints if joint.kind != "fixed"]
        joints = joint_actuator_attributes(actuator, names, document)
        comment = f"  {actuator_comment(actuator)}\n"
    settings = _Settings(
        moving_base,
        gravity_vector,
        rate,
        folder,
        tool_frame,
        balance_inertia is True,
        joints,
        comment,
    )
    text, skipped = _write(document, imu_mounts, settings)
    if balance_inertia != "auto" or not _mujoco_installed():
        return text, skipped
    try:
        load_mjcf(text)
    except ModelError as exc:
        if _UNBALANCED not in str(exc):
            raise
        text, skipped = _write(document, imu_mounts, replace(settings, balance=True))
        load_mjcf(text)
        links = str(exc).partition("Element name ")[2] or str(exc)
        warnings.warn(
            "MuJoCo refuses inertias of this URDF whose principal moments break A + B >= C "
            f'({links}); written with balanceinertia="true", which raises them: those '
            "links' dynamics differ from the URDF's",
            UserWarning,
            stacklevel=2,
        )
    return text, skipped


def load_mjcf(xml: str) -> mujoco.MjModel:
    """Compile MJCF text with MuJoCo (imported here: the optional ``mujoco`` extra).

    Raises:
        ModelError: MuJoCo cannot compile it (its message, on one line).
    """
    import mujoco

    try:
        return mujoco.MjModel.from_xml_string(xml)
    except ValueError as exc:
        raise ModelError(
            f"MuJoCo cannot compile the MJCF: {' '.join(str(exc).split())}", parameter="xml"
        ) from None
