"""``aaria info``: a summary of a run file (any robot, any version) or a data set; a data card."""

from __future__ import annotations

import json
from pathlib import Path

import click

from aaria_pin.cli._options import json_option


@click.command(
    epilog="""\b
Examples:
  aaria info run.h5               # a run: robot, samples, rate, joints, IMUs, arrays
  aaria info ds.h5                # a data set: runs complete and failed, settings, arrays
  aaria info --card ds.h5         # its data card
  aaria info --json ds.h5         # the summary as JSON"""
)
@click.argument("file", type=click.Path(path_type=Path, dir_okay=False))
@json_option("Print the summary (or the card) as JSON.")
@click.option(
    "--card",
    is_flag=True,
    help="Print a data set's card: command, versions, ranges, columns with units and frames, "
    "noise, runs by structure, failures.",
)
def info(file: Path, as_json: bool, card: bool) -> None:
    """Summarise a run file or a data set: kind, robot, samples, rate, joints, IMUs, arrays.

    With --card, a data set's data card instead (the stored one when current).
    """
    from aaria_pin.apps.file_summary import describe_file

    summary, text = describe_file(file, card)
    click.echo(json.dumps(summary, indent=2, default=str) if as_json else text, nl=as_json)
