"""Where a run's robot and inputs come from: a DH preset or table file, a URDF robot, torques.

The questions every command and script that builds a robot asks, answered once:
:func:`dh_table_source` (a preset, or a table file in a convention), :func:`urdf_source` (a
robot of the catalogue, or a URDF file), :func:`read_torques` (a torque file: a run file's
``tau`` and its time grid, or a T × n table), :func:`robot_name` (a URDF name from a file name).
"""

from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Any, cast

from aaria_pin.aaria.dh import Convention
from aaria_pin.errors import ParameterError

__all__ = ["dh_table_source", "read_torques", "robot_name", "urdf_source"]


def _one_of(name: str, value: Any, other: str, other_value: Any) -> None:
    """Refuse neither or both of two sources (both: naming them, as options that conflict)."""
    if value is None and other_value is None:
        raise ParameterError(
            parameter=name, value=None, allowed=f"exactly one of {name} and {other}"
        )
    if value is not None and other_value is not None:
        from aaria_pin.core.conflicts import OptionConflictError

        raise OptionConflictError(parameter=name, other=other, given_with=True, value=value)


def dh_table_source(
    preset: str | None = None,
    dh_file: str | os.PathLike[str] | None = None,
    convention: str | None = None,
) -> tuple[Any, Convention, str]:
    """A DH table from a preset or a table file, its convention and its name.

    Args:
        preset: a preset's name (:mod:`aaria_pin.aaria.presets`)
        dh_file: a table file: CSV, ``.npy``, or ``.mat`` holding ``senSenDH``
        convention: the convention of ``dh_file``'s table (None: ``"aaria"``); a preset has
            its own (None, or the same)

    Returns:
        ``(table, convention, name)``: the preset's name, or the file's stem.

    Raises:
        ParameterError: neither ``preset`` nor ``dh_file``, or an unknown preset.
        OptionConflictError: both ``preset`` and ``dh_file``; a preset with another
            ``convention`` than its own (it would be ignored).
        InputFileError: a table file that cannot be read.
    """
    from aaria_pin.aaria.presets import get_preset
    from aaria_pin.files.io import read_table

    _one_of("preset", preset, "dh_file", dh_file)
    if preset is not None:
        chosen = get_preset(preset)
        if convention not in (None, chosen.convention):
            from aaria_pin.core.conflicts import OptionConflictError

            raise OptionConflictError(
                parameter="convention", other="preset", given_with=True, value=convention
            )
        return chosen.table, chosen.convention, chosen.name
    path = Path(os.fspath(cast("os.PathLike[str]", dh_file)))
    given = "aaria" if convention is None else convention
    return read_table(path, "senSenDH"), cast("Convention", given), path.stem


def urdf_source(
    robot: str | None = None, urdf_file: str | os.PathLike[str] | None = None
) -> tuple[str, Path, str]:
    """A URDF robot's text, its folder (where its meshes are found) and its source's name.

    Args:
        robot: a robot of the catalogue (:mod:`aaria_pin.core.catalogue`), e.g. ``"ur5"``
        urdf_file: a URDF file

    Raises:
        ParameterError: neither ``robot`` nor ``urdf_file``; an unknown robot.
        OptionConflictError: both ``robot`` and ``urdf_file``.
        InputFileError: a missing file, a folder or a FIFO (refused without a wait).
    """
    from aaria_pin.core.catalogue import find_robot
    from aaria_pin.core.urdf_robot import read_urdf_file
    from aaria_pin.files.paths import existing_input

    _one_of("robot", robot, "urdf_file", urdf_file)
    if robot is not None:
        entry = find_robot(robot)
        return read_urdf_file(entry.urdf), entry.urdf.parent, entry.name
    path = existing_input(cast("os.PathLike[str]", urdf_file), None, "URDF")
    return read_urdf_file(path), path.parent, os.fspath(cast("os.PathLike[str]", urdf_file))


def read_torques(path: str | os.PathLike[str]) -> tuple[Any, dict[str, float]]:
    """Joint torques to drive a run with, and the time grid they were sampled on.

    Args:
        path: an HDF5 run file (its ``tau_motor``, what its motors gave, when it was made with
            an actuator, else its ``tau``; its ``rate`` [Hz] and ``duration`` [s] are the
            grid, the defaults for a file that stores none) or a T × n table (CSV, ``.npy``,
            or a ``.mat`` holding ``tau``, such as a ``.mat`` run file; no grid). A run with an
            actuator replays with the same actuator (``--hardware``): its motion again

    Returns:
        The (T, n) torques [N·m or N] and ``{"rate": …, "duration": …}`` (empty for a table).

    Raises:
        InputFileError: a file that cannot be read.
    """
    from aaria_pin.files.io import read_table

    if Path(path).suffix.lower() not in (".h5", ".hdf5"):
        return read_table(Path(path), "tau"), {}
    from aaria_pin.files.runfile import read_run

    run = read_run(path)
    metadata = run.metadata
    tau = run.tables["tau_motor"] if "tau_motor" in run.tables else run.tau
    return tau, {"duration": metadata.duration, "rate": metadata.rate}


def robot_name(stem: str) -> str:
    """A URDF robot name from a preset or file name: letters, digits and ``_`` only."""
    cleaned = re.sub(r"[^A-Za-z0-9_]", "_", stem)
    return cleaned if cleaned[:1].isalpha() else f"arm_{cleaned}"
