"""``aaria wrist``: forward and inverse kinematics of the report's spherical wrist."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import click

from aaria_pin.cli._app import AariaGroup
from aaria_pin.cli._options import FINITE_FLOAT, grid_options, hardware_options, json_option, shown
from aaria_pin.cli._viz_options import PICTURE_SUFFIXES, output_option
from aaria_pin.core.seeds import MAX_SEED
from aaria_pin.errors import ParameterError

_ORDERS = (*"xyz xzy yxz yzx zxy zyx XYZ XZY YXZ YZX ZXY ZYX ZYZ zyz".split(),)
_ORDER_HELP = (
    " Named as scipy names them: lowercase about fixed axes ('xyz' = Rz·Ry·Rx),"
    " uppercase about moving axes ('ZYZ' = Rz·Ry·Rz, the wrist's own)."
)
_radians = click.option("--radians", is_flag=True, help="Angles in radians (default degrees).")


def _order(help: str) -> Any:
    return shown("--order", default="xyz", type=click.Choice(_ORDERS), help=help + _ORDER_HELP)


def _positive(_ctx: click.Context, param: click.Parameter, value: float) -> float:
    if not value > 0:
        raise ParameterError(parameter=param.name, value=value, allowed="> 0")
    return value


def _range(_ctx: click.Context, param: click.Parameter, value: tuple[float, float]) -> Any:
    if value[0] > value[1]:
        low_high = f"{value[0]:g} {value[1]:g} (reversed); allowed: LOW HIGH with LOW <= HIGH"
        raise ParameterError(f"{param.name} is {low_high}", parameter=param.name)
    return value


def _echo(report: Any, as_json: bool) -> None:
    for note in report.notes:
        click.echo(f"aaria: note: {note}", err=True)
    click.echo(json.dumps(report.to_dict()) if as_json else report.text())


@click.group(
    cls=AariaGroup,
    context_settings={"ignore_unknown_options": True},
    epilog="""\b
Examples:
  aaria wrist fk -30 45 10 && aaria wrist ik --angles 10 -40 75 --order zyx
  aaria wrist simulate 60 45 -30 -o wrist.h5 && aaria wrist workspace --theta2 0 90""",
)
def wrist() -> None:
    """The spherical wrist of the wrist report (standard DH, d3 = 132 mm)."""


@wrist.command(
    context_settings={"ignore_unknown_options": True},
    epilog="""\b
Examples:
  aaria wrist fk -30 45 10                    # pose, xyz angles, both IK branches [deg]
  aaria wrist fk 30 45 10 --order ZYX --json  # one JSON object
  aaria wrist fk 0.5 0.8 -0.2 --radians       # joint angles in radians""",
)
@click.argument("joints", nargs=3, type=FINITE_FLOAT)
@_order("Angle sequence to express the rotation in.")
@_radians
@json_option()
def fk(joints: tuple[float, float, float], order: str, radians: bool, as_json: bool) -> None:
    """Tool pose and angles of joint angles J1 J2 J3 (negative values work as they are)."""
    from aaria_pin.apps.wrist.report import joints_report

    _echo(joints_report(joints, order, degrees=not radians), as_json)


@wrist.command(
    context_settings={"ignore_unknown_options": True},
    epilog="""\b
Examples:
  aaria wrist ik --angles 10 -40 75 --order zyx  # about fixed z, then y, then x [deg]
  aaria wrist ik --angles 0 120 30 --limits      # only the report's 0-360°, 0-180°
  aaria wrist ik --matrix 1 0 0 0 1 0 0 0 1      # singular: only θ1 + θ3 is fixed
  # the rotation `aaria wrist fk 30 45 10` prints, back to its joint angles:
  aaria wrist ik --matrix 0.516245 -0.598741 0.612372 0.498566 0.791475 0.353553 \\
      -0.696364 0.122788 0.707107""",
)
@click.option(
    "--angles", nargs=3, type=FINITE_FLOAT,
    help="Tool rotation as three angles A B C in the sequence of --order, in that order"
    " (default xyz: A about the fixed x axis, then B about y, then C about z).",
)  # fmt: skip
@_order("Sequence of --angles, and of the angles printed.")
@click.option(
    "--matrix", nargs=9, type=FINITE_FLOAT,
    help="Tool rotation R11 R12 … R33, row by row. A matrix within 1e-5 of a rotation"
    " (largest |RᵀR - I| entry, e.g. the 6 decimals `wrist fk` prints) is projected onto the"
    " nearest rotation, with a note on stderr; beyond that it is refused.",
)  # fmt: skip
@click.option("--limits", is_flag=True, help="Keep solutions in the report's 0–360°, 0–180°.")
@_radians
@json_option()
def ik(angles: Any, order: str, matrix: Any, limits: bool, radians: bool, as_json: bool) -> None:
    """Every joint solution for a tool rotation given as angles or as a matrix."""
    from aaria_pin.apps.wrist.report import rotation_report

    if (angles is None) == (matrix is None):
        raise click.UsageError("give exactly one of --angles A B C or --matrix R11 … R33")
    _echo(rotation_report(angles, matrix, order, limits, not radians), as_json)


