"""What the pictures show, from a preset, a DH table or a run file: a scene, frame poses, signals.

A DH table (a preset or a file) gives one pose: every joint at zero, the base at the world
origin. A run file gives the run: the arm rebuilt from the file, its frame poses over time
computed by Pinocchio from the stored joint values and base motion, and the stored signals.

**Run kinds.** :func:`run_kind` recognises a file and :func:`load_run_view` reads it with the
loader registered for its kind: ``"aaria"`` (``aaria simulate`` / data-set run files,
:mod:`~aaria_pin.viz._aaria_source`), ``"wrist"`` (``aaria wrist simulate``,
:mod:`~aaria_pin.viz._wrist_source`) and ``"generic"`` (the run file of any URDF robot, drawn
as a stick figure, :mod:`~aaria_pin.viz._generic_source`). Other kinds plug in with
:func:`register_run_kind`: a probe that recognises the file and a loader that returns a
:class:`RunView`. The generic kind is a fallback: it is tried after every other kind, so an
application's own kind of generic run file (the pick-and-place arm's) is recognised first.

**Plug-ins.** Applications register their kinds and presets without ``import aaria_pin``
importing them: the modules named in ``_PLUGINS`` (``aaria_pin.viz._arm_source``) are imported,
where they exist, the first time a run kind or a preset is looked up. A plug-in module

- calls :func:`register_run_kind` at import for each kind of run file it knows, and
- may define ``PRESETS: Mapping[str, Callable[[], tuple[Scene, Array]]]``: preset name → a
  builder taking no argument that returns the scene of the model (``scene.name`` is the
  picture's title) and the world pose of each of its frames at rest, ``(F, 4, 4)`` in the
  order of ``scene.frames`` (the world frame first, the identity). ``aaria render --preset``
  draws these beside the DH table presets (:func:`preset_view`).
"""

from __future__ import annotations

import importlib
import os
from collections.abc import Callable
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.aaria.dh import Convention
from aaria_pin.aaria.dh_robot import build_dh_robot
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion
from aaria_pin.errors import InputFileError, ModelError, ParameterError
from aaria_pin.viz._aaria_source import is_aaria_run, load_aaria_run
from aaria_pin.viz._generic_source import is_generic_run, load_generic_run
from aaria_pin.viz._run_view import RunFile, RunView, Signals, run_file, scene_poses, still
from aaria_pin.viz._wrist_source import is_wrist_run, load_wrist_run
from aaria_pin.viz.scene import Scene, scene_from_dh_robot

__all__ = [
    "PresetBuilder",
    "RunFile",
    "RunView",
    "Signals",
    "load_run_view",
    "preset_names",
    "preset_view",
    "register_run_kind",
    "run_kind",
    "sample_at",
    "table_view",
]

Probe = Callable[[RunFile], bool]
"""Whether a file is of a kind, from its names and attributes (a :class:`RunFile`, read once
for every probe; it is path-like, so a probe of a path takes it too)."""
Loader = Callable[[Path], RunView]
"""Reads a file the kind's probe recognised (it need not check the kind again)."""
PresetBuilder = Callable[[], tuple[Scene, Array]]
"""A plug-in preset: the model's scene and the (F, 4, 4) world pose of its frames at rest."""

_PLUGINS: tuple[str, ...] = ("aaria_pin.viz._arm_source",)
"""Modules imported (where they exist) on the first look-up of a run kind or a preset."""

_ANNOUNCED_PRESETS = {"pick-place-arm": "aaria_pin.viz._arm_source"}
"""Model presets a plug-in is to provide: named in the error while it does not."""

_KINDS: dict[str, tuple[Probe, Loader]] = {}
_FALLBACK_KINDS: dict[str, tuple[Probe, Loader]] = {}
_PRESETS: dict[str, PresetBuilder] = {}
_plugins_loaded = False


def table_view(
    table: ArrayLike, convention: Convention = "aaria", name: str = "arm"
) -> tuple[Scene, Array]:
    """The scene of a DH table and its frame poses with every joint at zero, base at the origin.

    Args:
        table: the DH table
        convention: its convention
        name: what to call it

    Returns:
        The scene and the (F, 4, 4) world pose of each of its frames.

    Raises:
        TableError: a bad table.
    """
    robot = build_dh_robot(table, convention)
    model = robot.model(moving_base=False)
    scene = scene_from_dh_robot(robot, name)
    zeros = np.zeros((1, model.n_joints))
    return scene, scene_poses(model, scene, BaseMotion.resting(1), still(zeros))[0]


