"""What a picture of an arm holds: solids, lines and frames fixed to named frames.

A :class:`Scene` lists the frames it needs (``scene.frames``: ``"world"`` first, then frames of
the Pinocchio model) and the things drawn on them, each in its frame's coordinates [m]:

- :class:`Solid` — a mesh of flat faces (boxes, cylinders), e.g. a link's box;
- :class:`Lines` — line segments, e.g. the three axes of a coordinate frame (a triad);
- :class:`Bone` — a segment from one frame's origin to another's (for robots described without
  solids, such as a URDF robot without meshes: links drawn as segments between joint origins).

:func:`posed_geometry` places everything with one pose per frame and returns plain arrays
(world faces, lines and their roles), which the PNG renderer and the HTML viewer draw alike.
Builders: :func:`scene_from_description` (solids of a robot description, the roles of its parts
giving the colours), :func:`scene_from_dh_robot` (adds the paper's frames: world green, DH red at
each link's end, tool tip yellow, IMUs small and purple) and :func:`scene_from_model` (any
Pinocchio model: bones between joint origins, joints as green cylinders).

Colours follow the paper (section IV): revolute joints green cylinders, prismatic joints green
rods, links and tool blue boxes, DH frames red, the world frame green, the tool frame yellow,
sensors purple.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike

from aaria_pin.aaria.dh_robot import DHRobot, link_name
from aaria_pin.core.model import RobotModel
from aaria_pin.core.se3 import Array
from aaria_pin.core.urdf import RobotDescription

__all__ = [
    "AXIS_COLOURS",
    "COLOURS",
    "PART_ROLES",
    "ROLE_LABELS",
    "WORLD",
    "Bone",
    "Lines",
    "PosedGeometry",
    "Scene",
    "Solid",
    "box_solid",
    "cylinder_solid",
    "mesh_solid",
    "one_axis_joint",
    "posed_geometry",
    "scene_from_description",
    "scene_from_dh_robot",
    "scene_from_model",
    "triad",
]

WORLD = "world"
"""Name of the world frame in a scene (its pose is always the identity)."""

COLOURS: dict[str, tuple[float, float, float]] = {
    "joint": (0.10, 0.70, 0.15),
    "link": (0.15, 0.35, 0.90),
    "dh_frame": (0.90, 0.05, 0.05),
    "world_frame": (0.05, 0.75, 0.10),
    "tool_frame": (1.00, 0.85, 0.00),
    "imu_frame": (0.60, 0.15, 0.80),
    "bone": (0.15, 0.35, 0.90),
    "other": (0.55, 0.55, 0.55),
}
"""RGB colour (0–1) of each drawing role."""

ROLE_LABELS = (
    ("joint", "joints"),
    ("link", "links, tool"),
    ("dh_frame", "DH frames"),
    ("world_frame", "world frame"),
    ("tool_frame", "tool frame"),
    ("imu_frame", "IMUs"),
)
"""Legend label of each drawing role, in legend order."""

AXIS_COLOURS = ((0.85, 0.10, 0.10), (0.10, 0.65, 0.10), (0.10, 0.25, 0.90))
"""RGB colour (0–1) of a frame's x, y and z axes (RGB = xyz)."""

PART_ROLES = {
    "housing": "joint",
    "rail": "joint",
    "slider": "joint",
    "link": "link",
    "tool": "link",
}
"""Drawing role of each body part role of :class:`~aaria_pin.core.inertia.Part`."""

_CYLINDER_SIDES = 16


@dataclass(frozen=True)
class Solid:
    """A mesh of flat faces fixed to a frame.

    Attributes:
        frame: the frame it is fixed to
        vertices: (V, 3) vertices in the frame [m]
        faces: (F, 4) vertex indices of each face (a triangle repeats its last vertex)
        role: drawing role, a key of :data:`COLOURS`
        colour: its own RGB colour (0–1), e.g. a URDF material's; None: the role's
    """

    frame: str
    vertices: Array
    faces: Array
    role: str
    colour: tuple[float, float, float] | None = None

    @property
    def rgb(self) -> tuple[float, float, float]:
        """The colour it is drawn in: its own, else its role's."""
        return self.colour or COLOURS.get(self.role, COLOURS["other"])

    def triangles(self) -> Array:
        """(K, 3) vertex indices of its faces cut into triangles (a quad gives two)."""
        faces = np.asarray(self.faces, dtype=np.int64)
        second = faces[faces[:, 3] != faces[:, 2]][:, [0, 2, 3]]
        return np.concatenate([faces[:, :3], second])