@wrist.command(
    context_settings={"ignore_unknown_options": True},
    epilog="""\b
Examples:
  aaria wrist simulate 60 45 -30 -o wrist.h5                  # trapezoid, 40°/s after 2 s
  aaria wrist simulate 60 45 -30 --profile ramp -o wrist.mat  # the report's ramp
  aaria wrist simulate 90 30 0 --speed 20 --rate 500 -o slow.h5""",
)
@click.argument("targets", nargs=3, type=FINITE_FLOAT)
@shown("--speed", default=40.0, type=FINITE_FLOAT, callback=_positive, help="Joint speed [deg/s].")
@shown("--acceleration", default=80.0, type=FINITE_FLOAT, callback=_positive,
    help="Acceleration limit of the trapezoid [deg/s^2].")  # fmt: skip
@shown("--profile", default="trapezoid", type=click.Choice(["trapezoid", "ramp"]),
    help="Smooth trapezoid (for torques) or the report's ramp.")  # fmt: skip
@grid_options("(default: 1 s after arrival)", 100.0)
@click.option("--radians", is_flag=True, help="Targets in radians (default degrees).")
@hardware_options
@click.option("-o", "--output", type=click.Path(dir_okay=False), required=True,
    help="Run file: .h5 or .mat (time, q, qd, qdd, tau, tool_pose).")  # fmt: skip
def simulate(targets: Any, radians: bool, output: str, **motion: Any) -> None:
    """Move the wrist to TARGETS (J1 J2 J3) after 2 s and write joint torques along the way.

    Its IMUs are noise-free: --imu-model (or [imu] of --hardware) is recorded, no signal changes.
    """
    import numpy as np

    from aaria_pin.aaria.hardware import hardware_run_options
    from aaria_pin.apps.wrist.run import simulate_wrist, write_wrist_run

    motion["hardware"] = hardware_run_options(motion.pop("imu_model"), motion.pop("hardware_file"))
    motion.update({key: np.radians(motion.pop(key)) for key in ("speed", "acceleration")})
    run = simulate_wrist(np.array(targets) if radians else np.radians(targets), **motion)
    peaks = "  ".join(f"{v:.4g}" for v in np.abs(run.tau).max(axis=0))
    write_wrist_run(output, run)
    click.echo(f"wrote {output}: {run.time.size} samples, peak |tau| per joint [N*m]: {peaks}")


@wrist.command(
    epilog="""\b
Examples:
  aaria wrist workspace                              # the report's 0-360°, 0-180°: the sphere
  aaria wrist workspace --theta2 0 90 --plot ws.png  # a hemisphere, and a picture of it
  aaria wrist workspace --samples 20000 --json       # one JSON object""",
)
@shown("--samples", default=200_000, type=click.IntRange(1, 10_000_000), help="Tool points.")
@shown("--theta1", default=(0.0, 360.0), nargs=2, type=FINITE_FLOAT, callback=_range,
    help="Joint 1 range LOW HIGH [deg] (the report's 0-360).")  # fmt: skip
@shown("--theta2", default=(0.0, 180.0), nargs=2, type=FINITE_FLOAT, callback=_range,
    help="Joint 2 range LOW HIGH [deg] (the report's 0-180).")  # fmt: skip
@shown("--seed", default=0, type=click.IntRange(0, MAX_SEED), help="Seed of the samples.")
@output_option("picture", PICTURE_SUFFIXES, "--plot", required=False,
    help="Write a picture of the tool points (.png, .pdf or .svg).")  # fmt: skip
@json_option()
def workspace(theta1: Any, theta2: Any, plot: Path | None, as_json: bool, **samples: Any) -> None:
    """Sample the reachable tool points: radius and covered solid angle."""
    import numpy as np

    from aaria_pin.apps.wrist.report import workspace_report
    from aaria_pin.apps.wrist.wrist_kinematics import wrist_workspace

    limits = np.radians([list(theta1), list(theta2), [-180.0, 180.0]])
    space = wrist_workspace(limits=limits, **samples)
    if plot:
        from aaria_pin.viz.report_plots import plot_workspace

        plot_workspace(space, plot)
    summary, text = workspace_report(space)
    click.echo(json.dumps(summary) if as_json else text + (f"\nwrote {plot}" if plot else ""))
