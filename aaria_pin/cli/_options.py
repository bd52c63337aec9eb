"""Options shared by several commands: where a DH table or a robot comes from, sampling, torques."""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar, cast

import click

if TYPE_CHECKING:
    from aaria_pin.aaria.dh import Convention

F = TypeVar("F", bound=Callable[..., Any])


class FiniteFloat(click.ParamType):
    """A float that is neither NaN nor infinite; else one line naming the option (exit 2)."""

    name = "float"

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        """The number, or :class:`~aaria_pin.errors.ParameterError` for NaN or ±inf."""
        import math

        from aaria_pin.errors import ParameterError

        number = click.FLOAT.convert(value, param, ctx)
        if not math.isfinite(number):
            if isinstance(param, click.Argument):
                raise ParameterError(
                    f"{param.human_readable_name} holds {number}; allowed: finite numbers"
                )
            name = param.name if param is not None else None
            raise ParameterError(parameter=name, value=number, allowed="a finite number")
        return number


FINITE_FLOAT = FiniteFloat()
"""The click type of a number option that must be finite (``--elevation``, ``--time``)."""


def json_option(help: str = "Print one JSON object.") -> Callable[[F], F]:
    """``--json`` (the parameter ``as_json``): print the result as JSON."""
    return click.option("--json", "as_json", is_flag=True, help=help)


def shown(*decls: str, default: Any, help: str, **attrs: Any) -> Callable[[F], F]:
    """An option with a default shown in the help; its type is the default's unless given."""
    attrs.setdefault("type", type(default))
    return click.option(*decls, default=default, show_default=True, help=help, **attrs)


PRESET_HELP = "Built-in table: aaria-fig2, aaria-fig3, spherical-wrist."
"""The help of ``--preset`` for commands that take the DH presets only."""


def table_source_options(func: F) -> F:
    """Add ``--preset NAME | --dh FILE [--convention ...]`` to a command."""
    return table_source(PRESET_HELP)(func)


def table_source(preset_help: str = PRESET_HELP) -> Callable[[F], F]:
    """``--preset NAME | --dh FILE [--convention ...]`` with ``--preset`` described otherwise.

    Args:
        preset_help: the help of ``--preset`` (a command that also takes plug-in presets
            names them)
    """

    def add(func: F) -> F:
        return _table_source_options(func, preset_help)

    return add


def _table_source_options(func: F, preset_help: str) -> F:
    func = click.option(
        "--convention",
        type=click.Choice(["aaria", "standard", "modified"]),
        default="aaria",
        show_default=True,
        help="Convention of the --dh table.",
    )(func)
    func = click.option(
        "--dh",
        "dh_file",
        type=click.Path(path_type=Path, dir_okay=False),
        help="DH table file: CSV, .npy, or .mat holding senSenDH.",
    )(func)
    func = click.option("--preset", help=preset_help)(func)
    return func


def load_table_source(
    preset: str | None, dh_file: Path | None, convention: str
) -> tuple[Any, Convention, str]:
    """Resolve ``--preset`` / ``--dh`` into ``(table, convention, name)``.

    Raises:
        click.UsageError: neither or both given.
    """
    from aaria_pin.aaria.presets import get_preset
    from aaria_pin.files.io import read_table

    if (preset is None) == (dh_file is None):
        raise click.UsageError("give exactly one of --preset NAME or --dh FILE")
    if preset is not None:
        chosen = get_preset(preset)
        return chosen.table, chosen.convention, chosen.name
    assert dh_file is not None
    return read_table(dh_file, "senSenDH"), cast("Convention", convention), dh_file.stem


def robot_name(stem: str) -> str:
    """A URDF robot name from a preset or file name: letters, digits and ``_`` only."""
    cleaned = re.sub(r"[^A-Za-z0-9_]", "_", stem)
    return cleaned if cleaned[:1].isalpha() else f"arm_{cleaned}"