@dataclass(frozen=True)
class Lines:
    """Line segments fixed to a frame.

    Attributes:
        frame: the frame they are fixed to
        points: (L, 2, 3) segment end points in the frame [m]
        role: drawing role, a key of :data:`COLOURS`
        width: line width [px]
        axes: the three segments are a frame's x, y, z axes, drawn red, green, blue
            (:data:`AXIS_COLOURS`); the role's colour marks the frame's origin
    """

    frame: str
    points: Array
    role: str
    width: float = 2.0
    axes: bool = False

    def colours(self) -> Array:
        """(L, 3) RGB of each segment: x, y, z axes red, green, blue, else the role's."""
        if self.axes:
            return np.asarray(AXIS_COLOURS)[np.arange(len(self.points)) % 3]
        return np.broadcast_to(COLOURS.get(self.role, COLOURS["other"]), (len(self.points), 3))


@dataclass(frozen=True)
class Bone:
    """A segment from the origin of one frame to the origin of another."""

    frame_a: str
    frame_b: str
    role: str = "bone"
    width: float = 4.0


@dataclass(frozen=True)
class Scene:
    """Everything drawn for one robot, and the frames it needs.

    Attributes:
        name: the robot's name
        frames: frame names, ``"world"`` first; poses are given in this order
        solids: meshes
        lines: line sets (frames' axes)
        bones: segments between frame origins
    """

    name: str
    frames: tuple[str, ...]
    solids: tuple[Solid, ...] = ()
    lines: tuple[Lines, ...] = ()
    bones: tuple[Bone, ...] = ()

    @property
    def model_frames(self) -> tuple[str, ...]:
        """The frames whose poses come from the model (all but the world)."""
        return self.frames[1:]


@dataclass(frozen=True)
class PosedGeometry:
    """A scene placed in the world: plain arrays, independent of any plotting library.

    Attributes:
        faces: (N, 4, 3) face corners in the world [m]
        face_roles: (N,) drawing role of each face
        segments: (M, 2, 3) line segments in the world [m] (lines and bones)
        segment_roles: (M,) drawing role of each segment
        segment_widths: (M,) line width of each segment [px]
        face_rgb: (N, 3) colour (0–1) of each face (its solid's own, else its role's); None:
            the roles' colours
        segment_rgb: (M, 3) colour (0–1) of each segment (frame axes RGB = xyz); None: the
            roles' colours
        origins: (P, 3) origin of each frame drawn as axes [m]
        origin_roles: (P,) drawing role of each (its colour marks the origin)
    """

    faces: Array
    face_roles: tuple[str, ...]
    segments: Array
    segment_roles: tuple[str, ...]
    segment_widths: Array
    face_rgb: Array | None = None
    segment_rgb: Array | None = None
    origins: Array | None = None
    origin_roles: tuple[str, ...] = ()

    def bounds(self) -> Array:
        """(2, 3) lower and upper corner of everything drawn [m]."""
        points = np.concatenate([self.faces.reshape(-1, 3), self.segments.reshape(-1, 3)])
        if points.size == 0:
            return np.array([[-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]])
        return np.array([points.min(axis=0), points.max(axis=0)])


