"""Pick-place runs and the pick-place arm for the viewers: the arm's own part meshes.

``aaria render``, ``aaria plot`` and ``aaria view`` read runs through run kinds
(:func:`aaria_pin.viz.sources.register_run_kind`). A pick-place run is a run of a URDF robot,
which the ``"model"`` kind would draw as a stick figure; this module is the ``"pick-place"``
kind: :func:`is_pick_place_run` recognises the run (its record's ``kind`` is ``"pick-place"``,
or, in a file of 0.1.0, its ``robot`` is ``"pick_place_arm"``; a ``task`` attribute, where
there is one, is ``"pick-place"``) and :func:`load_pick_place_view` builds a
:class:`~aaria_pin.viz.sources.RunView` whose scene holds every link's mesh
(:func:`aaria_pin.apps.arm.preset.arm_parts`, the same trimesh parts as the URDF's STL files)
attached to its link frame, and the cylinder attached to a frame ``cylinder`` that follows the
grasp frame while it is held and stands on its pick spot before, on its place spot after
(:func:`aaria_pin.apps.arm.run.cylinder_track`). The rest (the record, the model built from its
URDF, the signals and the frame poses) is the ``"model"`` kind's
(:func:`aaria_pin.viz._model_source.read_model_view`). :data:`PRESETS` gives
``aaria render --preset pick-place-arm``: the arm at its home pose.

**Plug-in.** The viz package imports this module (its ``_PLUGINS``) the first time it looks up
a run kind or a preset, so ``import aaria_pin`` never loads it; on import it registers the
kind, which is tried before the ``"model"`` fallback.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from typing import Any

import numpy as np

from aaria_pin.apps.arm.dims import ArmDimensions, get_arm_preset
from aaria_pin.apps.arm.parts import MeshPart, cylinder_mesh
from aaria_pin.apps.arm.preset import arm_parts, build_arm_model
from aaria_pin.apps.arm.run import cylinder_track
from aaria_pin.apps.arm.stored_task import PICK_PLACE_KIND, is_pick_place, stored_task
from aaria_pin.apps.arm.task import home_pose
from aaria_pin.core.se3 import Array
from aaria_pin.errors import InputFileError
from aaria_pin.viz._model_source import read_model_view
from aaria_pin.viz._run_view import run_file, run_title, scene_poses, still
from aaria_pin.viz.scene import WORLD, Scene, Solid, triad
from aaria_pin.viz.sources import RunView, register_run_kind

__all__ = [
    "CYLINDER_FRAME",
    "PART_ROLES",
    "PICK_PLACE_KIND",
    "PRESETS",
    "arm_scene",
    "is_pick_place_run",
    "load_pick_place_view",
    "preset_scene",
]

CYLINDER_FRAME = "cylinder"
"""The scene frame the cylinder's solid is attached to (its centre, axis along z)."""

PART_ROLES = {
    "pillar": "other",
    "carriage": "joint",
    "upper_arm": "link",
    "forearm": "link",
    "hand_yaw_link": "joint",
    "hand_pitch_link": "joint",
    "hand": "link",
    "sliding_finger": "link",
}
"""Drawing role (a key of :data:`aaria_pin.viz.scene.COLOURS`) of each link's mesh."""

_CYLINDER_ROLE = "dh_frame"  # drawn red


def is_pick_place_run(path: str | os.PathLike[str]) -> bool:
    """Whether ``path`` holds a pick-place run (never raises on a file that is not a run).

    Args:
        path: the file, or its :class:`~aaria_pin.viz.sources.RunFile` (read once by the viewers)
    """
    try:
        record = run_file(path).record
    except InputFileError:
        return False
    if record is None:
        return False
    return is_pick_place(record.metadata)


def _solid(frame: str, mesh: Any, role: str) -> Solid:
    faces = np.asarray(mesh.faces, dtype=int)
    quads = np.column_stack([faces, faces[:, 2]])  # a triangle repeats its last vertex
    return Solid(frame, np.asarray(mesh.vertices, dtype=float), quads, role)


