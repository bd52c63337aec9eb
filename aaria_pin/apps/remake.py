"""Re-make a run from its record or its run file alone, whatever the robot (``--from``).

A run record holds the inputs that made it: an Aaria DH run its tables ``senSenDH``,
``senSenJ``, ``senSenB``; a URDF robot's run its URDF text, ``joint_table``, ``base_table`` and
IMU layout; a wrist run its ``targets`` and motion settings; a pick-and-place run its cylinder,
place, preset, rate and IK branch; every run its rate, duration, seed and noise setting (and a
run driven by torques its ``torque_table``; a DH or URDF run that follows a Fourier excitation
its ``fourier_coefficients`` and ``fourier`` attribute, one that follows a given trajectory its
``joint_trajectory``: :func:`~aaria_pin.core.excitation.stored_motion`; a run without a
``motion`` attribute, written before, follows its joint table's sines). :func:`remake_record`
simulates the run again from them, by the producer of its kind (``attributes["kind"]``), so
that with no overrides the re-made run equals the stored one; :func:`remake_run` does the same
from a run file.
"""

from __future__ import annotations

import os
from typing import Any

from aaria_pin.core.record import RunRecord
from aaria_pin.errors import InputFileError

__all__ = ["RUN_KINDS", "remake_record", "remake_run", "run_kind", "simulate_urdf_from_run_file"]

RUN_KINDS = ("dh", "urdf", "wrist", "pick-place")
"""The kinds of run (``attributes["kind"]``) that can be re-made."""


def run_kind(record: RunRecord) -> str:
    """The kind of a run: its ``kind`` attribute, else guessed from its tables.

    Raises:
        InputFileError: no known kind.
    """
    kind = record.attributes.get("kind")
    if kind is None:
        if "senSenDH" in record.tables:
            kind = "dh"
        elif "joint_table" in record.tables:
            kind = "urdf"
        elif "targets" in record.tables or "targets_rad" in record.attributes:
            kind = "wrist"
        elif "cylinder" in record.attributes:
            kind = "pick-place"
    if kind not in RUN_KINDS:
        raise InputFileError(
            parameter="kind", value=kind, allowed=", ".join(RUN_KINDS), element="run"
        )
    return str(kind)


def remake_record(stored: RunRecord, **overrides: Any) -> RunRecord:
    """Simulate a run again from the inputs its record holds.

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
    kind = run_kind(stored)
    if kind == "dh":
        from aaria_pin.aaria.simulate import simulate_from_record

        return simulate_from_record(stored, **overrides)
    if kind == "urdf":
        from aaria_pin.core.urdf_run import simulate_urdf_from_record

        return simulate_urdf_from_record(stored, **overrides)
    if kind == "wrist":
        from aaria_pin.apps.wrist.run import simulate_wrist_from_record, wrist_record

        return wrist_record(simulate_wrist_from_record(stored, **overrides))
    from aaria_pin.apps.arm.run import pick_place_record, simulate_pick_place_from_record

    try:
        return pick_place_record(simulate_pick_place_from_record(stored, **overrides))
    except KeyError as exc:
        raise InputFileError(
            f"pick-place run has no attribute {exc}; allowed: a run written by this toolkit",
            element="run",
        ) from None


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
    try:
        return remake_record(stored, **overrides)
    except InputFileError as exc:
        if str(path) in str(exc):
            raise
        raise InputFileError(f"{path}: {exc}", element=str(path)) from None


def simulate_urdf_from_run_file(path: str | os.PathLike[str], **overrides: Any) -> RunRecord:
    """Re-make a URDF robot's run stored in a run file (moved here from ``core.urdf_run``).

    Args:
        path: the run file
        **overrides: keyword arguments of :func:`~aaria_pin.core.urdf_run.simulate_urdf_run`

    Returns:
        The run record; with no overrides it equals the stored one.
    """
    from aaria_pin.core.urdf_run import simulate_urdf_from_record
    from aaria_pin.files.runfile import read_run_inputs

    return simulate_urdf_from_record(read_run_inputs(path), **overrides)
