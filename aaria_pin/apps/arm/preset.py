"""The ``pick-place-arm`` preset: the robotic-arm report's arm as meshes, a URDF and a model.

The report (Tschupp & Studer, "Robotic Arm Simulation", 2016) builds its arm of five pieces in
OpenSCAD: a pillar (no motion), an upper arm (moves along z), a forearm (turns about z), a hand
with two fingers (turns about all three axes) and a separate finger that squeezes (slides).
Its IK (section 4.2.8) treats the arm as two links turning about vertical axes, of lengths A
(upper arm) and B (forearm). This preset is that arm:

``pillar`` (root, fixed to the floor) —``lift`` (prismatic, z)→ ``carriage`` (a collar on the
pillar) —``shoulder`` (revolute, z, about the pillar's axis)→ ``upper_arm`` (length A)
—``elbow`` (revolute, z)→ ``forearm`` (length B) —``hand_yaw`` (z), ``hand_pitch`` (y),
``hand_roll`` (z)→ ``hand`` (the report's ZYZ hand; the three axes meet at the wrist centre)
—``finger`` (prismatic, along the hand's x: the gap to the two fixed fingers)→
``sliding_finger``; a
massless frame ``grasp`` on the hand marks a gripped cylinder's centre (for a cylinder of the
radius and height given, :data:`DEFAULT_GRASP` by default).

**Dimensions.** The report's text gives no dimension (its OpenSCAD files are not in it), so
every number of :class:`~aaria_pin.apps.arm.dims.ArmDimensions` (in :mod:`aaria_pin.apps.arm.dims`,
with where a gripped cylinder sits in the hand) is chosen, to be of the size the report's pictures
suggest (a table-top arm) and consistent with its IK: the forearm is shorter than the upper
arm (A = 0.40 m > B = 0.30 m), so folding it back leaves the hand outside the pillar and the
reachable annulus is 0.10–0.70 m. Densities are chosen too: aluminium (2700 kg/m³) for every
moving part, steel (7850 kg/m³) for the pillar and its foot.

**Meshes.** Each link's mesh is generated with trimesh (:mod:`aaria_pin.apps.arm.parts`), in the
link frame; the URDF references ``meshes/<link>.stl`` relative to itself, and
:func:`write_arm_urdf` writes the URDF and its STL files together (``aaria arm urdf -o DIR``).
The files are made at run time, not shipped: they follow the dimensions, and a model built by
:func:`build_arm_model` needs no file at all (mass properties come from the meshes in memory).
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from aaria_pin.apps.arm.dims import (
    ARM_PRESETS,
    PALM_FACE,
    ArmDimensions,
    get_arm_preset,
    grasp_offset,
)
from aaria_pin.apps.arm.parts import (
    MeshPart,
    box_mesh,
    combine,
    cylinder_mesh,
    export_stl,
    ring_mesh,
    stadium_mesh,
)
from aaria_pin.core.se3 import rot_x, translation
from aaria_pin.core.urdf import (
    JointDescription,
    LinkDescription,
    Material,
    Mesh,
    RobotDescription,
    Shape,
)
from aaria_pin.core.urdf_emitter import emit_urdf

if TYPE_CHECKING:
    from aaria_pin.core.model import RobotModel

__all__ = [
    "ARM_JOINTS",
    "ARM_PRESETS",
    "DEFAULT_GRASP",
    "PALM_FACE",
    "ArmDimensions",
    "arm_description",
    "arm_joints",
    "arm_parts",
    "arm_urdf",
    "build_arm_model",
    "get_arm_preset",
    "grasp_offset",
    "write_arm_urdf",
]

_STEEL = 7850.0

DEFAULT_GRASP = (0.03, 0.12)
"""Radius and height of the cylinder whose grasp point frame ``grasp`` marks by default [m]."""


def arm_parts(dims: ArmDimensions) -> dict[str, MeshPart]:
    """Each link's mesh (in its link frame), density and colour, by link name."""
    d = dims
    r, w, foot = d.pillar_radius, 0.06, d.foot_thickness
    face, t = d.finger_face, d.finger_thickness
    palm_x = (face - t, face + d.finger_travel + 2 * t)
    grey, blue, green, orange = (
        (0.55, 0.55, 0.58, 1.0),
        (0.2, 0.35, 0.85, 1.0),
        (0.13, 0.69, 0.30, 1.0),
        (0.95, 0.55, 0.1, 1.0),
    )
    pillar = combine(
        box_mesh((d.foot_size, d.foot_size, foot), (0.0, 0.0, foot / 2)),
        cylinder_mesh(r, d.pillar_height - foot, (0.0, 0.0, (foot + d.pillar_height) / 2)),
    )
    ring = ring_mesh(r + 0.002, r + 0.03, 0.04)
    bar = stadium_mesh(d.upper_arm - (r + 0.03 + w / 2), w, 0.04)
    bar.apply_translation((r + 0.03 + w / 2, 0.0, 0.0))
    upper = combine(ring, bar)
    half_gap = d.wrist_drop - 0.02  # forearm's lower face to the wrist centre
    fingers = [
        box_mesh((t, t, d.finger_length), (face - t / 2, y, PALM_FACE + d.finger_length / 2))
        for y in (-0.02, 0.02)
    ]
    parts = {
        "pillar": MeshPart("pillar", pillar, _STEEL, grey),
        "carriage": MeshPart("carriage", ring_mesh(r + 0.002, r + 0.03, 0.06), d.density, green),
        "upper_arm": MeshPart("upper_arm", upper, d.density, blue),
        "forearm": MeshPart("forearm", stadium_mesh(d.forearm, 0.05, 0.04), d.density, blue),
        "hand_yaw_link": MeshPart(
            "hand_yaw_link",
            cylinder_mesh(0.025, half_gap, (0.0, 0.0, -half_gap / 2)),
            d.density,
            green,
        ),
        "hand_pitch_link": MeshPart(
            "hand_pitch_link", box_mesh((0.03, 0.05, 0.03)), d.density, green
        ),
        "hand": MeshPart(
            "hand",
            combine(
                box_mesh(
                    (palm_x[1] - palm_x[0], 0.06, 0.02), (sum(palm_x) / 2, 0.0, PALM_FACE - 0.01)
                ),
                *fingers,
            ),
            d.density,
            orange,
        ),
        "sliding_finger": MeshPart(
            "sliding_finger",
            box_mesh((t, 0.025, d.finger_length), (t / 2, 0.0, d.finger_length / 2)),
            d.density,
            orange,
        ),
    }
    return parts


