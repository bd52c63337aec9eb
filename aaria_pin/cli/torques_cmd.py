"""``aaria torques``: torque-level analysis of any run file or data set, whatever the robot."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import click

from aaria_pin.cli._viz_options import PICTURE_SUFFIXES, check_run_option, output_option


def _print_run(report: dict[str, Any]) -> None:
    width = max([5, *(len(joint["joint"]) for joint in report["joints"])])
    click.echo(
        f"{'module':<7} {'joint':<{width}} {'type':<10} {'peak |tau|':>12} {'rms':>10} "
        f"{'rms gravity':>11} {'rms coriolis':>12} {'rms inertial':>12} {'energy net':>11}"
        f" {'energy abs':>11}"
    )
    for joint in report["joints"]:
        terms = joint["rms_terms"]
        click.echo(
            f"{joint['module']:<7} {joint['joint']:<{width}} {joint['type']:<10}"
            f" {joint['peak_abs']:>8.4g} {joint['unit']:<3}"
            f" {joint['rms']:>10.4g} {terms['gravity']:>11.4g} {terms['coriolis']:>12.4g}"
            f" {terms['inertial']:>12.4g} {joint['energy_net_J']:>9.4g} J"
            f" {joint['energy_abs_J']:>9.4g} J"
        )
    peaks = report["base_wrench_peak"]
    click.echo(
        "base wrench peaks: "
        + ", ".join(f"{k} {v:.4g} {'N' if k.startswith('f') else 'N*m'}" for k, v in peaks.items())
    )


def _unit(kind: str) -> str:
    """The unit of a joint's torque: a force [N] for a prismatic joint, else a torque [N*m]."""
    return "N" if kind == "prismatic" else "N*m"


def _print_dataset(report: dict[str, Any]) -> None:
    names = report.get("joints", {})
    for module, kinds in report["by_module"].items():
        label = f"module {module}" + (f" ({names[module]})" if module in names else "")
        for kind, stats in kinds.items():
            unit = _unit(kind)
            click.echo(
                f"{label} {kind:<10} runs {stats['runs']:>6}  peak |tau| "
                f"median {stats['median']:.4g} {unit}  p95 {stats['p95']:.4g} {unit}  "
                f"max {stats['max']:.4g} {unit}"
            )
    click.echo(
        "largest peaks: "
        + "; ".join(
            f"run {x['run']} module {x['module']} ({x['type']}) {x['peak_abs']:.4g} "
            f"{_unit(x['type'])}"
            for x in report["largest"]
        )
    )


@click.command(
    epilog="""\b
Examples:
  aaria torques run.h5                   # per joint: peak, RMS, its terms, energy
  aaria torques run.h5 --plot rms.png    # and the RMS of each term, side by side
  aaria torques ds.h5                    # a data set: peaks by module and joint type
  aaria torques ds.h5 --run 7 --json"""
)
@click.argument("file", type=click.Path(path_type=Path, dir_okay=False))
@click.option("--run", "run_index", type=click.IntRange(0), help="One run of a data set.")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
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
    from aaria_pin.apps.torques import run_torque_report

    check_run_option(file, run_index)
    report, one_run = run_torque_report(file, run_index)
    if not one_run:
        if as_json:
            click.echo(json.dumps(report))
        else:
            _print_dataset(report)
        return
    if plot:
        from aaria_pin.viz.report_plots import plot_torque_report

        plot_torque_report(report, plot, f"joint torques of {file.name}")
    if as_json:
        click.echo(json.dumps(report))
    else:
        _print_run(report)
