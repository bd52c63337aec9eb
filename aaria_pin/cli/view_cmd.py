"""``aaria view``: a self-contained HTML page that plays a run in 3D."""

from __future__ import annotations

from pathlib import Path

import click

from aaria_pin.cli._options import shown
from aaria_pin.cli._viz_options import output_option, run_option


@click.command(
    epilog="""\b
Examples:
  aaria view run.h5 -o run.html                      # open it in a browser, offline
  aaria view ds.h5 --run 5 --max-samples 2000 -o run5.html"""
)
@click.argument("run_file", type=click.Path(path_type=Path, dir_okay=False))
@run_option()
@shown("--max-samples", default=500, type=click.IntRange(2),
    help="Most samples in the page (the run is decimated evenly).")  # fmt: skip
@output_option("HTML page", (".html", ".htm"))
def view(run_file: Path, run_index: int | None, max_samples: int, output: Path) -> None:
    """Write an HTML page that plays the run in 3D, its signals beside it (works offline).

    The robot is drawn with its URDF visual geometry (meshes, boxes, cylinders, spheres),
    frame axes red, green, blue = x, y, z; beside it the chosen IMU's six signals and the joint
    torques, with a cursor at the shown time.

    RUN_FILE is a run file of any robot (any version) or a data set (--run picks the run).
    """
    from aaria_pin.viz.html import write_run_viewer

    shown_samples, samples = write_run_viewer(run_file, output, run_index, max_samples)
    size = output.stat().st_size / 1e6
    click.echo(f"wrote {output}: {shown_samples} of {samples} samples, {size:.2f} MB")
