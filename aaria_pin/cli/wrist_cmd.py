"""``aaria wrist``: forward and inverse kinematics of the report's spherical wrist."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import click

from aaria_pin.cli._options import FINITE_FLOAT
from aaria_pin.cli._viz_options import PICTURE_SUFFIXES, output_option
from aaria_pin.core.seeds import MAX_SEED
from aaria_pin.errors import ParameterError

MATRIX_TOLERANCE = 1e-5
"""Largest ``|RᵀR - I|`` entry of a ``--matrix`` accepted and projected onto the nearest
rotation: the 6-decimal matrix ``aaria wrist fk`` prints is within about 3e-6 of one."""

EXACT_TOLERANCE = 1e-12
"""``|RᵀR - I|`` up to which a ``--matrix`` is used as it is (no projection, no note)."""


_NUMBER = FINITE_FLOAT
_ORDERS = (
    "xyz",
    "xzy",
    "yxz",
    "yzx",
    "zxy",
    "zyx",
    "XYZ",
    "XZY",
    "YXZ",
    "YZX",
    "ZXY",
    "ZYX",
    "ZYZ",
    "zyz",
)


def _positive(ctx: click.Context, param: click.Parameter, value: float) -> float:
    if not value > 0:
        raise ParameterError(parameter=param.name, value=value, allowed="> 0")
    return value


def _range(
    ctx: click.Context, param: click.Parameter, value: tuple[float, float]
) -> tuple[float, float]:
    low, high = value
    if low > high:
        raise ParameterError(
            f"{param.opts[0]} is {low:g} {high:g} (reversed); allowed: LOW HIGH with LOW <= HIGH",
            parameter=param.name,
        )
    return value


def _emit(result: dict[str, Any], as_json: bool, radians: bool) -> None:
    if as_json:
        click.echo(json.dumps(result))
        return
    unit = "rad" if radians else "deg"
    click.echo("rotation:")
    for row in result["rotation"]:
        click.echo("  " + "  ".join(f"{v:+.6f}" for v in row))
    click.echo("tool point [m]: " + "  ".join(f"{row[3]:+.6f}" for row in result["pose"][:3]))
    click.echo(
        f"angles ({result['order']}) [{unit}]: " + "  ".join(f"{v:+.4f}" for v in result["angles"])
    )
    click.echo(
        f"joint solutions [{unit}]"
        + (" (singular: only θ1 ± θ3 is fixed)" if result["singular"] else "")
        + ":"
    )
    for solution in result["solutions"]:
        click.echo("  " + "  ".join(f"{v:+.4f}" for v in solution))
    if not result["solutions"]:
        click.echo("  none: unreachable within the joint limits")


def _report(rotation: Any, order: str, radians: bool, limits: bool) -> dict[str, Any]:
    import numpy as np

    from aaria_pin.apps.wrist.kinematics import REPORT_LIMITS, wrist_fk, wrist_ik
    from aaria_pin.core.rotations import angles_from_matrix

    ik = wrist_ik(rotation, REPORT_LIMITS if limits else None)
    reference = ik.solutions[0] if len(ik.solutions) else wrist_ik(rotation).solutions[0]
    pose = wrist_fk(reference)
    angles = angles_from_matrix(pose[:3, :3], order)
    scale = 1.0 if radians else 180.0 / np.pi
    if ik.residual > 1e-9:
        click.echo(
            f"aaria: note: the solutions reproduce the rotation to {ik.residual:.2g} only"
            " (a member of the singular family moved into the joint limits)",
            err=True,
        )
    return {
        "rotation": pose[:3, :3].tolist(),
        "pose": pose.tolist(),
        "order": order,
        "angles": (angles.angles * scale).tolist(),
        "gimbal_lock": bool(angles.locked),
        "solutions": (ik.solutions * scale).tolist(),
        "singular": ik.singular,
        "reachable": ik.reachable,
        "residual": ik.residual,
    }


def _matrix_rotation(values: tuple[float, ...]) -> Any:
    """The rotation of a ``--matrix``: as given, projected if within tolerance, else refused."""
    import numpy as np

    from aaria_pin.core.rotations import as_rotation, rotation_defect

    matrix = np.array(values, dtype=float).reshape(3, 3)
    defect, det = (float(v) for v in rotation_defect(matrix))
    if defect > MATRIX_TOLERANCE or det <= 0:
        raise ParameterError(
            f"--matrix is not a rotation (|RᵀR - I| = {defect:.3g}, det = {det:.6g}); allowed:"
            f" |RᵀR - I| <= {MATRIX_TOLERANCE:g} and det > 0, rows as `aaria wrist fk` prints them",
            parameter="matrix",
        )
    if defect <= EXACT_TOLERANCE:
        return matrix
    rotation, _ = as_rotation(matrix, tolerance=EXACT_TOLERANCE, project=True)
    moved = float(np.abs(rotation - matrix).max())
    click.echo(
        f"aaria: note: --matrix is {defect:.2g} from a rotation (|RᵀR - I|); using the nearest"
        f" rotation (SVD), {moved:.2g} from it",
        err=True,
    )
    return rotation


_ORDER_HELP = (
    "Named as scipy names them: lowercase about fixed axes ('xyz' = Rz·Ry·Rx),"
    " uppercase about moving axes ('ZYZ' = Rz·Ry·Rz, the wrist's own)."
)


@click.group(
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
@click.argument("joints", nargs=3, type=_NUMBER)
@click.option(
    "--order",
    type=click.Choice(_ORDERS),
    default="xyz",
    show_default=True,
    help="Angle sequence to express the rotation in. " + _ORDER_HELP,
)
@click.option("--radians", is_flag=True, help="Angles in radians (default degrees).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
def fk(joints: tuple[float, float, float], order: str, radians: bool, as_json: bool) -> None:
    """Tool pose and angles of joint angles J1 J2 J3 (negative values work as they are)."""
    import numpy as np

    from aaria_pin.apps.wrist.kinematics import wrist_fk

    q = np.array(joints) if radians else np.radians(joints)
    _emit(_report(wrist_fk(q)[:3, :3], order, radians, limits=False), as_json, radians)


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
    "--angles",
    nargs=3,
    type=_NUMBER,
    help="Tool rotation as three angles A B C in the sequence of --order, in that order"
    " (default xyz: A about the fixed x axis, then B about y, then C about z).",
)
@click.option(
    "--order",
    type=click.Choice(_ORDERS),
    default="xyz",
    show_default=True,
    help="Sequence of --angles, and of the angles printed. " + _ORDER_HELP,
)
@click.option(
    "--matrix",
    nargs=9,
    type=_NUMBER,
    help="Tool rotation R11 R12 … R33, row by row. A matrix within 1e-5 of a rotation"
    " (largest |RᵀR - I| entry, e.g. the 6 decimals `wrist fk` prints) is projected onto the"
    " nearest rotation, with a note on stderr; beyond that it is refused.",
)
@click.option("--limits", is_flag=True, help="Keep solutions in the report's 0–360°, 0–180°.")
@click.option("--radians", is_flag=True, help="Angles in radians (default degrees).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
def ik(
    angles: tuple[float, float, float] | None,
    order: str,
    matrix: tuple[float, ...] | None,
    limits: bool,
    radians: bool,
    as_json: bool,
) -> None:
    """Every joint solution for a tool rotation given as angles or as a matrix."""
    import numpy as np

    from aaria_pin.core.rotations import matrix_from_angles

    if (angles is None) == (matrix is None):
        raise click.UsageError("give exactly one of --angles A B C or --matrix R11 … R33")
    if angles is not None:
        values = np.array(angles) if radians else np.radians(angles)
        rotation = matrix_from_angles(values, order)
    else:
        rotation = _matrix_rotation(matrix)  # type: ignore[arg-type]
    _emit(_report(rotation, order, radians, limits), as_json, radians)


@wrist.command(
    context_settings={"ignore_unknown_options": True},
    epilog="""\b
