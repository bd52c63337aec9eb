"""``aaria identify --dynamics``: the inertial base parameters of a run's robot from its torques.

The body of the command, called by :mod:`aaria_pin.cli.identify_cmd` for ``--dynamics``.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import click

__all__ = ["dynamics_command", "print_dynamics_report"]


def _format(value: float | None, spec: str = ".3g") -> str:
    return "n/a" if value is None else format(value, spec)


def print_dynamics_report(report: dict[str, Any], show_parameters: bool = False) -> None:
    """Print a :meth:`DynamicIdentification.to_json` report as a few lines of text.

    Args:
        report: the report
        show_parameters: print every base parameter (its combination, estimate, std, model)
    """
    click.echo(
        f"base parameters: {report['n_base']} of {report['n_standard']} standard "
        f"(rank tolerance {report['rank_tolerance']:g}); fitted on "
        f"{report['samples_train']} samples, tested on {report['samples_holdout']}"
    )
    width = max(len(name) for name in report["signals"])
    click.echo(f"{'signal':<{width}} {'held-out rel. RMS':>18} {'held-out RMS':>13}")
    for name in report["signals"]:
        click.echo(
            f"{name:<{width}} {_format(report['holdout_relative_rms'][name]):>18} "
            f"{_format(report['holdout_rms'][name]):>13}"
        )
    mass = report["total_mass"]
    if mass["estimate"] is None:
        click.echo(f"total mass: not determined by the data (model {mass['model']:.6g} kg)")
    else:
        click.echo(
            f"total mass: {mass['estimate']:.6g} kg (model {mass['model']:.6g} kg, "
            f"error {mass['error']:.3g} kg)"
        )
    com = report["centre_of_mass"]
    if com["error"]:
        click.echo(
            f"centre of mass error over the run: RMS {com['error']['rms']:.3g} m, "
            f"max {com['error']['max']:.3g} m"
        )
    else:
        click.echo("centre of mass: not determined by the data")
    if show_parameters:
        for parameter in report["base_parameters"]:
            click.echo(
                f"{parameter['name']}: {parameter['estimate']:.6g} ± "
                f"{_format(parameter['std'])} (model {parameter['model']:.6g}) = "
                f"{parameter['combination']}"
            )


def dynamics_command(
    file: Path,
    run_index: int | None = None,
    *,
    holdout: float = 0.2,
    as_json: bool = False,
    output: Path | None = None,
    show_parameters: bool = False,
) -> dict[str, Any]:
    """Identify the base inertial parameters of a run file's (or a data set run's) robot.

    Prints the report (text, or one JSON object with ``as_json``) and writes it as JSON to
    ``output`` when given (atomically).

    Args:
        file: a run file of any robot, or a data set (with ``run_index``)
        run_index: the run of a data set
        holdout: fraction of the run, at its end, held out of the fit (``--holdout``)
        as_json: print one JSON object (``--json``)
        output: a ``.json`` file to write the report to (``-o``)
        show_parameters: print every base parameter in the text report

    Returns:
        The report (:meth:`~aaria_pin.apps.identify.dynamics.DynamicIdentification.to_json`).

    Raises:
        ParameterError: ``run_index`` given for a run file, or a holdout outside [0, 0.9].
        InputFileError: an unreadable file, or a run whose model cannot be rebuilt.
        OutputFileError: an output that cannot be written.
    """
    from aaria_pin.apps.identify.dynamics import identify_dynamics
    from aaria_pin.files.source import open_record

    record = open_record(file, run_index)
    report = identify_dynamics(record, holdout=holdout).to_json()
    text = json.dumps(report)
    if output is not None:
        from aaria_pin.files.io import write_text_atomic

        write_text_atomic(output, text + "\n")
    if as_json:
        click.echo(text)
    else:
        print_dynamics_report(report, show_parameters)
    return report
