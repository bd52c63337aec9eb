"""``aaria render``: a picture (PNG, PDF, SVG) of an arm in one pose, in the paper's colours."""

from __future__ import annotations

from pathlib import Path

import click

from aaria_pin.cli._options import FINITE_FLOAT, load_table_source, table_source
from aaria_pin.cli._viz_options import PICTURE_SUFFIXES, check_run_option, output_option


@click.command(
    epilog="""\b
Examples:
  aaria render --preset aaria-fig2 -o fig2.png                 # every joint at zero
  aaria render --preset pick-place-arm --elevation 30 -o arm.svg
  aaria render --from run.h5 --time 2.5 --width 600 --height 450 -o pose.png
  aaria render --from ds.h5 --run 3 -o run3.pdf                # a data set's run 3"""
)
@table_source(
    "Built-in table (aaria-fig2, aaria-fig3, spherical-wrist) or a plug-in's model preset "
    "(pick-place-arm); an unknown name lists those installed."
)
@click.option(
    "--from",
    "run_file",
    type=click.Path(path_type=Path, dir_okay=False),
    help="Run file of any robot, or a data set (--run): the arm at --time.",
)
@click.option(
    "--run", "run_index", type=click.IntRange(0), help="One run of a data set (default 0)."
)
@click.option(
    "--time", "at_time", type=FINITE_FLOAT, help="Time in the run [s] (default: its start)."
)
@click.option("--width", type=int, default=1000, show_default=True, help="Width [px].")
@click.option("--height", type=int, default=800, show_default=True, help="Height [px].")
@click.option(
    "--elevation",
    type=FINITE_FLOAT,
    default=20.0,
    show_default=True,
    help="View elevation above the x-y plane [deg].",
)
@click.option(
    "--azimuth",
    type=FINITE_FLOAT,
    default=-60.0,
    show_default=True,
    help="View azimuth about z [deg].",
)
@output_option("picture", PICTURE_SUFFIXES)
def render(
    preset: str | None,
    dh_file: Path | None,
    convention: str,
    run_file: Path | None,
    run_index: int | None,
    at_time: float | None,
    width: int,
    height: int,
    elevation: float,
    azimuth: float,
    output: Path,
) -> None:
    """Draw an arm in 3D: a preset or table with every joint at zero, or a run at a time.

    The output's suffix picks the format: .png (exactly --width x --height px), .pdf or .svg
    (vector, cropped to the drawing). Frame axes are red, green, blue = x, y, z; a legend names
    the colours.

    --preset also takes the model presets of plug-ins (pick-place-arm, the arm's viewer plug-in):
    the model at rest.
    """
    import numpy as np

    from aaria_pin.viz.render import render_geometry
    from aaria_pin.viz.scene import posed_geometry
    from aaria_pin.viz.sources import load_run_view, preset_view, sample_at, table_view

    if [preset, dh_file, run_file].count(None) != 2:
        raise click.UsageError("give exactly one of --preset NAME, --dh FILE or --from RUN_FILE")
    if run_file is None and at_time is not None:
        raise click.UsageError("--time needs --from RUN_FILE")
    if run_file is None and run_index is not None:
        raise click.UsageError("--run needs --from DATASET")
    if run_file is not None:
        check_run_option(run_file, run_index)
        view = load_run_view(run_file, run_index)
        k = sample_at(view.time, view.time[0] if at_time is None else at_time)
        scene, poses = view.scene, view.frame_poses(np.array([k]))[0]
        title = f"{view.title}, t = {view.time[k]:.3f} s"
    elif preset is not None:
        scene, poses = preset_view(preset)
        title = scene.name
    else:
        table, table_convention, name = load_table_source(None, dh_file, convention)
        scene, poses = table_view(table, table_convention, name)
        title = dh_file.name if dh_file is not None else name
    render_geometry(
        posed_geometry(scene, poses),
        output,
        title,
        width=width,
        height=height,
        elevation=elevation,
        azimuth=azimuth,
    )
    size = f"{width} x {height} px" if output.suffix.lower() == ".png" else "vector"
    click.echo(f"wrote {output}: {size}, {title}")