Examples:
  aaria wrist simulate 60 45 -30 -o wrist.h5                  # trapezoid, 40°/s after 2 s
  aaria wrist simulate 60 45 -30 --profile ramp -o wrist.mat  # the report's ramp
  aaria wrist simulate 90 30 0 --speed 20 --rate 500 -o slow.h5""",
)
@click.argument("targets", nargs=3, type=_NUMBER)
@click.option(
    "--speed",
    type=_NUMBER,
    default=40.0,
    show_default=True,
    callback=_positive,
    help="Joint speed [deg/s].",
)
@click.option(
    "--acceleration",
    type=_NUMBER,
    default=80.0,
    show_default=True,
    callback=_positive,
    help="Acceleration limit of the trapezoid [deg/s^2].",
)
@click.option(
    "--profile",
    type=click.Choice(["trapezoid", "ramp"]),
    default="trapezoid",
    show_default=True,
    help="Smooth trapezoid (for torques) or the report's ramp.",
)
@click.option("--duration", type=float, help="Run length [s] (default: 1 s after arrival).")
@click.option("--rate", type=float, default=100.0, show_default=True, help="Sample rate [Hz].")
@click.option("--radians", is_flag=True, help="Targets in radians (default degrees).")
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False),
    required=True,
    help="Run file: .h5 or .mat (time, q, qd, qdd, tau, tool_pose).",
)
def simulate(
    targets: tuple[float, float, float],
    speed: float,
    acceleration: float,
    profile: str,
    duration: float | None,
    rate: float,
    radians: bool,
    output: str,
) -> None:
    """Move the wrist to TARGETS (J1 J2 J3) after 2 s and write joint torques along the way."""
    import numpy as np

    from aaria_pin.apps.wrist.run import simulate_wrist, write_wrist_run

    goal = np.array(targets) if radians else np.radians(targets)
    run = simulate_wrist(
        goal,
        speed=np.radians(speed),
        acceleration=np.radians(acceleration),
        profile="ramp" if profile == "ramp" else "trapezoid",
        duration=duration,
        rate=rate,
    )
    write_wrist_run(output, run)
    peaks = "  ".join(f"{v:.4g}" for v in np.abs(run.tau).max(axis=0))
    click.echo(f"wrote {output}: {run.time.size} samples, peak |tau| per joint [N*m]: {peaks}")


@wrist.command(
    epilog="""\b