def arm_joints(
    dims: ArmDimensions, grasp: tuple[float, float] = DEFAULT_GRASP
) -> tuple[JointDescription, ...]:
    """The joints: placements at q = 0, axes and limits (velocities chosen here).

    Args:
        dims: the arm
        grasp: radius and height of the gripped cylinder that places frame ``grasp`` [m]
    """
    d = dims
    turn = 2.0 * np.pi
    y_axis = (0.0, 1.0, 0.0)
    return (
        JointDescription(
            "lift",
            "prismatic",
            "pillar",
            "carriage",
            np.eye(4),
            lower=d.lift_range[0],
            upper=d.lift_range[1],
            effort=500.0,
            velocity=0.2,
        ),
        JointDescription(
            "shoulder",
            "revolute",
            "carriage",
            "upper_arm",
            translation(z=-d.shoulder_drop),
            lower=-turn,
            upper=turn,
            effort=100.0,
            velocity=1.5,
        ),
        JointDescription(
            "elbow",
            "revolute",
            "upper_arm",
            "forearm",
            translation(d.upper_arm, 0.0, -d.elbow_drop),
            lower=-np.pi,
            upper=np.pi,
            effort=50.0,
            velocity=1.5,
        ),
        JointDescription(
            "hand_yaw",
            "revolute",
            "forearm",
            "hand_yaw_link",
            translation(d.forearm, 0.0, -d.wrist_drop) @ rot_x(np.pi),
            lower=-turn,
            upper=turn,
            effort=10.0,
            velocity=2.0,
        ),
        JointDescription(
            "hand_pitch",
            "revolute",
            "hand_yaw_link",
            "hand_pitch_link",
            np.eye(4),
            axis=y_axis,
            lower=-np.pi,
            upper=np.pi,
            effort=10.0,
            velocity=2.0,
        ),
        JointDescription(
            "hand_roll",
            "revolute",
            "hand_pitch_link",
            "hand",
            np.eye(4),
            lower=-turn,
            upper=turn,
            effort=10.0,
            velocity=2.0,
        ),
        JointDescription(
            "finger",
            "prismatic",
            "hand",
            "sliding_finger",
            translation(d.finger_face, 0.0, PALM_FACE),
            axis=(1.0, 0.0, 0.0),
            lower=0.0,
            upper=d.finger_travel,
            effort=50.0,
            velocity=0.05,
        ),
        JointDescription("grasp_mount", "fixed", "hand", "grasp", grasp_offset(dims, *grasp)),
    )


ARM_JOINTS = tuple(j.name for j in arm_joints(ArmDimensions()) if j.kind != "fixed")
"""The actuated joints, in model order."""


