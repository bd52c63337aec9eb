"""``aaria view``: a self-contained HTML page that plays a run in 3D."""

from __future__ import annotations

from pathlib import Path

import click

from aaria_pin.cli._viz_options import check_run_option, output_option


@click.command(
    epilog="""\b
Examples:
  aaria view run.h5 -o run.html                      # open it in a browser, offline
  aaria view ds.h5 --run 5 --max-samples 2000 -o run5.html"""
)
@click.argument("run_file", type=click.Path(path_type=Path, dir_okay=False))
@click.option(
    "--run", "run_index", type=click.IntRange(0), help="One run of a data set (default 0)."
)
@click.option(
    "--max-samples",
    type=click.IntRange(2),
    default=500,
    show_default=True,
    help="Most samples in the page (the run is decimated evenly).",
)
@output_option("HTML page", (".html", ".htm"))
def view(run_file: Path, run_index: int | None, max_samples: int, output: Path) -> None:
    """Write an HTML page that plays the run in 3D, its signals beside it (works offline).

    The robot is drawn with its URDF visual geometry (meshes, boxes, cylinders, spheres),
    frame axes red, green, blue = x, y, z; beside it the chosen IMU's six signals and the joint
    torques, with a cursor at the shown time.

    RUN_FILE is a run file of any robot (any version) or a data set (--run picks the run).
    """
    from aaria_pin.viz.html import shown_samples, signal_panels, write_viewer
    from aaria_pin.viz.sources import load_run_view

    check_run_option(run_file, run_index)
    run = load_run_view(run_file, run_index)
    samples = shown_samples(run.time.size, max_samples)
    panels = signal_panels(run.signals, samples)
    poses = run.frame_poses(samples)
    write_viewer(output, run.scene, run.time[samples], poses, run.title, panels)
    size = output.stat().st_size
    click.echo(f"wrote {output}: {samples.size} of {run.time.size} samples, {size / 1e6:.2f} MB")
