"""Re-make a run from its record or its run file alone, whatever the robot (``--from``).

A run record holds the inputs that made it: an Aaria DH run its tables ``senSenDH``,
``senSenJ``, ``senSenB``; a URDF robot's run its URDF text, ``joint_table``, ``base_table`` and
IMU layout; a wrist run its ``targets`` and motion settings; a pick-and-place run its cylinder,
place, preset, rate and IK branch; every run its rate, duration, seed and noise setting (and a
run driven by torques its ``torque_table``; a DH or URDF run that follows a Fourier excitation
its ``fourier_coefficients`` and ``fourier`` attribute, one that follows a given trajectory its
``joint_trajectory``: :func:`~aaria_pin.core.run.motion_from_record`; a run without a
``motion`` attribute, written before, follows its joint table's sines). :func:`remake_record`
simulates the run again from them, by the kind registered for it (``attributes["kind"]``:
:func:`~aaria_pin.core.run.kind_of`), so
that with no overrides the re-made run equals the stored one; :func:`remake_run` does the same
from a run file.
"""

from __future__ import annotations

import os
from typing import Any

from aaria_pin.core.record import RunRecord
from aaria_pin.errors import InputFileError

__all__ = [
    "remake_file_record",
    "remake_record",
    "remake_run",
    "run_kind",
    "simulate_urdf_from_run_file",
]

_KIND_MODULES = (
    "aaria_pin.aaria.simulate",
    "aaria_pin.core.urdf_run",
    "aaria_pin.apps.wrist.run",
    "aaria_pin.apps.arm.run",
)
"""The modules that register the run kinds that can be re-made (``attributes["kind"]``: dh,
urdf, wrist, pick-place; :data:`~aaria_pin.core.record_checks.KIND_TABLES`)."""


def _registered() -> None:
    """Import the modules that define the kinds: each registers its kind on import."""
    from importlib import import_module

    for module in _KIND_MODULES:
        import_module(module)


def run_kind(record: RunRecord) -> str:
    """The kind of a run: its ``kind`` attribute, else recognised from its tables.

    Raises:
        InputFileError: no known kind.
    """
    from aaria_pin.core.run import kind_of

    _registered()
    return kind_of(record).name


def remake_record(stored: RunRecord, **overrides: Any) -> RunRecord:
    """Simulate a run again from the inputs its record holds, by its registered kind.

    Args:
        stored: the run's record
        **overrides: keyword arguments of the kind's producer that replace the stored ones
            (:func:`~aaria_pin.aaria.simulate.simulate_run`,
            :func:`~aaria_pin.core.urdf_run.simulate_urdf_run`,
            :func:`~aaria_pin.apps.wrist.run.simulate_wrist`,
            :func:`~aaria_pin.apps.arm.run.simulate_pick_place`)

    Returns:
        The re-made record; with no overrides it equals the stored one.

    Raises:
        InputFileError: a run of no known kind, or one that lacks its inputs.
    """
    from aaria_pin.core.run import kind_of

    _registered()
    return kind_of(stored).remake(stored, **overrides)


def remake_run(path: str | os.PathLike[str], **overrides: Any) -> RunRecord:
    """Re-make the run stored in a run file (any kind) from its inputs alone.

    Args:
        path: an ``.h5``, ``.hdf5`` or ``.mat`` run file
        **overrides: as in :func:`remake_record`

    Returns:
        The re-made record; with no overrides it equals the stored one.

    Raises:
        InputFileError: not a run file, or a run that cannot be re-made.
    """
    from aaria_pin.files.runfile import read_run_inputs

    stored = read_run_inputs(path)  # the inputs only: the stored series are not read
    return remake_file_record(stored, path, **overrides)


def remake_file_record(
    stored: RunRecord, path: str | os.PathLike[str], **overrides: Any
) -> RunRecord:
    """:func:`remake_record` of a record read from ``path``: its errors name the file.

    Raises:
        InputFileError: a run that cannot be re-made, ``"FILE: ..."`` (``parameter="file"``).
    """
    try:
        return remake_record(stored, **overrides)
    except InputFileError as exc:
        if str(path) in str(exc):
            raise
        raise InputFileError(f"{path}: {exc}", element=str(path), parameter="file") from None


def simulate_urdf_from_run_file(path: str | os.PathLike[str], **overrides: Any) -> RunRecord:
    """Deprecated: :func:`remake_run` (any kind); re-make a URDF robot's run from its file.

    Args:
        path: the run file
        **overrides: keyword arguments of :func:`~aaria_pin.core.urdf_run.simulate_urdf_run`

    Returns:
        The run record; with no overrides it equals the stored one.
    """
    from aaria_pin.core.run.deprecation import warn_deprecated
    from aaria_pin.core.urdf_run import urdf_request_from_record
    from aaria_pin.files.runfile import read_run_inputs

    warn_deprecated("simulate_urdf_from_run_file", "aaria_pin.apps.remake.remake_run(path, **o)")

    return urdf_request_from_record(read_run_inputs(path), **overrides).record()
