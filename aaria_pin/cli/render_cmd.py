"""``aaria render``: a picture (PNG, PDF, SVG) of an arm in one pose, in the paper's colours."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from aaria_pin.cli._options import FINITE_FLOAT, shown, table_source
from aaria_pin.cli._viz_options import PICTURE_SUFFIXES, output_option, run_option


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
@click.option("--from", "run_file", type=click.Path(path_type=Path, dir_okay=False),
    help="Run file of any robot, or a data set (--run): the arm at --time.")  # fmt: skip
@run_option()
@click.option("--time", type=FINITE_FLOAT, help="Time in the run [s] (default: its start).")
@shown("--width", default=1000, help="Width [px].")
@shown("--height", default=800, help="Height [px].")
@shown("--elevation", default=20.0, type=FINITE_FLOAT,
    help="View elevation above the x-y plane [deg].")  # fmt: skip
@shown("--azimuth", default=-60.0, type=FINITE_FLOAT, help="View azimuth about z [deg].")
@output_option("picture", PICTURE_SUFFIXES)
def render(run_file: Path | None, run_index: int | None, output: Path, **options: Any) -> None:
    """Draw an arm in 3D: a preset or table with every joint at zero, or a run at a time.

    The output's suffix picks the format: .png (exactly --width x --height px), .pdf or .svg
    (vector, cropped to the drawing). Frame axes are red, green, blue = x, y, z; a legend names
    the colours.

    --preset also takes the model presets of plug-ins (pick-place-arm, the arm's viewer plug-in):
    the model at rest.
    """
    from aaria_pin.viz.render import PictureSettings, render_picture

    if [options["preset"], options["dh_file"], run_file].count(None) != 2:
        raise click.UsageError("give exactly one of --preset NAME, --dh FILE or --from RUN_FILE")
    view = {key: options.pop(key) for key in ("width", "height", "elevation", "azimuth")}
    settings = PictureSettings(**view)
    title = render_picture(output, run_file=run_file, run=run_index, settings=settings, **options)
    size = f"{view['width']} x {view['height']} px" if output.suffix.lower() == ".png" else "vector"
    click.echo(f"wrote {output}: {size}, {title}")
