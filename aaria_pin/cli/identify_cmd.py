"""``aaria identify``: flags into one :class:`~aaria_pin.apps.identify.request.IdentifyRequest`."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from aaria_pin.cli._viz_options import check_output

if TYPE_CHECKING:
    from aaria_pin.apps.identify.request import IdentifyOutcome

_MODES_HELP = """
\b
Examples:
  aaria identify run.h5 -o est.csv --urdf est.urdf   # kinematics of a DH run
  aaria identify ds.h5 --run 3 --json                # one run of a data set
  aaria identify run.h5 --start guess.npy            # fit from a start table first
  aaria identify --dynamics run.h5 --parameters      # inertial base parameters from torques
  aaria identify --dataset clean.h5 noisy.h5 --workers 2 --plot cdf.png
  aaria identify --dynamics run.h5 --consistent --write-urdf fitted.urdf
  aaria identify --rigid imu_a imu_b rec.mcap      # two IMUs on one body, no encoders
"""


def _plot_tool_tip_cdf(path: Path, outcome: IdentifyOutcome) -> None:
    """The CDF of the tool-tip RMS error per group (log scale) to a picture."""
    from aaria_pin.apps.identify.benchmark import WITHIN, tool_tip_cdf
    from aaria_pin.viz._figure import figure_file

    with figure_file(path, 800, 500, layout="constrained") as figure:
        axes = figure.add_subplot()
        for label, errors, share in tool_tip_cdf(outcome.runs, outcome.groups):
            axes.step(errors, share, where="post", label=label)
        for threshold in WITHIN:
            axes.axvline(threshold, color="0.6", linestyle=":", linewidth=1)
        axes.set_xscale("log")
        axes.set_ylim(0.0, 1.0)
        axes.set_xlabel("tool-tip position RMS error over the run [m]")
        axes.set_ylabel("share of arms")
        axes.set_title("aaria identify: kinematic identification against the truth")
        axes.grid(True, which="both", alpha=0.3)
        axes.legend(loc="lower right")


@click.command(epilog=_MODES_HELP)
@click.argument("files", nargs=-1, type=click.Path(path_type=Path))  # a bag folder too
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
@click.option("--run", type=click.IntRange(0), help="One run of a data set.")
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
    help="--dynamics: share of the run, at its end, held out of the fit.  [default: 0.2]",
)
@click.option("--parameters", is_flag=True, help="--dynamics: print every base parameter.")
@click.option("--torques", type=click.Choice(["auto", "measured", "current", "motor", "rigid"]),
    default="auto", help="--dynamics: the torques fitted (auto: what the run has).")  # fmt: skip
@click.option("--torque-constant", type=click.FloatRange(min=0.0, min_open=True),
    help="--torques current: motor torque constant [N*m/A]  [default: the run's]")  # fmt: skip
@click.option("--gear-ratio", type=click.FloatRange(min=0.0, min_open=True),
    help="--torques current: the gearboxes' ratio  [default: the run's]")  # fmt: skip
@click.option("--friction/--no-friction", default=None,
    help="--dynamics: fit friction and armature  [default: if the torques hold them]")  # fmt: skip
@click.option("--consistent", is_flag=True, help="--dynamics: physically consistent bodies.")
@click.option("--write-urdf", "dynamics_urdf", type=click.Path(path_type=Path, dir_okay=False),
    help="--dynamics: the run's URDF, fitted dynamics (.urdf; implies --consistent).")  # fmt: skip
@click.option("--rigid", nargs=2, multiple=True, metavar="IMU_A IMU_B",
    help="IMU_B's pose and time offset relative to IMU_A on one rigid body (repeat).")  # fmt: skip
@click.option("--joint", nargs=2, multiple=True, metavar="IMU_A IMU_B",
    help="The joint (type, axis, point) between IMU_A's body and IMU_B's (repeat).")  # fmt: skip
@click.option(
    "--workers", type=click.IntRange(1, 1024), help="--dataset: processes [cores].  [default: 1]"
)
@click.option("--limit", type=click.IntRange(1), help="--dataset: at most N runs of each data set.")
@click.option(
    "--imu-model",
    help="A recording's IMUs: a preset (adis16485, the default; adis16470,"
    " bmi088, icm42688p, mpu6050) or a TOML file (aaria template imu-model).",
)
@click.option(
    "--plot",
    type=click.Path(path_type=Path, dir_okay=False),
    help="--dataset: the CDF of tool-tip errors per group (.png, .pdf, .svg).",
)
@click.option("--start", type=click.Path(path_type=Path, dir_okay=False), help="A start table"
              " (8 x 5 .npy, CSV, .mat, run file): its fit first, the usual after (a far"
              " table costs time).")  # fmt: skip
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
def identify(files: tuple[Path, ...], plot: Path | None, as_json: bool, **flags: Any) -> None:
    """Identify a robot: DH table and IMU mounts, dynamics, IMU pairs and joints from IMUs.

    FILE is a DH run file, a data set with --run K, or a recording (bag, bag folder, MCAP, CSV,
    aaria import's file; IMUs named imu_base, imu_tool, imu_link<k>_a|b, joints joint<k>). From
    the encoders, the IMU signals and
    each IMU's link: the structure, the DH table and the link IMUs' mounts (the base and tool
    IMUs define the base and tool-tip frames). Printed: the table, what the data cannot
    determine, σ, residuals per IMU, truth errors; a failed fit: one line, exit 1. Stderr: stages.

    With --dynamics: the robot's inertial base parameters (any run, URDF robots too) from
    q, qd, qdd, tau and the base wrench; held-out torque error, total mass, centre of mass.

    With --rigid A B (or --joint A B): FILE is a recording (bag, MCAP, CSV, a recorded or
    simulated run); B's pose and time offset on A's body (or the joint between their bodies)
    from the IMU signals alone, with sigma.

    With --dataset: every run of the data sets FILES identified (--workers processes), then
    the accuracy against the truth by noise, run length and rate: link types right, tool-tip
    RMS error median, 95th percentile and largest, within 1 mm and 1 cm, seconds per arm.
    """
    from aaria_pin.apps.identify.request import IdentifyRequest, identify_files

    request = IdentifyRequest(files, plot=plot, log=not as_json, **flags)  # flags: its fields
    if plot is not None:
        from aaria_pin.viz._formats import PICTURE_SUFFIXES

        check_output(plot, "picture", tuple(PICTURE_SUFFIXES))
    outcome = identify_files(request)
    if plot is not None:
        _plot_tool_tip_cdf(plot, outcome)
    click.echo(json.dumps(outcome.report) if as_json else "\n".join(outcome.lines))
    if outcome.failure is not None:  # a fit above the noise floor, or a degenerate table
        raise SystemExit(1)
