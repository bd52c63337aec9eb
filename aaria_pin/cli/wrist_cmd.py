"""``aaria wrist``: forward and inverse kinematics of the report's spherical wrist."""

from __future__ import annotations

import json
from typing import Any

import click

from aaria_pin.core.seeds import MAX_SEED

_NUMBER = click.FLOAT
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
    return {
        "rotation": pose[:3, :3].tolist(),
        "pose": pose.tolist(),
        "order": order,
        "angles": (angles.angles * scale).tolist(),
        "gimbal_lock": bool(angles.locked),
        "solutions": (ik.solutions * scale).tolist(),
        "singular": ik.singular,
        "reachable": ik.reachable,
    }


@click.group(context_settings={"ignore_unknown_options": True})
def wrist() -> None:
    """The spherical wrist of the wrist report (standard DH, d3 = 132 mm)."""


@wrist.command(context_settings={"ignore_unknown_options": True})
@click.argument("joints", nargs=3, type=_NUMBER)
@click.option(
    "--order",
    type=click.Choice(_ORDERS),
    default="xyz",
    show_default=True,
    help="Angle sequence to express the rotation in (lowercase: fixed axes).",
)
@click.option("--radians", is_flag=True, help="Angles in radians (default degrees).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
def fk(joints: tuple[float, float, float], order: str, radians: bool, as_json: bool) -> None:
    """Tool pose and angles of joint angles J1 J2 J3 (negative values work as they are)."""
    import numpy as np

    from aaria_pin.apps.wrist.kinematics import wrist_fk

    q = np.array(joints) if radians else np.radians(joints)
    _emit(_report(wrist_fk(q)[:3, :3], order, radians, limits=False), as_json, radians)


@wrist.command(context_settings={"ignore_unknown_options": True})
@click.option("--angles", nargs=3, type=_NUMBER, help="Tool rotation as three angles X Y Z.")
@click.option(
    "--order",
    type=click.Choice(_ORDERS),
    default="xyz",
    show_default=True,
    help="Sequence of --angles, and of the angles printed.",
)
@click.option("--matrix", nargs=9, type=_NUMBER, help="Tool rotation R11 R12 … R33, row by row.")
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
        raise click.UsageError("give exactly one of --angles X Y Z or --matrix R11 … R33")
    if angles is not None:
        values = np.array(angles) if radians else np.radians(angles)
        rotation = matrix_from_angles(values, order)
    else:
        rotation = np.array(matrix).reshape(3, 3)
    _emit(_report(rotation, order, radians, limits), as_json, radians)


@wrist.command(context_settings={"ignore_unknown_options": True})
@click.argument("targets", nargs=3, type=_NUMBER)
@click.option("--speed", type=float, default=40.0, show_default=True, help="Joint speed [deg/s].")
@click.option(
    "--acceleration",
    type=float,
    default=80.0,
    show_default=True,
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


@wrist.command()
@click.option("--samples", type=click.IntRange(1, 10_000_000), default=200_000, show_default=True)
@click.option(
    "--theta1",
    nargs=2,
    type=float,
    default=(0.0, 360.0),
    show_default=True,
    help="Joint 1 range [deg] (the report's 0-360).",
)
@click.option(
    "--theta2",
    nargs=2,
    type=float,
    default=(0.0, 180.0),
    show_default=True,
    help="Joint 2 range [deg] (the report's 0-180).",
)
@click.option("--seed", type=click.IntRange(0, MAX_SEED), default=0, show_default=True)
@click.option("--plot", type=click.Path(dir_okay=False), help="Write a PNG of the tool points.")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
def workspace(
    samples: int,
    theta1: tuple[float, float],
    theta2: tuple[float, float],
    seed: int,
    plot: str | None,
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
