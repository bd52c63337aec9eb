"""A run's request from where its robot comes from: a table, a URDF robot or a stored run.

What ``aaria simulate`` does once its options are read, for a Python user too:
:func:`dh_run_request` picks the motion (:class:`~aaria_pin.aaria.run_motion.MotionChoice`:
the joint table's sines, a Fourier excitation or a trajectory), gives a preset's joint and base
tables where none is given, and returns the engine's request
(:func:`~aaria_pin.aaria.simulate.dh_request`, or
:func:`~aaria_pin.aaria.simulate.dh_request_from_record` for a stored run);
:func:`urdf_run_request` the same for a URDF robot (a robot name or a URDF file, or its stored
run), and :func:`effort_warnings` says which joints went beyond their URDF effort limits.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from aaria_pin.aaria.dh import Convention
from aaria_pin.aaria.run_motion import MotionChoice, dh_motion, urdf_motion
from aaria_pin.core.record import RunRecord
from aaria_pin.core.run import RunRequest
from aaria_pin.errors import ParameterError

__all__ = [
    "dh_file_overrides",
    "dh_run_request",
    "effort_warnings",
    "urdf_file_overrides",
    "urdf_run_request",
]


def _table_overrides(options: Mapping[str, Any], joint_table: str) -> dict[str, Any]:
    """The joint and base tables of ``joints_file`` and ``base_file`` (where given)."""
    from aaria_pin.files.io import read_table

    found: dict[str, Any] = {}
    if options.get("joints_file") is not None:
        found["joint_table"] = read_table(options["joints_file"], joint_table)
    if options.get("base_file") is not None:
        found["base_table"] = read_table(options["base_file"], "senSenB")
    return found


def dh_file_overrides(options: Mapping[str, Any]) -> dict[str, Any]:
    """A DH run's options from its input files and density (``aaria simulate``'s).

    Args:
        options: ``joints_file``, ``base_file`` (oscillation tables), ``mount_file`` (IMU
            mounts: ``.npy`` or a run file), ``density`` [kg/m^3]; absent or None: not given
    """
    from aaria_pin.aaria.arm_run import read_imu_mounts
    from aaria_pin.aaria.dh_robot import BodyDimensions

    found = _table_overrides(options, "senSenJ")
    if options.get("mount_file") is not None:
        found["imu_mount"] = read_imu_mounts(options["mount_file"])
    if options.get("density") is not None:
        found["dims"] = BodyDimensions(density=options["density"])
    return found


def urdf_file_overrides(options: Mapping[str, Any]) -> dict[str, Any]:
    """A URDF robot's run options from its tool frame and input files (``aaria simulate``'s).

    Args:
        options: ``tool_frame``, ``imu_layout_file`` (TOML), ``joints_file``, ``base_file``;
            absent or None: not given
    """
    from aaria_pin.core.imu_layout import read_imu_layout
    from aaria_pin.files.paths import existing_input

    found: dict[str, Any] = {}
    if options.get("tool_frame") is not None:
        found["tool_frame"] = options["tool_frame"]
    if options.get("imu_layout_file") is not None:
        layout_file = existing_input(options["imu_layout_file"], None, "IMU layout")
        found["imu_layout"] = read_imu_layout(layout_file)
    return {**found, **_table_overrides(options, "joint_table")}


def dh_run_request(
    choice: MotionChoice,
    overrides: dict[str, Any],
    table_source: tuple[Any, Convention, str] | None = None,
    preset: str | None = None,
    stored: tuple[RunRecord, str] | None = None,
) -> RunRequest:
    """The request of a DH run (module docstring).

    Args:
        choice: the motion chosen
        overrides: the run's options (:class:`~aaria_pin.aaria.simulate.DhRunOptions`); the
            motion's are added to it
        table_source: ``(table, convention, name)`` of the arm (without ``stored``)
        preset: the preset the table is (its joint and base tables where none is given)
        stored: ``(record, source)``: the stored DH run to re-make, and its file

    Raises:
        ParameterError: a table of another convention than Aaria's (parameter ``dh_table``).
    """
    from aaria_pin.aaria.presets import get_preset
    from aaria_pin.aaria.simulate import dh_request, dh_request_from_record

    if stored is not None:
        record, source = stored
        overrides.update(dh_motion(choice, record, overrides, record.tables["senSenDH"]))
        return dh_request_from_record(record, source=source, **overrides)
    if table_source is None:
        raise ParameterError(parameter="dh_table", value=None, allowed="a DH table or a run")
    table, table_convention, name = table_source
    if table_convention != "aaria":
        raise ParameterError(
            f"table {name!r} is a {table_convention} DH table; allowed: an Aaria 8 × 5 table",
            parameter="dh_table",
        )
    overrides.update(dh_motion(choice, None, overrides, table))
    if preset is not None:  # its tables where none is given (after the motion's rules)
        chosen = get_preset(preset)
        overrides.setdefault("joint_table", chosen.joint_table)
        overrides.setdefault("base_table", chosen.base_table)
    return dh_request(table, robot_name=name, **overrides)


def urdf_run_request(
    choice: MotionChoice,
    overrides: dict[str, Any],
    robot: tuple[str | None, Path | None] = (None, None),
    stored: RunRecord | None = None,
    moving_base: bool = True,
) -> RunRequest:
    """The request of a URDF robot's run (module docstring).

    Args:
        choice: the motion chosen
        overrides: the run's options (:class:`~aaria_pin.core.urdf_run.UrdfRunOptions`); the
            motion's are added to it
        robot: ``(name, urdf_file)``: a robot of example-robot-data or a URDF file
        stored: the stored run to re-make instead (its URDF)
        moving_base: whether the base moves (a stored run: False fixes it, True keeps its own)
    """
    from aaria_pin.aaria.robot_inputs import urdf_source
    from aaria_pin.core.urdf_run import urdf_request, urdf_request_from_record

    if stored is not None:
        if not moving_base:
            overrides["moving_base"] = False
        overrides.update(urdf_motion(choice, stored, overrides))
        return urdf_request_from_record(stored, **overrides)
    text, folder, source = urdf_source(*robot)
    overrides.update(urdf_motion(choice, None, overrides, text, folder))
    return urdf_request(text, urdf_dir=folder, source=source, moving_base=moving_base, **overrides)


def effort_warnings(record: RunRecord) -> list[str]:
    """One line per joint whose peak |tau| went beyond its URDF effort limit."""
    exceeded = record.metadata.extra.get("effort_exceeded", {})
    return [f"joint {joint!r} reaches |tau| {peak:.4g}, beyond its URDF effort limit {limit:.4g}"
            " (N*m or N)" for joint, (peak, limit) in exceeded.items()]  # fmt: skip
