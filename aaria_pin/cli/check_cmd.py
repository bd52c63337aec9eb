"""``aaria check``: verify a whole run file or data set and list its damaged runs."""

import json
from pathlib import Path

import click

from aaria_pin.cli._options import json_option


@click.command(epilog="\b\nExamples:\n  aaria check ds.h5  # exit 0 intact, 1 damaged, 2 bad input")
@click.argument("file", type=click.Path(path_type=Path, dir_okay=False))
@json_option("Print {path, kind, runs, checked, ok, damaged: [{run, error}], notes} as JSON.")
def check(file: Path, as_json: bool) -> None:
    """Verify FILE whole, listing damaged runs (exit 1 if any); a data set's against checksums."""
    from aaria_pin.apps.check import check_file

    result = check_file(file)
    click.echo(json.dumps(result.to_json(), indent=2) if as_json else result.report())
    if not result.ok:
        raise SystemExit(1)