def arm_description(
    dims: ArmDimensions,
    mesh_folder: str = "meshes",
    grasp: tuple[float, float] = DEFAULT_GRASP,
    parts: Mapping[str, MeshPart] | None = None,
) -> RobotDescription:
    """The arm as a robot description: mesh links with their mass properties, and the joints.

    Each link's visual and collision shape is its mesh ``<mesh_folder>/<link>.stl`` (in the link
    frame, coloured ``<link>_colour``); its mass properties are the mesh's and its density's.
    The frame ``grasp`` is a massless link.

    Args:
        dims: the arm
        mesh_folder: the meshes' folder, relative to the URDF
        grasp: radius and height of the gripped cylinder that places frame ``grasp`` [m]
        parts: the arm's parts, :func:`arm_parts` of ``dims`` (made if not given)
    """
    parts = arm_parts(dims) if parts is None else parts
    links = [
        LinkDescription(
            name,
            mass_properties=part.inertia(),
            shapes=(
                Shape(
                    Mesh(f"{mesh_folder}/{name}.stl"),
                    material=Material(f"{name}_colour", part.rgba),
                    name=f"{name}_mesh",
                ),
            ),
        )
        for name, part in parts.items()
    ]
    links.append(LinkDescription("grasp"))
    return RobotDescription(
        "pick_place_arm",
        tuple(links),
        arm_joints(dims, grasp),
        comment="pick-place-arm of aaria_pin (robotic-arm report); meshes by trimesh",
        materials=(),
    )


def arm_urdf(
    dims: ArmDimensions,
    mesh_folder: str = "meshes",
    grasp: tuple[float, float] = DEFAULT_GRASP,
    parts: Mapping[str, MeshPart] | None = None,
) -> str:
    """URDF text of the arm: :func:`arm_description` (same arguments) by the core emitter."""
    return emit_urdf(arm_description(dims, mesh_folder, grasp, parts))


def write_arm_urdf(
    folder: str | os.PathLike[str],
    dims: ArmDimensions,
    grasp: tuple[float, float] = DEFAULT_GRASP,
    parts: Mapping[str, MeshPart] | None = None,
) -> Path:
    """Write ``folder/pick_place_arm.urdf`` and ``folder/meshes/<link>.stl``.

    Args:
        folder: the output folder (made if missing)
        dims: the arm
        grasp: radius and height of the gripped cylinder that places frame ``grasp`` [m]
        parts: the arm's parts, :func:`arm_parts` of ``dims`` (made if not given)

    Returns:
        The URDF's path.
    """
    from aaria_pin.errors import OutputFileError
    from aaria_pin.files.io import write_text_atomic
    from aaria_pin.files.paths import check_name_lengths

    root = Path(folder)
    meshes = root / "meshes"
    check_name_lengths(root / "pick_place_arm.urdf")  # a name too long: before any folder
    made = [p for p in (root, meshes) if not p.exists()]  # outermost first
    try:
        meshes.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputFileError(
            f"{root}: cannot make the folder ({exc.strerror})", parameter="folder", value=root
        ) from None
    parts = arm_parts(dims) if parts is None else parts
    urdf = root / "pick_place_arm.urdf"
    written: list[Path] = []
    try:
        for name, part in parts.items():
            target = meshes / f"{name}.stl"
            new = not target.exists()
            export_stl(part.mesh, target)  # atomic: an existing mesh is replaced only whole
            if new:
                written.append(target)
        write_text_atomic(urdf, arm_urdf(dims, grasp=grasp, parts=parts))
    except BaseException:  # a full disk half-way: no partial set of new files is left
        for path in written:
            path.unlink(missing_ok=True)
        for path in reversed(made):
            with contextlib.suppress(OSError):
                path.rmdir()  # only if now empty
        raise
    return urdf


def build_arm_model(
    dims: ArmDimensions,
    grasp: tuple[float, float] = DEFAULT_GRASP,
    *,
    free_flyer: bool = False,
    urdf: str | None = None,
) -> RobotModel:
    """The arm as a robot model (no mesh file needed): base frame ``pillar``, tool ``grasp``.

    Args:
        dims: the arm
        grasp: radius and height of the gripped cylinder that places frame ``grasp`` [m]
        free_flyer: root the pillar on a free-flyer joint (held still, its generalized force is
            the wrench of the pillar's mount), instead of fixing it to the world
        urdf: the arm's URDF text, :func:`arm_urdf` of ``dims`` and ``grasp`` (made if not
            given)

    Raises:
        ModelError: a URDF that cannot be built.
    """
    from aaria_pin.core.model import build_model

    return build_model(
        arm_urdf(dims, grasp=grasp) if urdf is None else urdf,
        moving_base=free_flyer,
        base_frame="pillar",
        tool_frame="grasp",
        sensor_frames=(),
    )
