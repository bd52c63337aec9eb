"""``aaria bench-task``: the benchmark tasks (list, make, score, baseline) over the library."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import click

from aaria_pin.cli._app import AariaGroup
from aaria_pin.cli._options import json_option

_FOLDER = click.Path(path_type=Path, file_okay=False)
_FILE = click.Path(path_type=Path, dir_okay=False)


@click.group("bench-task", cls=AariaGroup, epilog="""\b
Examples:
  aaria bench-task list
  aaria bench-task make structure -o structure/
  aaria bench-task baseline structure structure/ -o id.npz
  aaria bench-task score structure structure/ id.npz""")  # fmt: skip
def bench_task() -> None:
    """Benchmark tasks: a fixed data set, splits by run, a metric, a scorer of predictions."""


@bench_task.command("list", epilog="\b\nExamples:\n  aaria bench-task list")
def list_() -> None:
    """The tasks, one line each."""
    from aaria_pin.apps.bench_tasks.registry import TASKS

    for task in TASKS.values():
        click.echo(f"{task.name:<17} {task.summary}")


@bench_task.command(epilog="\b\nExamples:\n  aaria bench-task make structure -o structure/")
@click.argument("task")
@click.option("-o", "--output", "directory", type=_FOLDER, required=True, help="Task folder.")
@click.option("--runs", "n_runs", type=int, help="Fewer runs than the task's (not the benchmark).")
@click.option("--duration", type=float, help="Shorter runs [s] (not the benchmark).")
@click.option("--workers", type=click.IntRange(1, 1024), help="Worker processes [cores].")
@click.option("--overwrite", is_flag=True, help="Replace the folder's data set.")
def make(task: str, **settings: Any) -> None:
    """Write TASK's data set (dataset.h5) and card (task.json) into a folder."""
    from aaria_pin.apps.bench_tasks.make import make_task

    click.echo(f"wrote {make_task(task, **settings)}")


@bench_task.command(epilog="\b\nExamples:\n  aaria bench-task score structure structure/ pred.npz")
@click.argument("task")
@click.argument("directory", type=_FOLDER)
@click.argument("predictions", type=_FILE)
@json_option("Print the score as JSON (with per-run values).")
def score(task: str, directory: Path, predictions: Path, as_json: bool) -> None:
    """Score a predictions file (NPZ, one array run_<k> per test run) on TASK's test runs."""
    from aaria_pin.apps.bench_tasks.scoring import score_lines, score_task

    result = score_task(task, directory, predictions)
    click.echo(json.dumps(result, indent=2) if as_json else "\n".join(score_lines(result)))


@bench_task.command(epilog="""\b
Examples:
  aaria bench-task baseline structure structure/ -o id.npz
  aaria bench-task baseline structure structure/ -o warm.npz --start learned.npz""")  # fmt: skip
@click.argument("task")
@click.argument("directory", type=_FOLDER)
@click.option("-o", "--output", type=_FILE, required=True, help="Predictions file (.npz).")
@click.option(
    "--baseline",
    help="structure: identify, nominal; inverse-dynamics: zero, train-mean, rigid-body,"
    " rigid-body-truth (the ceiling);"
    " sensor-to-state: train-mean [the first].",
)
@click.option("--workers", type=click.IntRange(1, 1024), default=1, show_default=True,
              help="Processes (identify, rigid-body).")  # fmt: skip
@click.option("--start", type=_FILE, help="identify: start each arm's fit from its table in"
              " this structure predictions file (.npz).")  # fmt: skip
def baseline(task: str, directory: Path, output: Path, **settings: Any) -> None:
    """Write a baseline's predictions of TASK's test runs (structure: aaria identify)."""
    from aaria_pin.apps.bench_tasks.baselines import run_baseline

    click.echo(f"wrote {run_baseline(task, directory, output, **settings)}")
