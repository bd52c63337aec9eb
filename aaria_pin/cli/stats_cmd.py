"""``aaria dataset-stats``: per-channel mean and std of a data set's arrays over one split.

The statistics a training loop normalises with (:meth:`DatasetReader.statistics
<aaria_pin.files.dataset.reader.DatasetReader.statistics>`): one streaming pass over the split's
complete runs; ``--store`` writes them into the file (``statistics/<split>/<name>/mean|std``),
where ``DatasetReader.windows(..., normalise=True)`` finds them.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import click

_ALL = "all"
"""The ``--split`` value for every complete run."""


def _names(text: str | None) -> tuple[str, ...] | None:
    return tuple(part.strip() for part in text.split(",") if part.strip()) if text else None


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
    "--names",
    default=None,
    help="Arrays or views, comma-separated (senSen, signals, imu, q, tau, …); default the "
    "first view.",
)
@click.option(
    "--split",
    type=click.Choice(["train", "validation", "test", _ALL]),
    default="train",
    show_default=True,
    help="The runs: a split by run, or all complete runs.",
)
@click.option("--seed", type=int, default=0, show_default=True, help="The split's seed.")
@click.option(
    "--fractions",
    default="0.8,0.1,0.1",
    show_default=True,
    help="Fractions of the runs in the train, validation and test splits.",
)
@click.option("--store", is_flag=True, help="Store them in the file (replacing the split's).")
@click.option("--json", "as_json", is_flag=True, help="Print {name: {mean, std}} as JSON.")
def dataset_stats(
    file: Path,
    names: str | None,
    split: str,
    seed: int,
    fractions: str,
    store: bool,
    as_json: bool,
) -> None:
    """Per-channel mean and std of a data set's arrays over the training split (or another)."""
    import numpy as np

    from aaria_pin.errors import ParameterError
    from aaria_pin.files.dataset.reader import DatasetReader
    from aaria_pin.files.io import existing_input

    try:
        shares = tuple(float(part) for part in fractions.split(","))
    except ValueError:
        raise ParameterError(
            parameter="fractions", value=fractions, allowed="three numbers, e.g. 0.8,0.1,0.1"
        ) from None
    chosen_split = None if split == _ALL else split
    existing_input(file, None, "data set")  # a missing file or a folder in one line
    with DatasetReader(file) as reader:
        statistics = reader.statistics(
            _names(names), split=chosen_split, seed=seed, fractions=shares, store=store
        )
        runs = len(reader.split_runs(chosen_split, seed, shares))
        views = reader.layout.views if reader.layout is not None else {}
    if as_json:
        document: dict[str, Any] = {
            name: {"mean": mean.tolist(), "std": std.tolist()}
            for name, (mean, std) in statistics.items()
        }
        click.echo(json.dumps(document, indent=2))
        return
    click.echo(f"{file}: split {split} (seed {seed}, fractions {fractions}), {runs} runs")
    for name, (mean, std) in statistics.items():
        shape = " × ".join(map(str, mean.shape)) or "scalar"
        click.echo(f"{name} ({shape} channels)")
        click.echo(f"  {'channel':<24} {'mean':>14} {'std':>14}")
        columns = views[name].columns if name in views else None
        for index in np.ndindex(mean.shape):
            label = columns[index[0]] if columns is not None else str(list(index))
            click.echo(f"  {label:<24} {mean[index]:>14.6g} {std[index]:>14.6g}")
    if store:
        click.echo(f"stored in {file} under statistics/{split}")
