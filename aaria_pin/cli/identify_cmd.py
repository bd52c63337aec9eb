"""``aaria identify``: the kinematic model of an Aaria arm from its IMU signals and encoders."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from aaria_pin.cli._viz_options import check_output, check_run_option

if TYPE_CHECKING:
    from aaria_pin.apps.identify.kinematics import KinematicIdentification

_TABLE_HEADER = (
    "estimated Aaria DH table (aaria identify): alpha [rad], a [m], theta [rad], d [m], "
    "link type; rows 1-6 modules, 7 tool, 8 base"
)


def _print(result: KinematicIdentification) -> None:
    names = {0: "empty", 1: "revolute", 2: "prismatic"}
    click.echo(
        "structure: " + ", ".join(f"{m + 1} {names[t]}" for m, t in enumerate(result.link_types))
    )
    click.echo("table [alpha a theta d type]:")
    for row in result.table:
        click.echo("  " + " ".join(f"{v:9.5f}" for v in row[:4]) + f" {int(row[4])}")
    for deficiency in result.deficiencies:
        click.echo(f"not determined: {deficiency.description}")
    worst = max(result.residual_rms.items(), key=lambda item: item[1]["accel_m_s2"])
    click.echo(
        f"residual RMS: largest accelerometer {worst[1]['accel_m_s2']:.3g} m/s^2 ({worst[0]}), "
        f"fit {result.fit['seconds']:.1f} s on {result.fit['samples']} samples"
    )
    truth = result.truth
    if truth is not None:
        click.echo(
            f"against the truth: link types {sum(truth.link_types_right)}/6 right, tool tip "
            f"RMS {truth.tool_tip_rms:.3g} m, max {truth.tool_tip_max:.3g} m, joint axes within "
            f"{max(truth.axis_angle_max.values(), default=0.0):.3g} rad"
        )


def _write_outputs(result: KinematicIdentification, table: Path | None, urdf: Path | None) -> None:
    from aaria_pin.files.io import atomic_output, write_text_atomic

    if table is not None:
        import numpy as np

        with atomic_output(table) as temporary:
            np.savetxt(temporary, result.table, delimiter=",", fmt="%.17g", header=_TABLE_HEADER)
    if urdf is not None:
        from aaria_pin.aaria.dh_robot import build_dh_robot

        poses = [mount.T_parent_imu for mount in result.mounts]
        robot = build_dh_robot(result.table, imu_mount=poses, name="aaria_identified")
        write_text_atomic(urdf, robot.urdf)


def identify_kinematics_command(
    file: Path, run_index: int | None, table: Path | None, urdf: Path | None, as_json: bool
) -> dict[str, Any] | None:
    """Identify the run, write the outputs, print the result (or return it for ``--json``)."""
    from aaria_pin.apps.identify.kinematics import identify_kinematics
    from aaria_pin.files.source import open_record

    record = open_record(file, run_index)
    result = identify_kinematics(record)
    _write_outputs(result, table, urdf)
    if as_json:
        return result.to_json()
    _print(result)
    return None


_MODES_HELP = """
\b
Examples:
  aaria identify run.h5 -o est.csv --urdf est.urdf   # kinematics of a DH run
  aaria identify ds.h5 --run 3 --json                # one run of a data set
  aaria identify --dynamics run.h5 --parameters      # inertial base parameters from torques
  aaria identify --dataset clean.h5 noisy.h5 --workers 2 --plot cdf.png
