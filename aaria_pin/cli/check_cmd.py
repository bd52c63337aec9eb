"""``aaria check``: verify a whole run file or data set and list its damaged runs."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING

import click

from aaria_pin.cli._options import json_option

if TYPE_CHECKING:
    from aaria_pin.apps.check import FileCheck


def _summary(result: FileCheck) -> str:
    """The first line: the file, what it is, how many runs were checked, how many damaged."""
    what = "data set" if result.kind == "dataset" else "run file"
    if None in result.damaged:
        return f"{result.path}: {what}: damaged"
    runs = f", {result.checked} of {result.runs} runs complete" if result.kind == "dataset" else ""
    state = "all intact" if result.ok else f"{len(result.damaged)} damaged"
    return f"{result.path}: {what}{runs}: {state}"


@click.command(
    epilog="""\b
Examples:
  aaria check ds.h5             # every complete run: readable, finite, its checksum
  aaria check run.h5 --json
Exit status: 0 nothing damaged; 1 damage found (each damaged run on a line); 2 not a file
it can check (missing, another suffix, not a run file or data set)."""
)
@click.argument("file", type=click.Path(path_type=Path, dir_okay=False))
@json_option("Print {path, kind, runs, checked, ok, damaged: [{run, error}], notes} as JSON.")
def check(file: Path, as_json: bool) -> None:
    """Verify FILE whole and list its damaged runs; exit 1 when damage is found.

    A data set: every complete run read, checked finite and compared with its checksum. A run
    file: read whole.
    """
    from aaria_pin.apps.check import check_file

    result = check_file(file)
    if as_json:
        click.echo(json.dumps(result.to_json(), indent=2))
    else:
        click.echo(_summary(result))
        for note in result.notes:
            click.echo(f"note: {note}")
        for why in result.damaged.values():  # one line each, naming its run
            click.echo(why)
    if not result.ok:
        raise SystemExit(1)
