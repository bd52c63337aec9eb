"""``aaria identify --dataset``: the identification benchmark over data sets, as a table and a plot.

The body of the command, called by :mod:`aaria_pin.cli.identify_cmd` for ``--dataset``.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

if TYPE_CHECKING:
    from aaria_pin.apps.identify.benchmark import RunAccuracy

__all__ = ["dataset_command", "plot_tool_tip_cdf", "print_accuracy_table"]


def _mm(value: float | None) -> str:
    return "-" if value is None else f"{value * 1e3:.3g}"


def print_accuracy_table(groups: Sequence[dict[str, Any]]) -> None:
    """Print :func:`~aaria_pin.apps.identify.benchmark.accuracy_table` as a text table."""
    from aaria_pin.apps.identify.benchmark import group_label

    width = max([len(group_label(g)) for g in groups] + [5])
    dynamics = any("dynamics_holdout_relative_rms_median" in g for g in groups)
    header = (
        f"{'group':<{width}} {'arms':>5} {'failed':>6} {'types right':>11} "
        f"{'tool tip RMS [mm]: median':>25} {'p95':>7} {'max':>7} {'<=1 mm':>7} {'<=1 cm':>7} "
        f"{'s/arm':>6}"
    )
    click.echo(header + (f" {'torque held-out rel. RMS':>24}" if dynamics else ""))
    for g in groups:
        line = (
            f"{group_label(g):<{width}} {g['runs']:>5} {g['failed']:>6} "
            f"{g['link_types_right_share']:>11.1%} {_mm(g['tool_tip_rms_median_m']):>25} "
            f"{_mm(g['tool_tip_rms_p95_m']):>7} {_mm(g['tool_tip_rms_max_m']):>7} "
            f"{g['within_1mm_share']:>7.1%} {g['within_1cm_share']:>7.1%} "
            f"{g['seconds_median']:>6.1f}"
        )
        if dynamics:
            value = g.get("dynamics_holdout_relative_rms_median")
            line += f" {'-' if value is None else format(value, '.3g'):>24}"
        click.echo(line)


def plot_tool_tip_cdf(
    path: Path, runs: Sequence[RunAccuracy], groups: Sequence[dict[str, Any]]
) -> None:
    """The cumulative distribution of the tool-tip RMS error per group (log scale), to a picture.

    Args:
        path: ``.png``, ``.pdf`` or ``.svg``
        runs: the runs' results
        groups: their groups (:func:`~aaria_pin.apps.identify.benchmark.accuracy_table`)
    """
    import numpy as np

    from aaria_pin.apps.identify.benchmark import WITHIN, group_label
    from aaria_pin.viz._figure import figure_file

    with figure_file(path, 800, 500, layout="constrained") as figure:
        axes = figure.add_subplot()
        for g in groups:
            key = (g["noise"], g["duration_s"], g["rate_hz"])
            errors = np.sort(
                [
                    r.tool_tip_rms if np.isfinite(r.tool_tip_rms) else np.inf
                    for r in runs
                    if (r.noise, r.duration, r.rate) == key
                ]
            )
            share = np.arange(1, errors.size + 1) / errors.size
            finite = np.isfinite(errors)
            axes.step(
                np.maximum(errors[finite], 1e-9),
                share[finite],
                where="post",
                label=f"{group_label(g)} ({g['runs']} arms)",
            )
        for threshold in WITHIN:
            axes.axvline(threshold, color="0.6", linestyle=":", linewidth=1)
        axes.set_xscale("log")
        axes.set_ylim(0.0, 1.0)
        axes.set_xlabel("tool-tip position RMS error over the run [m]")
        axes.set_ylabel("share of arms")
        axes.set_title("aaria identify: kinematic identification against the truth")
        axes.grid(True, which="both", alpha=0.3)
        axes.legend(loc="lower right")


def dataset_command(
    files: Sequence[Path],
    *,
    workers: int = 1,
    dynamics: bool = False,
    limit: int | None = None,
    as_json: bool = False,
    output: Path | None = None,
    plot: Path | None = None,
) -> dict[str, Any]:
    """Identify every run of the data sets, print the accuracy table, write the report and plot.

    Args:
        files: data sets of DH arms
        workers: processes (``--workers``)
        dynamics: also identify the inertial parameters (``--dynamics``)
        limit: at most this many runs of each data set (``--limit``)
        as_json: print one JSON object (``--json``) instead of the table
        output: a ``.json`` file for the report (``-o``)
        plot: a ``.png``/``.pdf``/``.svg`` file for the CDF of tool-tip errors (``--plot``)

    Returns:
        The report: ``groups`` (the accuracy table) and ``runs`` (one entry per run).

    Raises:
        InputFileError: a file that is not a readable data set.
        ParameterError: a data set of URDF robots.
        OutputFileError: an output that cannot be written.
    """
    from aaria_pin.apps.identify.benchmark import accuracy_table, benchmark_datasets

    runs = benchmark_datasets(files, workers=workers, dynamics=dynamics, limit=limit)
    groups = accuracy_table(runs)
    report = {"groups": groups, "runs": [r.to_json() for r in runs]}
    text = json.dumps(report)
    if output is not None:
        from aaria_pin.files.io import write_text_atomic

        write_text_atomic(output, text + "\n")
    if plot is not None:
        plot_tool_tip_cdf(plot, runs, groups)
    if as_json:
        click.echo(text)
    else:
        print_accuracy_table(groups)
        for run in runs:
            if run.error is not None:
                click.echo(f"{run.dataset} run {run.run}: {run.error}")
    return report