def arm_scene(
    dims: ArmDimensions,
    cylinder: tuple[float, float] | None = None,
    parts: Mapping[str, MeshPart] | None = None,
) -> Scene:
    """The arm's scene: its part meshes on their links, frames world and ``grasp``.

    Args:
        dims: the arm
        cylinder: radius and height of a cylinder to draw on frame :data:`CYLINDER_FRAME`
            (the last frame) [m], or None
        parts: the arm's parts, :func:`arm_parts` of ``dims`` (made if not given)

    Returns:
        The scene; its frames are the world, the links in :func:`arm_parts` order, ``grasp``,
        then the cylinder's frame if any.
    """
    parts = arm_parts(dims) if parts is None else parts
    solids = [_solid(name, p.mesh, PART_ROLES.get(name, "other")) for name, p in parts.items()]
    frames = [WORLD, *parts, "grasp"]
    if cylinder is not None:
        drum = cylinder_mesh(cylinder[0], cylinder[1], sections=24)
        solids.append(_solid(CYLINDER_FRAME, drum, _CYLINDER_ROLE))
        frames.append(CYLINDER_FRAME)
    size = 0.1 * (dims.upper_arm + dims.forearm)
    lines = (triad(WORLD, size, "world_frame", width=3.0), triad("grasp", 0.5 * size, "tool_frame"))
    return Scene("pick_place_arm", tuple(frames), tuple(solids), lines)


def preset_scene(name: str = "pick-place-arm") -> tuple[Scene, Array]:
    """An arm preset at its home pose (:func:`aaria_pin.apps.arm.task.home_pose`), no cylinder.

    Returns:
        The scene (:func:`arm_scene`) and the (F, 4, 4) world pose of each of its frames [m].

    Raises:
        ParameterError: an unknown preset.
    """
    from aaria_pin.core.trajectory import BaseMotion

    dims = get_arm_preset(name)
    scene = arm_scene(dims)
    robot = build_arm_model(dims)
    return scene, scene_poses(robot, scene, BaseMotion.resting(1), still(home_pose(dims)[None]))[0]


PRESETS = {"pick-place-arm": preset_scene}
"""Model presets for ``aaria render --preset``: name → builder of the scene and its poses."""


def load_pick_place_view(path: str | os.PathLike[str]) -> RunView:
    """Read a pick-place run file for drawing.

    Returns:
        A run view of kind :data:`PICK_PLACE_KIND`: the arm's part meshes on their links, the
        cylinder, the world and grasp frames; signals as the ``"model"`` kind's
        (:func:`aaria_pin.viz._model_source.read_model_view`: q, tau labelled by joint,
        with units, and the mount's wrench).

    Raises:
        InputFileError: not a pick-place run file, or attributes that cannot be used.
    """
    if not is_pick_place_run(path):
        raise InputFileError(
            f"{os.fspath(path)}: not a pick-place run file; allowed: a run file of aaria arm"
            " pick-place",
            parameter="run",
        )
    return _load(path)


def _load(file: str | os.PathLike[str]) -> RunView:
    """Read a file known to be a pick-place run file (the registered loader: no re-probe)."""
    view = read_model_view(file)
    try:
        task = stored_task(view.record)
    except InputFileError as exc:
        raise InputFileError(f"{file}: {exc}", parameter="file") from None
    if task is None:  # the loader of pick-place runs: the probe said it is one
        raise InputFileError(f"{file}: not a pick-place run", parameter="run")
    c = task.cylinder
    scene = arm_scene(task.dims, (c.radius, c.height))
    time = view.signals.time
    held = (time >= task.held[0]) & (time < task.held[1])
    cylinder = cylinder_track(held, (c.x, c.y), task.place, c.height, view.record.tool_pose)
    linked = view.poser(scene.frames[1:-1])  # the links and the grasp frame

    def frame_poses(samples: Array) -> Array:
        index = np.asarray(samples, dtype=int)
        out = np.empty((index.size, len(scene.frames), 4, 4))
        out[:, 0] = np.eye(4)
        out[:, 1:-1] = linked(index)
        out[:, -1] = cylinder[index]
        return out

    return RunView(run_title(file), PICK_PLACE_KIND, scene, view.signals, frame_poses)


register_run_kind(PICK_PLACE_KIND, is_pick_place_run, _load)
