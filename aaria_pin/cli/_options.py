"""Options shared by several commands: where a DH table or a robot comes from, sampling, torques."""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import click

F = TypeVar("F", bound=Callable[..., Any])
_FILE = click.Path(path_type=Path, dir_okay=False)


class FiniteFloat(click.ParamType):
    """A float that is neither NaN nor infinite; else one line naming the option (exit 2)."""

    name = "float"

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        """The number, or :class:`~aaria_pin.errors.ParameterError` for NaN or ±inf."""
        from aaria_pin.errors import ParameterError

        number = click.FLOAT.convert(value, param, ctx)
        if not math.isfinite(number):
            if isinstance(param, click.Argument):
                message = f"{param.human_readable_name} holds {number}; allowed: finite numbers"
                raise ParameterError(message, parameter=param.name)
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


def grid_options(
    duration: float | str = "(default 10)", rate: float | str = "(default 100)"
) -> Callable[[F], F]:
    """``--duration`` [s] and ``--rate`` [Hz] of a run (their bounds are the library's).

    Args:
        duration: its default (shown), or the help's text of it (the option is then None)
        rate: the same for ``--rate``
    """

    def option(flag: str, what: str, default: float | str) -> Callable[[F], F]:
        if isinstance(default, str):
            return click.option(flag, type=float, help=f"{what} {default}.")
        return shown(flag, default=default, type=float, help=f"{what}.")

    return stacked(option("--duration", "Run length [s]", duration),
                   option("--rate", "Sample rate [Hz]", rate))  # fmt: skip


PRESET_HELP = "Built-in table: aaria-fig2, aaria-fig3, spherical-wrist."
"""The help of ``--preset`` for commands that take the DH presets only."""


def table_source(preset_help: str = PRESET_HELP) -> Callable[[F], F]:
    """``--preset NAME | --dh FILE [--convention ...]``, ``--preset`` with its own help."""
    return stacked(
        click.option("--preset", help=preset_help),
        click.option("--dh", "dh_file", type=_FILE,
                     help="DH table file: CSV, .npy, or .mat holding senSenDH."),
        shown("--convention", default="aaria", type=click.Choice(["aaria", "standard", "modified"]),
              help="Convention of the --dh table."),
    )  # fmt: skip


def stacked(*options: Callable[[F], F]) -> Callable[[F], F]:
    """The options as one decorator, in the order given (as if written one above the other)."""
    return lambda func: functools.reduce(lambda f, option: option(f), reversed(options), func)


table_source_options = table_source()
"""``--preset NAME | --dh FILE [--convention ...]`` with the DH presets' help."""


def given(name: str) -> bool:
    """Whether the running command's option ``name`` was given (not left at its default)."""
    source, ps = click.get_current_context().get_parameter_source(name), click.core.ParameterSource
    return source not in (None, ps.DEFAULT, ps.DEFAULT_MAP)


def load_table_source(preset: str | None, dh_file: Path | None, convention: str) -> Any:
    """``--preset`` / ``--dh`` as ``(table, convention, name)`` (:func:`dh_table_source`).

    ``--convention`` is passed only when given: a preset of another convention refuses it.
    """
    from aaria_pin.aaria.robot_inputs import dh_table_source

    if (preset is None) == (dh_file is None):
        raise click.UsageError("give exactly one of --preset NAME or --dh FILE")
    return dh_table_source(preset, dh_file, convention if given("convention") else None)


fourier_options = stacked(
    click.option("--harmonics", type=click.IntRange(1, 1000),
                 help="Harmonics per joint of --motion fourier (default 5)."),
    click.option("--base-frequency", type=FINITE_FLOAT,
                 help="Base frequency of --motion fourier [Hz] (default: the lowest >= 0.1 Hz that"
                 " fits a whole number of periods into a run)."),
)  # fmt: skip
"""``--harmonics`` and ``--base-frequency``, the settings of ``--motion fourier``."""

