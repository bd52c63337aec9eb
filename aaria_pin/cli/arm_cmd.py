"""``aaria arm``: the robotic-arm report's pick-and-place arm (URDF with meshes, the task)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from aaria_pin.cli._app import AariaGroup
from aaria_pin.cli._options import given, hardware_options, shown, stacked
from aaria_pin.cli._viz_options import output_option


def _within(bounds: str, unit: str) -> Any:
    """A callback refusing a number outside ``aaria_pin.viz.arm_pictures.<bounds>`` (one line)."""

    def check(_ctx: click.Context, param: click.Parameter, value: int) -> int:
        from aaria_pin.errors import ParameterError
        from aaria_pin.viz import arm_pictures

        low, high = getattr(arm_pictures, bounds)
        if not low <= value <= high:
            allowed = f"{low} to {high} {unit}"
            raise ParameterError(f"{param.name} {value}; allowed: {allowed}", parameter=param.name)
        return value

    return check


_PRESET = shown("--preset", default="pick-place-arm", help="Arm preset.")
_CYLINDER = stacked(
    shown("--radius", default=0.03, help="Gripped cylinder's radius [m]."),
    shown("--height", default=0.12, help="Gripped cylinder's height [m]."),
)


@click.group(
    cls=AariaGroup,
    epilog="""\b
Examples:
  aaria arm urdf -o arm/                    # arm/pick_place_arm.urdf and arm/meshes/*.stl
  aaria arm pick-place --cylinder 0.35 0.1 --place 0.2 -0.3 -o pp.h5 --sheet pp.png""",
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
@click.option("-o", "--output", "folder", required=True, type=click.Path(path_type=Path),
    help="Folder: writes pick_place_arm.urdf and meshes/*.stl.")  # fmt: skip
@_PRESET
@_CYLINDER
def urdf(folder: Path, preset: str, radius: float, height: float) -> None:
    """Write the arm's URDF and the STL meshes of its parts.

    Its frame 'grasp' is the centre of a gripped cylinder of --radius and --height.
    """
    from aaria_pin.apps.arm.report import write_arm_folder

    path, meshes = write_arm_folder(folder, preset, radius, height)
    click.echo(f"wrote {path} and {meshes} meshes in {folder / 'meshes'}")


@arm.command(
    "pick-place",
    epilog="""\b
Examples:
  aaria arm pick-place --cylinder 0.35 0.1 --place 0.2 -0.3 -o pp.h5
  aaria arm pick-place --cylinder 0.3 0.2 --place -0.3 0.2 --mass 1.5 --branch left \\
      -o pp.mat --sheet poses.png --animation task.gif --fps 15 --gif-size 400""",
)
@click.option("--cylinder", "cylinder_xy", nargs=2, type=float, required=True, metavar="X Y",
    help="Where the cylinder stands [m].")  # fmt: skip
@click.option("--place", "place_xy", nargs=2, type=float, required=True, metavar="X Y",
    help="Where to put it down [m].")  # fmt: skip
@shown("--mass", default=0.5, help="Cylinder mass [kg].")
@_CYLINDER
@shown("--branch", default="nearest", type=click.Choice(["nearest", "left", "right"]),
    help="IK branch of every move.")  # fmt: skip
@shown("--rate", default=100.0, help="Sample rate [Hz].")
@_PRESET
@hardware_options
@output_option("run file", (".h5", ".hdf5", ".mat"), help="Run file (.h5 or .mat).")
@output_option("contact sheet", (".png",), "--sheet", required=False,
    help="PNG contact sheet of the poses (start and end of every phase).")  # fmt: skip
@output_option("animation", (".gif",), "--animation", required=False,
    help="GIF animation of the task.")  # fmt: skip
@shown("--fps", default=10, callback=_within("ANIMATION_FPS", "frames per second"),
    help="Animation frame rate [frames per second of run time].")  # fmt: skip
@shown("--gif-size", default=300, callback=_within("ANIMATION_SIZES", "px"),
    help="Animation width and height [px].")  # fmt: skip
def pick_place(output: Path, sheet: Path | None, animation: Path | None, **task: Any) -> None:
    """Pick a cylinder from the floor and put it elsewhere: path, torques, run file.

    Prints the phases and each joint's peak torque [N*m] or force [N] and the payload's share
    of it; --sheet and --animation draw the task. The arm has no IMU: --imu-model is recorded only.
    """
    from aaria_pin.aaria.hardware import hardware_run_options
    from aaria_pin.apps.arm.report import pick_place_report
    from aaria_pin.apps.arm.run import simulate_pick_place, write_pick_place_run
    from aaria_pin.apps.arm.task import Cylinder
    from aaria_pin.core.conflicts import OptionConflictError

    # the files and --fps are checked while the options are read, before anything is computed
    fps, size = task.pop("fps"), task.pop("gif_size")
    for name, v in (("fps", fps), ("gif_size", size)):
        if animation is None and given(name):
            raise OptionConflictError(parameter=name, other="animation", given_with=False, value=v)
    task["hardware"] = hardware_run_options(task.pop("imu_model"), task.pop("hardware_file"))
    shape = [task.pop(key) for key in ("cylinder_xy", "radius", "height", "mass")]
    run = simulate_pick_place(Cylinder(*shape[0], *shape[1:]), task.pop("place_xy"), **task)
    write_pick_place_run(output, run)
    click.echo(f"wrote {output}: {run.path.time.size} samples, {run.path.time[-1]:.2f} s")
    text, warnings = pick_place_report(run)
    click.echo(text)
    for warning in warnings:
        click.echo(f"warning: {warning}", err=True)
    if sheet is not None:
        from aaria_pin.viz.arm_pictures import write_contact_sheet

        click.echo(f"wrote {write_contact_sheet(sheet, run)}")
    if animation is not None:
        from aaria_pin.viz.arm_pictures import write_animation

        frames = f"about {int(run.path.time[-1] * fps) + 1} frames of {size} x {size} px"
        click.echo(f"aaria: drawing the animation: {frames} at {fps} fps into {animation} …",
                   err=True)  # fmt: skip
        click.echo(f"wrote {write_animation(animation, run, fps=fps, size=size)}")
