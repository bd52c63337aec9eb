"""``aaria dataset-stats``: per-channel mean and std of a data set's arrays over one split."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import click

from aaria_pin.cli._options import json_option, shown


def _numbers(_ctx: click.Context, param: click.Parameter, text: str) -> tuple[float, ...]:
    from aaria_pin.errors import ParameterError

    try:
        return tuple(float(part) for part in text.split(","))
    except ValueError:
        raise ParameterError(
            parameter=param.name, value=text, allowed="three numbers, e.g. 0.8,0.1,0.1"
        ) from None


def _names(_ctx: click.Context, _param: click.Parameter, text: str | None) -> Any:
    return None if text is None else tuple(p.strip() for p in text.split(",") if p.strip())


@click.command(
    "dataset-stats",
    epilog="""\b
Examples:
  aaria dataset-stats ds.h5                      # the training split's senSen channels
  aaria dataset-stats ds.h5 --names imu,tau --store
  aaria dataset-stats ds.h5 --split all --json""",
)
@click.argument("file", type=click.Path(path_type=Path, dir_okay=False))
@click.option(
    "--names", callback=_names,
    help="Arrays or views, comma-separated (senSen, signals, imu, q, tau, …); default the "
    "first view.",
)  # fmt: skip
@shown("--split", default="train", type=click.Choice(["train", "validation", "test", "all"]),
    help="The runs: a split by run, or all complete runs.")  # fmt: skip
@shown("--seed", default=0, help="The split's seed.")
@shown("--fractions", default="0.8,0.1,0.1", callback=_numbers,
    help="Fractions of the runs in the train, validation and test splits.")  # fmt: skip
@click.option("--store", is_flag=True, help="Store them in the file (replacing the split's).")
@json_option("Print {name: {mean, std}} as JSON.")
def dataset_stats(file: Path, as_json: bool, **settings: Any) -> None:
    """Per-channel mean and std of a data set's arrays over the training split (or another)."""
    from aaria_pin.apps.file_summary import statistics_report

    document, text = statistics_report(file, **settings)
    click.echo(json.dumps(document, indent=2) if as_json else text)