"""


def _check_modes(
    files: tuple[Path, ...],
    dynamics: bool,
    dataset: bool,
    run_index: int | None,
    urdf: Path | None,
    plot: Path | None,
) -> None:
    """Refuse options of another mode (one line, exit 2)."""
    if not files:
        raise click.UsageError("no FILE given; allowed: a run file, or data sets with --dataset")
    if not dataset:
        if len(files) > 1:
            raise click.UsageError(
                f"{len(files)} files given; allowed: one run file, or data sets with --dataset"
            )
        if plot is not None:
            raise click.UsageError("--plot is for --dataset")
    elif run_index is not None:
        raise click.UsageError("--run is for one run; --dataset identifies every run")
    if urdf is not None and (dynamics or dataset):
        raise click.UsageError("--urdf is for the kinematic identification of one run")


@click.command(epilog=_MODES_HELP)
@click.argument("files", nargs=-1, type=click.Path(path_type=Path, dir_okay=False))
@click.option(
    "--dynamics",
    is_flag=True,
    help="Identify the inertial base parameters from the torques (with --dataset: as well).",
)
@click.option(
    "--dataset",
    is_flag=True,
    help="Benchmark: identify every run of the data sets FILES, accuracy by noise and length.",
)
@click.option("--run", "run_index", type=click.IntRange(0), help="One run of a data set.")
@click.option(
    "-o",
    "--output",
    type=click.Path(path_type=Path, dir_okay=False),
    help="The estimated 8 x 5 DH table (.csv); with --dynamics or --dataset the report (.json).",
)
@click.option(
    "--urdf",
    type=click.Path(path_type=Path, dir_okay=False),
    help="Write the estimated arm, IMUs at their estimated mounts (.urdf).",
)
@click.option(
    "--holdout",
    type=click.FloatRange(0.0, 0.9),
    default=0.2,
    show_default=True,
    help="--dynamics: share of the run, at its end, held out of the fit.",
)
@click.option("--parameters", is_flag=True, help="--dynamics: print every base parameter.")
@click.option(
    "--workers",
    type=click.IntRange(1, 1024),
    default=1,
    show_default=True,
    help="--dataset: processes [cores].",
)
@click.option("--limit", type=click.IntRange(1), help="--dataset: at most N runs of each data set.")
@click.option(
    "--plot",
    type=click.Path(path_type=Path, dir_okay=False),
    help="--dataset: the CDF of tool-tip errors per group (.png, .pdf, .svg).",
)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
def identify(
    files: tuple[Path, ...],
    dynamics: bool,
    dataset: bool,
    run_index: int | None,
    output: Path | None,
    urdf: Path | None,
    holdout: float,
    parameters: bool,
    workers: int,
    limit: int | None,
    plot: Path | None,
    as_json: bool,
) -> None:
    """Identify an Aaria arm's kinematic model from a DH run's IMU signals and encoders.

    FILE is a DH run file, or a data set with --run K. Only the encoders, the IMU signals and
    which link each IMU is on are used: the structure (each module empty, revolute or
    prismatic), the extended DH table and the link IMUs' mounts are estimated (the base and
    tool IMUs define the base and tool-tip frames). Printed: the table, the parameter
    combinations the data cannot determine, residuals, and the errors against the truth the
    file holds.

    With --dynamics: the robot's inertial base parameters (any run, URDF robots too) from
    q, qd, qdd, tau and the base wrench; held-out torque error, total mass, centre of mass.

    With --dataset: every run of the data sets FILES identified (--workers processes), then
    the accuracy against the truth by noise, run length and rate: link types right, tool-tip
    RMS error median, 95th percentile and largest, share within 1 mm and 1 cm, seconds per arm.
    """
    _check_modes(files, dynamics, dataset, run_index, urdf, plot)
    if dataset:
        from aaria_pin.cli._identify_dataset import dataset_command

        if output is not None:
            check_output(output, "JSON report", (".json",))
        if plot is not None:
            from aaria_pin.viz._formats import PICTURE_SUFFIXES

            check_output(plot, "picture", tuple(PICTURE_SUFFIXES))
        dataset_command(
            files,
            workers=workers,
            dynamics=dynamics,
            limit=limit,
            as_json=as_json,
            output=output,
            plot=plot,
        )
        return
    (file,) = files
    check_run_option(file, run_index)
    if dynamics:
        from aaria_pin.cli._identify_dynamics import dynamics_command

        if output is not None:
            check_output(output, "JSON report", (".json",))
        dynamics_command(
            file,
            run_index,
            holdout=holdout,
            as_json=as_json,
            output=output,
            show_parameters=parameters,
        )
        return
    if output is not None:
        check_output(output, "CSV table", (".csv",))
    if urdf is not None:
        check_output(urdf, "URDF", (".urdf",))
    report = identify_kinematics_command(file, run_index, output, urdf, as_json)
    if report is not None:
        click.echo(json.dumps(report))
