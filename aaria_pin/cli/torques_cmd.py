"""``aaria torques``: torque-level analysis of any run file or data set, whatever the robot."""

from __future__ import annotations

import json
from pathlib import Path

import click

from aaria_pin.cli._options import json_option
from aaria_pin.cli._viz_options import PICTURE_SUFFIXES, output_option, run_option


@click.command(
    epilog="""\b
Examples:
  aaria torques run.h5                   # per joint: peak, RMS, its terms, energy
  aaria torques run.h5 --plot rms.png    # and the RMS of each term, side by side
  aaria torques ds.h5                    # a data set: peaks by module and joint type
  aaria torques ds.h5 --run 7 --json"""
)
@click.argument("file", type=click.Path(path_type=Path, dir_okay=False))
@run_option("One run of a data set.")
@json_option()
@output_option(
    "picture",
    PICTURE_SUFFIXES,
    "--plot",
    required=False,
    help="Picture (.png, .pdf, .svg) of each joint's RMS and its terms' RMS, side by side.",
)
def torques(file: Path, run_index: int | None, as_json: bool, plot: Path | None) -> None:
    """Peak and RMS torques, the RMS of their gravity / Coriolis / inertial terms, energy.

    The terms add up to tau at every sample; their RMS do not add up to tau's RMS (they are
    printed and drawn side by side, never stacked).

    FILE is a run file of any robot (a DH arm, a URDF robot, the wrist, the pick-place arm;
    any version) or a data set: a summary of its runs' peaks, or one run with --run.
    """
    from aaria_pin.apps.torques import run_torque_report, torque_text
    from aaria_pin.core.conflicts import OptionConflictError
    from aaria_pin.files.detection import is_dataset_file

    if plot and run_index is None and is_dataset_file(file):  # a summary has no plot
        raise OptionConflictError(parameter="plot", other="run", given_with=False, value=str(plot))
    report, one_run = run_torque_report(file, run_index)
    if plot:
        from aaria_pin.viz.report_plots import plot_torque_report

        plot_torque_report(report, plot, f"joint torques of {file.name}")
    click.echo(json.dumps(report) if as_json else torque_text(report, one_run))