def box_solid(frame: str, T_frame_box: Array, size: Sequence[float], role: str) -> Solid:
    """A box centred on ``T_frame_box`` with edge lengths ``size`` (x, y, z) [m]."""
    half = np.asarray(size, dtype=float) / 2.0
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    local = corners * half
    vertices = local @ T_frame_box[:3, :3].T + T_frame_box[:3, 3]
    faces = np.array(
        [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    )
    return Solid(frame, vertices, faces, role)


def cylinder_solid(
    frame: str, T_frame_cylinder: Array, radius: float, length: float, role: str
) -> Solid:
    """A cylinder along the z axis of ``T_frame_cylinder``, centred on its origin [m]."""
    n = _CYLINDER_SIDES
    angle = 2.0 * np.pi * np.arange(n) / n
    ring = np.column_stack([radius * np.cos(angle), radius * np.sin(angle)])
    local = np.concatenate(
        [
            np.column_stack([ring, np.full(n, -length / 2.0)]),
            np.column_stack([ring, np.full(n, length / 2.0)]),
            [[0.0, 0.0, -length / 2.0], [0.0, 0.0, length / 2.0]],
        ]
    )
    vertices = local @ T_frame_cylinder[:3, :3].T + T_frame_cylinder[:3, 3]
    k = np.arange(n)
    k1 = (k + 1) % n
    sides = np.column_stack([k, k1, n + k1, n + k])
    bottom = np.column_stack([np.full(n, 2 * n), k1, k, k])
    top = np.column_stack([np.full(n, 2 * n + 1), n + k, n + k1, n + k1])
    return Solid(frame, vertices, np.concatenate([sides, bottom, top]), role)


def mesh_solid(
    frame: str,
    T_frame_mesh: Array,
    vertices: ArrayLike,
    triangles: ArrayLike,
    role: str,
    colour: tuple[float, float, float] | None = None,
) -> Solid:
    """A triangle mesh (vertices [m] in its own frame ``T_frame_mesh``) fixed to a frame."""
    placed = np.asarray(vertices, dtype=float) @ T_frame_mesh[:3, :3].T + T_frame_mesh[:3, 3]
    corners = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    return Solid(frame, placed, np.column_stack([corners, corners[:, 2]]), role, colour)


def triad(
    frame: str, length: float, role: str, T_frame_triad: Array | None = None, width: float = 2.0
) -> Lines:
    """The x, y, z axes of a coordinate frame as segments of ``length`` [m] from its origin.

    They are drawn red, green, blue (:data:`AXIS_COLOURS`); ``role`` colours the origin.
    """
    T = np.eye(4) if T_frame_triad is None else T_frame_triad
    origin = T[:3, 3]
    points = np.array([[origin, origin + length * T[:3, axis]] for axis in range(3)])
    return Lines(frame, points, role, width, axes=True)


def scene_from_description(description: RobotDescription, name: str | None = None) -> Scene:
    """Solids of every link's parts, fixed to the link's frame (no coordinate frames).

    Args:
        description: links (with solid parts) and joints
        name: scene name (default: the description's)

    Returns:
        The scene; part roles map to drawing roles by :data:`PART_ROLES`.
    """
    solids: list[Solid] = []
    frames = [WORLD]
    for link in description.links:
        for part in link.parts:
            role = PART_ROLES.get(part.role, "other")
            if part.shape == "box":
                solids.append(box_solid(link.name, part.T_body_part, part.dimensions, role))
            else:
                radius, length = part.dimensions
                solids.append(cylinder_solid(link.name, part.T_body_part, radius, length, role))
            if link.name not in frames:
                frames.append(link.name)
    return Scene(name or description.name, tuple(frames), tuple(solids))


def _reach(robot: DHRobot) -> float:
    """A length scale of the arm: the sum of its link, offset and tool lengths [m]."""
    lengths = [float(np.linalg.norm(robot.chain.T_base_entry[:3, 3]))]
    for joint in robot.chain.joints:
        lengths.append(float(np.linalg.norm(joint.link_end)))
        lengths.append(float(np.linalg.norm(joint.T_prev_joint[:3, 3])))
    lengths.append(robot.chain.tool_length)
    return max(sum(lengths), 0.1)


def scene_from_dh_robot(robot: DHRobot, name: str | None = None) -> Scene:
    """The paper's picture of a DH arm: its solids and its frames.

    Frames: the world (green, at the world origin), ``dh0`` and each link's end frame (red:
    the paper draws the DH frames at the end of each link, not on the joint), the tool tip
    (yellow), and every mounted IMU (purple, smaller). Frame axes are 8 % of the arm's reach
    (IMUs 3 %).

    Args:
        robot: the arm
        name: scene name (default: the robot's)

    Returns:
        The scene.
    """
    base = scene_from_description(robot.description, name)
    size = 0.08 * _reach(robot)
    frames = list(base.frames)
    lines = [triad(WORLD, 1.2 * size, "world_frame", width=3.0), triad("dh0", size, "dh_frame")]
    for joint in robot.chain.joints:
        lines.append(triad(link_name(joint.module), size, "dh_frame", joint.T_post_end))
    lines.append(triad("tool_tip", size, "tool_frame", width=3.0))
    for slot in robot.imu_slots:
        if slot.parent is not None:
            lines.append(triad(slot.name, 0.4 * size, "imu_frame", width=1.5))
    for item in lines:
        if item.frame not in frames:
            frames.append(item.frame)
    return Scene(base.name, tuple(frames), base.solids, tuple(lines))


def one_axis_joint(joint: pin.JointModel) -> tuple[str, Array] | None:
    """Kind and unit axis of a one-axis revolute or prismatic joint (bounded or not), else None.

    The kind is :func:`aaria_pin.core.kinematics.joint_kind`'s (exact Pinocchio type names: a
    planar joint is not prismatic); a free-flyer or any other joint gives None.
    """
    from aaria_pin.core.kinematics import joint_kind
    from aaria_pin.errors import ModelError

    try:
        kind, axis = joint_kind(joint)
    except ModelError:
        return None
    return (kind, axis) if kind in ("revolute", "prismatic") else None


def scene_from_model(robot: RobotModel, size: float = 0.05) -> Scene:
    """A stick figure of any Pinocchio model: bones between joint origins, green joints.

    For robots described without solids (a URDF robot without meshes): each joint is a green
    cylinder along its axis (revolute) or a thin green rod (prismatic), bones join each joint's
    origin to its parent joint's origin (a first joint to the base frame) and the tool frame to
    its joint, and the world, tool and sensor frames are drawn as in :func:`scene_from_dh_robot`.

    Args:
        robot: the model
        size: joint cylinder radius [m]; frame axes are 4 times it

    Returns:
        The scene.
    """
    model = robot.model
    frames = [WORLD]
    solids: list[Solid] = []
    bones: list[Bone] = []
    first = 2 if robot.moving_base else 1
    joint_frame = {j: str(model.names[j]) for j in range(first, model.njoints)}
    for j, frame in joint_frame.items():
        frames.append(frame)
        kind_axis = one_axis_joint(model.joints[j])
        if kind_axis is not None:
            kind, axis = kind_axis
            T = np.eye(4)
            z = axis / np.linalg.norm(axis)
            helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
            x = np.cross(helper, z)
            x /= np.linalg.norm(x)
            T[:3, 0], T[:3, 1], T[:3, 2] = x, np.cross(z, x), z
            prismatic = kind == "prismatic"
            radius, length = (size / 3.0, 6.0 * size) if prismatic else (size, 2.0 * size)
            solids.append(cylinder_solid(frame, T, radius, length, "joint"))
        parent = int(model.parents[j])
        if parent in joint_frame:
            bones.append(Bone(joint_frame[parent], frame))
        else:  # a first joint: from the base frame
            bones.append(Bone(robot.base_frame, frame))
    tool_parent = int(model.frames[robot.frame_id(robot.tool_frame)].parentJoint)
    frames += [robot.base_frame, robot.tool_frame]
    if tool_parent in joint_frame:
        bones.append(Bone(joint_frame[tool_parent], robot.tool_frame))
    lines = [
        triad(WORLD, 5.0 * size, "world_frame", width=3.0),
        triad(robot.tool_frame, 4.0 * size, "tool_frame", width=3.0),
    ]
    for sensor in robot.sensor_frames:
        frames.append(sensor)
        lines.append(triad(sensor, 1.6 * size, "imu_frame", width=1.5))
    unique = tuple(dict.fromkeys(frames))
    return Scene(str(model.name), unique, tuple(solids), tuple(lines), tuple(bones))


def posed_geometry(scene: Scene, poses: Array) -> PosedGeometry:
    """Place a scene with one pose per frame.

    Args:
        scene: the scene
        poses: (F, 4, 4) world pose of each frame of ``scene.frames`` (the world's included)

    Returns:
        Faces and segments in world coordinates [m].
    """
    index = {name: k for k, name in enumerate(scene.frames)}

    def place(frame: str, points: Array) -> Array:
        T = poses[index[frame]]
        return np.asarray(points @ T[:3, :3].T + T[:3, 3])

    faces = [place(s.frame, s.vertices)[s.faces] for s in scene.solids]
    face_roles = [s.role for s in scene.solids for _ in range(len(s.faces))]
    face_rgb = [np.broadcast_to(s.rgb, (len(s.faces), 3)) for s in scene.solids]
    segments = [
        place(item.frame, item.points.reshape(-1, 3)).reshape(-1, 2, 3) for item in scene.lines
    ]
    roles = [item.role for item in scene.lines for _ in range(len(item.points))]
    widths = [item.width for item in scene.lines for _ in range(len(item.points))]
    rgb = [item.colours() for item in scene.lines]
    axes = [item for item in scene.lines if item.axes]
    origins = [place(item.frame, item.points[0, 0][None])[0] for item in axes]
    for bone in scene.bones:
        a, b = poses[index[bone.frame_a]][:3, 3], poses[index[bone.frame_b]][:3, 3]
        segments.append(np.array([[a, b]]))
        roles.append(bone.role)
        widths.append(bone.width)
        rgb.append(np.array([COLOURS.get(bone.role, COLOURS["other"])]))
    return PosedGeometry(
        np.concatenate(faces) if faces else np.zeros((0, 4, 3)),
        tuple(face_roles),
        np.concatenate(segments) if segments else np.zeros((0, 2, 3)),
        tuple(roles),
        np.asarray(widths, dtype=float),
        np.concatenate(face_rgb) if face_rgb else np.zeros((0, 3)),
        np.concatenate(rgb) if rgb else np.zeros((0, 3)),
        np.array(origins).reshape(-1, 3),
        tuple(item.role for item in axes),
    )
