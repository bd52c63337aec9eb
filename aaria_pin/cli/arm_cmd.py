"""``aaria arm``: the robotic-arm report's pick-and-place arm (URDF with meshes, the task)."""

from __future__ import annotations

from pathlib import Path

import click

from aaria_pin.cli._viz_options import output_option


def _check_fps(_ctx: click.Context, _param: click.Parameter, fps: int) -> int:
    """Refuse a frame rate outside :data:`aaria_pin.viz.arm_pictures.ANIMATION_FPS` (one line)."""
    from aaria_pin.errors import ParameterError
    from aaria_pin.viz.arm_pictures import ANIMATION_FPS

    low, high = ANIMATION_FPS
    if not low <= fps <= high:
        raise ParameterError(f"--fps {fps}; allowed: {low} to {high} frames per second")
    return fps


def _check_gif_size(_ctx: click.Context, _param: click.Parameter, size: int) -> int:
    """Refuse a GIF size outside :data:`aaria_pin.viz.arm_pictures.ANIMATION_SIZES` (one line)."""
    from aaria_pin.errors import ParameterError
    from aaria_pin.viz.arm_pictures import ANIMATION_SIZES

    low, high = ANIMATION_SIZES
    if not low <= size <= high:
        raise ParameterError(f"--gif-size {size}; allowed: {low} to {high} px")
    return size


@click.group(
    epilog="""\b
Examples:
  aaria arm urdf -o arm/                    # arm/pick_place_arm.urdf and arm/meshes/*.stl
  aaria arm pick-place --cylinder 0.35 0.1 --place 0.2 -0.3 -o pp.h5 --sheet pp.png"""
)
def arm() -> None:
    """The pick-and-place arm of the robotic-arm report."""


@arm.command(
    "urdf",
    epilog="""\b
Examples:
  aaria arm urdf -o arm/                                # the report's cylinder
  aaria arm urdf -o arm_big/ --radius 0.04 --height 0.2
  aaria view pp.h5 -o pp.html                           # a pick-place run, with its meshes""",
)
@click.option(
    "-o",
    "--output",
    "folder",
    required=True,
    type=click.Path(path_type=Path),
    help="Folder: writes pick_place_arm.urdf and meshes/*.stl.",
)
@click.option("--preset", default="pick-place-arm", show_default=True, help="Arm preset.")
@click.option(
    "--radius", type=float, default=0.03, show_default=True, help="Gripped cylinder's radius [m]."
)
@click.option(
    "--height", type=float, default=0.12, show_default=True, help="Gripped cylinder's height [m]."
)
def urdf(folder: Path, preset: str, radius: float, height: float) -> None:
    """Write the arm's URDF and the STL meshes of its parts.

    Its frame 'grasp' is the centre of a gripped cylinder of --radius and --height.
    """
    from aaria_pin.apps.arm.preset import arm_parts, get_arm_preset, write_arm_urdf
    from aaria_pin.apps.arm.task import Cylinder

    dims = get_arm_preset(preset)
    Cylinder(0.0, 0.0, radius, height)  # checks the numbers
    parts = arm_parts(dims)
    path = write_arm_urdf(folder, dims, (radius, height), parts)
    click.echo(f"wrote {path} and {len(parts)} meshes in {folder / 'meshes'}")