def fourier_options(func: F) -> F:
    """Add ``--harmonics`` and ``--base-frequency``, the settings of ``--motion fourier``."""
    func = click.option(
        "--base-frequency",
        type=FINITE_FLOAT,
        help="Base frequency of --motion fourier [Hz] (default: the lowest >= 0.1 Hz that fits a "
        "whole number of periods into a run).",
    )(func)
    return click.option(
        "--harmonics",
        type=click.IntRange(1, 1000),
        help="Harmonics per joint of --motion fourier (default 5).",
    )(func)


def robot_source_options(func: F) -> F:
    """Add ``--robot NAME | --urdf FILE`` and the URDF robot's tool, IMU and base options."""
    func = click.option(
        "--fixed-base", is_flag=True, help="URDF robot: keep the root link fixed at the origin."
    )(func)
    func = click.option(
        "--imu-layout",
        "imu_layout_file",
        type=click.Path(path_type=Path, dir_okay=False),
        help="URDF robot: IMU layout file (TOML, [[imu]] name, parent, xyz, rpy).",
    )(func)
    func = click.option("--tool", "tool_frame", help="URDF robot: the tool frame.")(func)
    func = click.option(
        "--urdf",
        "urdf_file",
        type=click.Path(path_type=Path, dir_okay=False),
        help="A URDF file to simulate instead of a DH arm.",
    )(func)
    func = click.option(
        "--robot", help="A robot of example-robot-data (see 'aaria robots'), e.g. ur5, panda."
    )(func)
    return func


def load_robot_source(robot: str | None, urdf_file: Path | None) -> tuple[str, Path, str]:
    """Resolve ``--robot`` / ``--urdf`` into ``(urdf text, its folder, source name)``.

    Raises:
        click.UsageError: both given.
    """
    from aaria_pin.core.catalogue import find_robot
    from aaria_pin.core.urdf_robot import read_urdf_file

    if robot is not None and urdf_file is not None:
        raise click.UsageError("give one of --robot NAME or --urdf FILE, not both")
    if robot is not None:
        entry = find_robot(robot)
        return read_urdf_file(entry.urdf), entry.urdf.parent, entry.name
    assert urdf_file is not None
    from aaria_pin.files.paths import existing_input

    existing_input(urdf_file, None, "URDF")  # a FIFO or a folder: one line, never a wait
    return read_urdf_file(urdf_file), urdf_file.parent, str(urdf_file)


def sampling_overrides(params: dict[str, Any]) -> dict[str, Any]:
    """``duration``, ``rate``, ``seed`` and ``noise`` of a command's options, where given."""
    keys = ("duration", "rate", "seed", "noise")
    return {key: params[key] for key in keys if params.get(key) is not None}


def torque_overrides(params: dict[str, Any]) -> dict[str, Any]:
    """``torques`` from ``--drive torque --torques FILE``, and the time grid of a torque run.

    ``--torques`` is an HDF5 run file (its ``tau``; the run's rate and duration then become
    the defaults of ``--rate`` and ``--duration``) or a T × n table (CSV, .npy, or a .mat
    holding ``tau``, such as a ``.mat`` run file).

    Raises:
        click.UsageError: ``--drive torque`` without ``--torques`` or the other way round.
    """
    path: Path | None = params.get("torques_file")
    if (params.get("drive") == "torque") != (path is not None):
        raise click.UsageError("--drive torque and --torques FILE go together")
    if path is None:
        return {}
    from aaria_pin.files.io import read_table

    if path.suffix.lower() in (".h5", ".hdf5"):
        from aaria_pin.files.runfile import read_run

        run = read_run(path)
        grid: dict[str, Any] = {
            key: float(run.attributes[key])
            for key in ("duration", "rate")
            if params.get(key) is None and key in run.attributes
        }
        return {"torques": run.tau, **grid}
    return {"torques": read_table(path, "tau")}
