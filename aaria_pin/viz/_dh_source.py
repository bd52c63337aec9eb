"""The run kinds drawn as the paper draws a DH arm: ``"aaria"`` (an Aaria DH run) and ``"wrist"``.

Both read the one run record (:attr:`~aaria_pin.viz._run_view.RunFile.record`: a run file of
any version, or a run of a data set) and differ only in where the arm comes from: an Aaria run
rebuilds it from its ``senSenDH`` table, its ``body_dimensions`` attribute and its IMU mounts
(:func:`aaria_pin.aaria.dh_robot.build_dh_robot`); a wrist run is the report's spherical wrist
(:func:`aaria_pin.apps.wrist.run.report_wrist`). The arm is posed by Pinocchio from the stored
joint values and the base motion (:func:`aaria_pin.apps.record_model.record_base`); the signals are
the record's (:func:`~aaria_pin.viz._run_view.record_signals`, labelled by module).
"""

from __future__ import annotations

import os

import numpy as np

from aaria_pin.aaria.dh_robot import DHRobot
from aaria_pin.core.record import RunRecord
from aaria_pin.errors import InputFileError, ParameterError
from aaria_pin.viz._run_view import (
    RunFile,
    RunView,
    dh_view,
    record_signals,
    run_file,
    run_record,
    run_title,
)

__all__ = ["is_aaria_run", "is_wrist_run", "load_aaria_run", "load_wrist_run"]


def _kind(file: str | os.PathLike[str] | RunFile) -> str | None:
    """The record's ``kind`` attribute (``"dh"`` for any record with a ``senSenDH`` table)."""
    record = run_file(file).record
    if record is None:
        return None
    if "senSenDH" in record.tables:
        return "dh"
    return record.metadata.kind


def is_aaria_run(file: str | os.PathLike[str] | RunFile) -> bool:
    """Whether ``file`` holds an Aaria DH run (kind ``"dh"``, a ``senSenDH`` table)."""
    return _kind(file) == "dh"


def is_wrist_run(file: str | os.PathLike[str] | RunFile) -> bool:
    """Whether ``file`` holds a run of the report's spherical wrist (kind ``"wrist"``)."""
    return _kind(file) == "wrist"


def _view(file: str | os.PathLike[str], kind: str, robot: DHRobot, record: RunRecord) -> RunView:
    from aaria_pin.apps.record_model import record_base

    base = record_base(record)
    signals = record_signals(record, robot.model(moving_base=False), by_module=True)
    return dh_view(run_title(file), kind, robot, base, signals.q, signals)


def load_aaria_run(file: str | os.PathLike[str]) -> RunView:
    """Read an Aaria DH run for drawing.

    Raises:
        InputFileError: an unreadable file, or a table, body dimensions or IMU mounts that
            cannot be used.
    """
    from aaria_pin.aaria.dh_robot import BodyDimensions, build_dh_robot

    record = run_record(file)
    dims = None
    stored_dims = record.metadata.extra.get("body_dimensions")
    if stored_dims is not None:
        try:
            dims = BodyDimensions(**stored_dims)
        except (TypeError, ValueError, ParameterError) as exc:
            raise InputFileError(
                f"{file}: body_dimensions cannot be used ({exc})", parameter="run"
            ) from None
    mounts = record.imu_mount
    robot = build_dh_robot(record.tables["senSenDH"], "aaria", dims)
    if mounts.shape[0] == len(robot.imu_slots):
        robot = build_dh_robot(record.tables["senSenDH"], "aaria", dims, imu_mount=mounts)
    return _view(file, "aaria", robot, record)


def load_wrist_run(file: str | os.PathLike[str]) -> RunView:
    """Read a run of the report's spherical wrist for drawing.

    Raises:
        InputFileError: an unreadable file, or joints that are not the wrist's.
    """
    from aaria_pin.apps.wrist.run import report_wrist

    record = run_record(file)
    robot = report_wrist()
    if np.shape(record.q)[1] != len(robot.chain.joints):
        raise InputFileError(
            f"{file}: q of shape {np.shape(record.q)}; allowed: T × {len(robot.chain.joints)}",
            parameter="run",
        )
    return _view(file, "wrist", robot, record)