def sample_at(time: Array, t: float) -> int:
    """Index of the sample nearest to time ``t`` [s].

    Raises:
        ParameterError: ``t`` outside the run (beyond half a sample step of its ends).
    """
    step = float(np.median(np.diff(time))) if time.size > 1 else 0.0
    if not (np.isfinite(t) and time[0] - step / 2 <= t <= time[-1] + step / 2):
        raise ParameterError(
            f"time {t:g} s is outside the run; allowed: {time[0]:g} to {time[-1]:g} s"
        )
    return int(np.argmin(np.abs(time - t)))


# --- plug-ins ------------------------------------------------------------------------------------


def _load_plugins() -> None:
    """Import each plug-in module once; one that is not installed is left out."""
    global _plugins_loaded
    if _plugins_loaded:
        return
    _plugins_loaded = True
    for name in _PLUGINS:
        try:
            module = importlib.import_module(name)
        except ModuleNotFoundError as exc:
            missing = exc.name or ""
            if name == missing or name.startswith(f"{missing}."):
                continue  # the plug-in itself is not there
            raise
        for preset, builder in dict(getattr(module, "PRESETS", {})).items():
            _PRESETS[str(preset)] = builder


def register_run_kind(kind: str, probe: Probe, loader: Loader, *, fallback: bool = False) -> None:
    """Teach the viewers a new kind of run file.

    Args:
        kind: its name
        probe: True for a file of this kind, given its :class:`RunFile` (it must not raise on
            other files)
        loader: reads such a file into a :class:`RunView` (given its path)
        fallback: try it only after every other kind (as the generic URDF kind is)
    """
    _KINDS.pop(kind, None)
    _FALLBACK_KINDS.pop(kind, None)
    (_FALLBACK_KINDS if fallback else _KINDS)[kind] = (probe, loader)


def _kinds() -> dict[str, tuple[Probe, Loader]]:
    """Every kind, in the order they are tried: as registered, the fallbacks last."""
    _load_plugins()
    return {**_KINDS, **_FALLBACK_KINDS}


def run_kind(path: str | os.PathLike[str]) -> str:
    """The kind of a run file (a key given to :func:`register_run_kind`).

    Raises:
        InputFileError: a missing file, or none of the known kinds.
    """
    file = Path(path)
    if not file.is_file():
        raise InputFileError(f"{file}: no such file")
    kinds = _kinds()
    header = run_file(file)  # one open for every probe
    for kind, (probe, _) in kinds.items():
        if probe(header):
            return kind
    raise InputFileError(
        f"{file}: not a run file the viewers know; allowed: {', '.join(kinds)} run files"
        " (.h5 or .mat)"
    )


def load_run_view(path: str | os.PathLike[str]) -> RunView:
    """Read a run file of any known kind for drawing.

    Raises:
        InputFileError: as :func:`run_kind`, or an unreadable file.
    """
    file = Path(path)
    return _kinds()[run_kind(file)][1](file)


def preset_names() -> tuple[str, ...]:
    """Presets :func:`preset_view` draws: the DH table presets, then the plug-ins' presets."""
    from aaria_pin.aaria.presets import preset_names as table_presets

    _load_plugins()
    tables = table_presets()
    return (*tables, *(name for name in _PRESETS if name not in tables))


def preset_view(name: str) -> tuple[Scene, Array]:
    """The scene of a preset at rest and the (F, 4, 4) world pose of each of its frames.

    A DH table preset (:mod:`aaria_pin.aaria.presets`) has every joint at zero and the base at the
    origin; a plug-in preset is drawn as its builder gives it.

    Raises:
        ParameterError: an unknown preset (the message lists the allowed ones).
        ModelError: a plug-in builder that returns poses not matching its scene.
    """
    from aaria_pin.aaria.presets import PRESETS

    if name in PRESETS:
        preset = PRESETS[name]
        return table_view(preset.table, preset.convention, preset.name)
    _load_plugins()
    allowed = ", ".join(preset_names())
    if name not in _PRESETS:
        if name in _ANNOUNCED_PRESETS:
            raise ParameterError(
                f"preset {name!r} is a model preset that cannot be drawn yet (no"
                f" PRESETS[{name!r}] in {_ANNOUNCED_PRESETS[name]}); allowed: {allowed}"
            )
        raise ParameterError(f"preset {name!r} is not known; allowed: {allowed}")
    scene, poses = _PRESETS[name]()
    poses = np.asarray(poses, dtype=float)
    if poses.shape != (len(scene.frames), 4, 4):
        raise ModelError(
            f"preset {name!r}: poses of shape {poses.shape} for {len(scene.frames)} frames;"
            " allowed: (frames, 4, 4)"
        )
    return scene, poses


register_run_kind("aaria", is_aaria_run, load_aaria_run)
register_run_kind("wrist", is_wrist_run, load_wrist_run)
register_run_kind("generic", is_generic_run, load_generic_run, fallback=True)