Examples:
  aaria wrist workspace                              # the report's 0-360°, 0-180°: the sphere
  aaria wrist workspace --theta2 0 90 --plot ws.png  # a hemisphere, and a picture of it
  aaria wrist workspace --samples 20000 --json       # one JSON object""",
)
@click.option("--samples", type=click.IntRange(1, 10_000_000), default=200_000, show_default=True)
@click.option(
    "--theta1",
    nargs=2,
    type=_NUMBER,
    default=(0.0, 360.0),
    show_default=True,
    callback=_range,
    help="Joint 1 range LOW HIGH [deg] (the report's 0-360).",
)
@click.option(
    "--theta2",
    nargs=2,
    type=_NUMBER,
    default=(0.0, 180.0),
    show_default=True,
    callback=_range,
    help="Joint 2 range LOW HIGH [deg] (the report's 0-180).",
)
@click.option("--seed", type=click.IntRange(0, MAX_SEED), default=0, show_default=True)
@output_option(
    "picture",
    PICTURE_SUFFIXES,
    "--plot",
    required=False,
    help="Write a picture of the tool points (.png, .pdf or .svg).",
)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
def workspace(
    samples: int,
    theta1: tuple[float, float],
    theta2: tuple[float, float],
    seed: int,
    plot: Path | None,
    as_json: bool,
) -> None:
    """Sample the reachable tool points: radius and covered solid angle."""
    import numpy as np

    from aaria_pin.apps.wrist.kinematics import wrist_workspace

    limits = np.radians([list(theta1), list(theta2), [-180.0, 180.0]])
    space = wrist_workspace(samples, limits, seed=seed)
    if plot:
        from aaria_pin.viz.report_plots import plot_workspace

        plot_workspace(space, plot)
    summary = {
        "radius_m": list(space.radius),
        "solid_angle_sr": space.solid_angle,
        "solid_angle_exact_sr": space.solid_angle_exact,
        "sphere_fraction": space.solid_angle / (4 * np.pi),
        "samples": samples,
    }
    if as_json:
        click.echo(json.dumps(summary))
        return
    click.echo(
        f"tool points on the sphere of radius {space.radius[1] * 1000:.3f} mm "
        f"(sampled radii {space.radius[0] * 1000:.3f}-{space.radius[1] * 1000:.3f} mm)"
    )
    exact = (
        f", exactly {space.solid_angle_exact:.4f} sr from the joint ranges"
        if space.solid_angle_exact is not None
        else ""
    )
    click.echo(
        f"covered solid angle {space.solid_angle:.4f} sr "
        f"({summary['sphere_fraction']:.1%} of the sphere){exact}"
    )
    if plot:
        click.echo(f"wrote {plot}")
