"""What the pictures show, from a preset, a DH table or a run: a scene, frame poses, signals.

A DH table (a preset or a file) gives one pose: every joint at zero, the base at the world
origin. A run (a run file of any robot and any version, or one run of a data set) gives the
run: its one record (:class:`~aaria_pin.core.record.RunRecord`, read by
:func:`aaria_pin.files.runfile.read_run` or by
:meth:`aaria_pin.files.dataset.reader.DatasetReader.record`), the model rebuilt from it, its
frame poses over time computed by Pinocchio from the stored joint values and base motion, and
its signals.

**Run kinds.** Every kind reads the same record; they differ only in the picture.
:func:`run_kind` tells a run's kind and :func:`load_run_view` reads it with the loader
registered for it: ``"aaria"`` (an Aaria DH run, drawn as the paper draws it, its arm rebuilt
from its ``senSenDH`` table) and ``"wrist"`` (the report's spherical wrist), both in
:mod:`~aaria_pin.viz._dh_source`, and ``"model"`` (any run, its model rebuilt from its URDF
and drawn as a stick figure, :mod:`~aaria_pin.viz._model_source`). Other kinds plug in with
:func:`register_run_kind`: a probe that recognises the run and a loader that returns a
:class:`RunView`. The ``"model"`` kind is a fallback: it is tried after every other kind, so an
application's own kind (the pick-and-place arm's) is recognised first. A probe and a loader
are given a :class:`RunFile`: path-like (the file), with the run's record (read once, on first
use, for every probe and the loader).

**Plug-ins.** Applications register their kinds and presets without ``import aaria_pin``
importing them: the modules named in ``_PLUGINS`` (``aaria_pin.viz._arm_source``) are imported,
where they exist, the first time a run kind or a preset is looked up. A plug-in module

- calls :func:`register_run_kind` at import for each kind of run it knows, and
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

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.aaria.dh import Convention
from aaria_pin.aaria.dh_robot import build_dh_robot
from aaria_pin.core.record import RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion
from aaria_pin.errors import InputFileError, ModelError, ParameterError
from aaria_pin.viz._dh_source import is_aaria_run, is_wrist_run, load_aaria_run, load_wrist_run
from aaria_pin.viz._model_source import MODEL_KIND, is_any_run, load_model_run
from aaria_pin.viz._run_view import (
    RunFile,
    RunView,
    Signals,
    dataset_run,
    record_run,
    run_file,
    scene_poses,
    still,
)
from aaria_pin.viz.scene import Scene, scene_from_dh_robot

__all__ = [
    "PresetBuilder",
    "RunFile",
    "RunView",
    "Signals",
    "load_run_view",
    "preset_names",
    "preset_view",
    "record_view",
    "register_run_kind",
    "run_kind",
    "sample_at",
    "table_view",
]

Probe = Callable[[RunFile], bool]
"""Whether a run is of a kind, from its record (a :class:`RunFile`, read once for every probe;
it is path-like, so a probe of a path takes it too). It must not raise on a file that is not a
run."""
Loader = Callable[[RunFile], RunView]
"""Reads a run the kind's probe recognised (it need not check the kind again), given its
:class:`RunFile` (path-like: a loader of a path takes it too, for a run file)."""
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
            f"time {t:g} s is outside the run; allowed: {time[0]:g} to {time[-1]:g} s",
            parameter="time",
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
        fallback: try it only after every other kind (as the ``"model"`` kind is)
    """
    _KINDS.pop(kind, None)
    _FALLBACK_KINDS.pop(kind, None)
    (_FALLBACK_KINDS if fallback else _KINDS)[kind] = (probe, loader)


def _kinds() -> dict[str, tuple[Probe, Loader]]:
    """Every kind, in the order they are tried: as registered, the fallbacks last."""
    _load_plugins()
    return {**_KINDS, **_FALLBACK_KINDS}


def _known_kind(header: RunFile) -> str:
    """The kind whose probe first claims a run.

    Raises:
        InputFileError: none does.
    """
    kinds = _kinds()
    for kind, (probe, _) in kinds.items():
        if probe(header):
            return kind
    raise InputFileError(
        f"{header.path}: not a run file the viewers know; allowed: {', '.join(kinds)} run files"
        " (.h5 or .mat)",
        parameter="file",
        value=str(header.path),
    )


def run_kind(path: str | os.PathLike[str]) -> str:
    """The kind of a run file (a key given to :func:`register_run_kind`).

    Raises:
        InputFileError: a missing file, a folder, a FIFO or device, or none of the known kinds.
    """
    from aaria_pin.files.paths import existing_input

    file = existing_input(path, None, "run")  # not a FIFO, which a reader could wait on
    return _known_kind(run_file(file))  # one read for every probe


def load_run_view(path: str | os.PathLike[str], run: int | None = None) -> RunView:
    """Read a run file of any known kind, or one run of a data set, for drawing.

    Args:
        path: a run file (any robot, any version), or a data set
        run: the run of a data set to draw (default: its first); only for a data set

    Raises:
        InputFileError: as :func:`run_kind`, or an unreadable file.
        ParameterError: ``run`` given for a run file, or not a run of the data set.
    """
    from aaria_pin.files.detection import is_dataset_file
    from aaria_pin.files.paths import existing_input

    file = existing_input(path, None, "run")  # not a FIFO, which a reader could wait on
    if is_dataset_file(file):
        header = dataset_run(file, 0 if run is None else run)
    else:
        if run is not None:  # refused by the one rule of ``run`` (open_record), worded once
            from aaria_pin.files.source import open_record

            open_record(file, run)
        header = run_file(file)
    return _kinds()[_known_kind(header)][1](header)


def record_view(record: RunRecord, title: str = "run") -> RunView:
    """A record in memory ready to be drawn, by the kind that claims it.

    Raises:
        InputFileError: no kind claims it, or its model cannot be rebuilt.
    """
    header = record_run(record, title)
    return _kinds()[_known_kind(header)][1](header)


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
                f" PRESETS[{name!r}] in {_ANNOUNCED_PRESETS[name]}); allowed: {allowed}",
                parameter="preset",
            )
        raise ParameterError(
            f"preset {name!r} is not known; allowed: {allowed}", parameter="preset"
        )
    scene, poses = _PRESETS[name]()
    poses = np.asarray(poses, dtype=float)
    if poses.shape != (len(scene.frames), 4, 4):
        raise ModelError(
            f"preset {name!r}: poses of shape {poses.shape} for {len(scene.frames)} frames;"
            " allowed: (frames, 4, 4)",
            parameter="name",
            value=name,
        )
    return scene, poses


register_run_kind("aaria", is_aaria_run, load_aaria_run)
register_run_kind("wrist", is_wrist_run, load_wrist_run)
register_run_kind(MODEL_KIND, is_any_run, load_model_run, fallback=True)