robot_source_options = stacked(
    click.option("--robot",
                 help="A robot of example-robot-data (see 'aaria robots'), e.g. ur5, panda."),
    click.option("--urdf", "urdf_file", type=_FILE, help="A URDF file instead of a DH arm."),
    click.option("--tool", "tool_frame", help="URDF robot: the tool frame."),
    click.option("--imu-layout", "imu_layout_file", type=_FILE,
                 help="URDF robot: IMU layout file (TOML, [[imu]] name, parent, xyz, rpy)."),
    click.option("--fixed-base", is_flag=True,
                 help="URDF robot: keep the root link fixed at the origin."),
)  # fmt: skip
"""``--robot NAME | --urdf FILE`` and the URDF robot's tool, IMU and base options."""


hardware_options = stacked(
    click.option("--imu-model", help="IMU model: a preset (adis16485, the default; adis16470,"
                 " bmi088, icm42688p, mpu6050) or a TOML file (aaria template imu-model)."),
    click.option("--hardware", "hardware_file", type=_FILE, help="TOML file of [imu], [encoder],"
                 " [torque_sensor], [current_sensor], [actuator] (aaria template hardware); with"
                 " --from the stored ones stay unless given."),
)  # fmt: skip
"""``--imu-model NAME|FILE`` and ``--hardware FILE``: the run's IMU and joint hardware."""


def sampling_overrides(params: dict[str, Any], stored: Any = None) -> dict[str, Any]:
    """``duration``, ``rate``, ``seed``, ``noise`` and the hardware options, where given."""
    from aaria_pin.aaria.hardware import hardware_run_options

    keys = ("duration", "rate", "seed", "noise")
    hardware = (params.get("imu_model"), params.get("hardware_file"), stored and stored.attributes)
    return {**{key: params[key] for key in keys if params.get(key) is not None},
            **hardware_run_options(*hardware)}  # fmt: skip


def integration_options(command: Any) -> Any:
    """``--limits``, ``--integrator``, ``--substeps``: how a driven run is integrated and held."""
    for option in (
        click.option("--substeps", type=click.IntRange(1), help="--drive torque: integration steps"
                     " per sample (default 4; a controller steps at its rate).") ,
        click.option("--integrator", type=click.Choice(["rk4", "euler"]),
                     help="Of a driven run: RK4 (default) or semi-implicit Euler."),
        click.option("--limits", type=click.Choice(["stop", "clamp", "ignore"]),
            help="--drive torque|pd|computed-torque: stop at the first joint beyond its model"
            " position or velocity limit (exit 1; the default), hold it on stiff-damped stops"
            " (clamp), or ignore them. --from: as stored."),
    ):  # fmt: skip
        command = option(command)
    return command


def drive_overrides(params: dict[str, Any]) -> dict[str, Any]:
    """The drive's options (torques, a torque run's time grid, drive, limits, integrator)."""
    from aaria_pin.aaria.robot_inputs import read_torques
    from aaria_pin.apps.run_progress import run_progress

    path: Path | None = params.get("torques_file")
    drive = params.get("drive")
    if (drive == "torque") != (path is not None):
        raise click.UsageError("--drive torque and --torques FILE go together")
    keys = ("limits", "integrator", "substeps")
    options: dict[str, Any] = {key: params[key] for key in keys if params.get(key) is not None}
    if path is None and options and drive == "motion" and params.get("from_run") is None:
        raise click.UsageError(
            f"--{next(iter(options))} goes with --drive torque|pd|computed-torque (or --from)"
        )
    options["progress"] = run_progress()  # a followed motion has none to tell
    if drive not in ("motion", "torque") or given("drive"):  # with --from: it replaces the stored
        options["drive"] = drive
    if drive not in ("motion", "torque"):
        return options
    if path is None:
        return options
    tau, grid = read_torques(path)
    return {"torques": tau, **options, **{k: v for k, v in grid.items() if params.get(k) is None}}