@arm.command(
    "pick-place",
    epilog="""\b
Examples:
  aaria arm pick-place --cylinder 0.35 0.1 --place 0.2 -0.3 -o pp.h5
  aaria arm pick-place --cylinder 0.3 0.2 --place -0.3 0.2 --mass 1.5 --branch left \\
      -o pp.mat --sheet poses.png --animation task.gif --fps 15 --gif-size 400""",
)
@click.option(
    "--cylinder",
    "cylinder_xy",
    nargs=2,
    type=float,
    required=True,
    metavar="X Y",
    help="Where the cylinder stands [m].",
)
@click.option(
    "--place",
    "place_xy",
    nargs=2,
    type=float,
    required=True,
    metavar="X Y",
    help="Where to put it down [m].",
)
@click.option("--mass", type=float, default=0.5, show_default=True, help="Cylinder mass [kg].")
@click.option("--radius", type=float, default=0.03, show_default=True, help="Radius [m].")
@click.option("--height", type=float, default=0.12, show_default=True, help="Height [m].")
@click.option(
    "--branch",
    type=click.Choice(["nearest", "left", "right"]),
    default="nearest",
    show_default=True,
    help="IK branch of every move.",
)
@click.option("--rate", type=float, default=100.0, show_default=True, help="Sample rate [Hz].")
@click.option("--preset", default="pick-place-arm", show_default=True, help="Arm preset.")
@output_option("run file", (".h5", ".hdf5", ".mat"), help="Run file (.h5 or .mat).")
@output_option(
    "contact sheet",
    (".png",),
    "--sheet",
    required=False,
    help="PNG contact sheet of the poses (start and end of every phase).",
)
@output_option(
    "animation", (".gif",), "--animation", required=False, help="GIF animation of the task."
)
@click.option(
    "--fps",
    type=int,
    default=10,
    show_default=True,
    callback=_check_fps,
    help="Animation frame rate [frames per second of run time].",
)
@click.option(
    "--gif-size",
    type=int,
    default=300,
    show_default=True,
    callback=_check_gif_size,
    help="Animation width and height [px].",
)
def pick_place(
    cylinder_xy: tuple[float, float],
    place_xy: tuple[float, float],
    mass: float,
    radius: float,
    height: float,
    branch: str,
    rate: float,
    preset: str,
    output: Path,
    sheet: Path | None,
    animation: Path | None,
    fps: int,
    gif_size: int,
) -> None:
    """Pick a cylinder from the floor and put it elsewhere: path, torques, run file.

    Prints the phases and each joint's peak torque [N*m] or force [N] and the payload's share
    of it; --sheet and --animation draw the task.
    """
    import numpy as np

    from aaria_pin.apps.arm.preset import ARM_JOINTS, arm_joints, get_arm_preset
    from aaria_pin.apps.arm.run import effort_excess, simulate_pick_place, write_pick_place_run
    from aaria_pin.apps.arm.task import PHASES, Cylinder

    # the files and --fps are checked while the options are read, before anything is computed
    cylinder = Cylinder(cylinder_xy[0], cylinder_xy[1], radius, height, mass)
    run = simulate_pick_place(cylinder, place_xy, preset=preset, rate=rate, branch=branch)
    write_pick_place_run(output, run)
    click.echo(f"wrote {output}: {run.path.time.size} samples, {run.path.time[-1]:.2f} s")
    for name, (start, end) in zip(PHASES, run.path.boundaries, strict=True):
        click.echo(f"  {name:<9} {start:6.2f} - {end:6.2f} s")
    peak = np.abs(run.tau).max(axis=0)
    share = np.abs(run.tau - run.tau_free).max(axis=0)
    units = {
        joint.name: "N" if joint.kind == "prismatic" else "N*m"
        for joint in arm_joints(get_arm_preset(preset))
    }
    click.echo("  joint       peak |tau|       payload share (peak)")
    for joint, p, s in zip(ARM_JOINTS, peak, share, strict=True):
        unit = units[joint]
        click.echo(f"  {joint:<10} {p:10.4g} {unit:<3}   {s:10.4g} {unit}")
    for joint, peak_value, limit in effort_excess(run):
        unit = units[joint]
        click.echo(
            f"warning: {joint} peak |tau| {peak_value:.4g} {unit} exceeds the URDF effort limit "
            f"{limit:g} {unit}",
            err=True,
        )
    if sheet is not None:
        from aaria_pin.viz.arm_pictures import write_contact_sheet

        click.echo(f"wrote {write_contact_sheet(sheet, run)}")
    if animation is not None:
        from aaria_pin.viz.arm_pictures import write_animation

        frames = int(run.path.time[-1] * fps) + 1
        click.echo(
            f"aaria: drawing the animation: about {frames} frames of {gif_size} x {gif_size} px "
            f"at {fps} fps into {animation} …",
            err=True,
        )
        click.echo(f"wrote {write_animation(animation, run, fps=fps, size=gif_size)}")
