"""``aaria dataset``: many random runs into one HDF5 data set, in parallel.

Flags in; the spec from its sources
(:meth:`~aaria_pin.apps.dataset.spec_sources.DatasetSources.spec`) and the job
(:func:`~aaria_pin.apps.dataset.generate.generate_dataset`); its reports out
(:mod:`~aaria_pin.apps.dataset.progress`).
"""

from __future__ import annotations

import shlex
import sys
from pathlib import Path
from typing import Any

import click

from aaria_pin.cli._options import (
    fourier_options,
    grid_options,
    robot_source_options,
    table_source_options,
)
from aaria_pin.core.seeds import MAX_SEED

_FILE = click.Path(path_type=Path, dir_okay=False)
_JOB_FLAGS = ("workers", "scheduler", "shards", "resume", "overwrite")
"""The flags of the job (:class:`~aaria_pin.apps.dataset.job.DatasetJob`); the rest are the
data set's sources (:class:`~aaria_pin.apps.dataset.spec_sources.DatasetSources`)."""


def _print_config(ctx: click.Context, _: click.Parameter, value: bool) -> None:
    if value and not ctx.resilient_parsing:
        from aaria_pin.aaria.randomize import default_config_toml

        click.echo(default_config_toml(), nl=False)
        ctx.exit(0)


@click.command(
    epilog="""\b
Examples:
  aaria dataset -n 1000 --seed 7 -o random.h5            # random arms, joints and bases
  aaria dataset -n 200 --preset aaria-fig2 -o fig2.h5    # one arm, random motions
  aaria dataset -n 200 --robot ur5 --duration 5 -o ur5.h5
  aaria dataset -n 1000 --motion fourier --duration 30 --rate 200 -o ident.h5  # excitation
  aaria dataset -n 1000 --config ranges.toml -o ds.h5    # ranges, hardware: aaria template config
  aaria dataset -n 100 --robot ur5 --drive pd --config ranges.toml -o pd.h5  # [controller] gains
  aaria dataset -n 1000 --seed 7 -o random.h5 --resume   # go on after Ctrl-C or a crash
  aaria dataset -n 100000 --scheduler tcp://head:8786 -o big.h5"""
)
@click.option("-n", "n_runs", type=int, required=True, help="Number of runs N.")
@click.option("-o", "--output", type=_FILE, required=True, help="Data set file (.h5).")
@click.option("--seed", type=click.IntRange(0, MAX_SEED), default=0, show_default=True,
              help="Seed of the whole data set: run k is the same for a given seed and k, whatever"
              " the workers.")  # fmt: skip
@click.option("--workers", type=click.IntRange(1, 1024), help="Local worker processes [cores].")
@click.option("--scheduler",
              help="Address of a Dask distributed scheduler (tcp://host:8786), instead of local"
              " workers.")  # fmt: skip
@click.option("--shards", type=click.Path(path_type=Path, file_okay=False),
              help="With --scheduler: folder of the workers' shard files [the output's"
              " folder].")  # fmt: skip
@grid_options(10.0, 100.0)
@click.option("--noise/--no-noise", default=True, show_default=True, help="IMU noise.")
@click.option("--imu-model", help="IMU model: a preset (adis16485, the default; adis16470,"
              " bmi088, icm42688p, mpu6050) or a TOML file; the config's [imu] values go over"
              " it.")  # fmt: skip
@click.option("--dtype", type=click.Choice(["float32", "float64"]), default="float32",
              show_default=True, help="Number type of the stored series (time, joints, IMU"
              " signals, torques, poses); the input tables stay float64.")  # fmt: skip
@click.option("--config", "config_file", type=_FILE,
              help="TOML file of ranges and of the hardware: [imu], [encoder], [torque_sensor],"
              " [current_sensor], [actuator], any number a range [low, high] drawn per run"
              " (aaria template config, aaria template hardware).")  # fmt: skip
@click.option("--vary",
              help="What is random, comma separated (default: structure,joints,base less the parts"
              " given by --preset/--dh, --joints, --base).")  # fmt: skip
@table_source_options
@robot_source_options
@click.option("--joints", "joints_file", type=_FILE, help="Fixed joint oscillation table.")
@click.option("--base", "base_file", type=_FILE, help="Fixed base oscillation table.")
@click.option("--motion", type=click.Choice(["sine", "fourier"]), default="sine",
              show_default=True, help="Joint motion of each run: the joint table's sines, or a"
              " Fourier excitation drawn from the run's joint stream (per joint a finite Fourier"
              " series within its limits; stored as the table fourier_coefficients).")  # fmt: skip
@fourier_options
@click.option("--drive", type=click.Choice(["motion", "pd", "computed-torque"]), default="motion",
              show_default=True, help="Follow each run's motion, or track it with a joint"
              " controller (gains: the config's [controller], ranges drawn per run).")  # fmt: skip
@click.option("--resume", is_flag=True,
              help="Continue an interrupted data set file (the same settings); its complete runs"
              " are verified and a damaged one made again.")  # fmt: skip
@click.option("--overwrite", is_flag=True, help="Replace an existing file (once the new one is).")
@click.option("--quiet", is_flag=True, help="No estimate, no progress bar or lines.")
@click.option("--progress-every", type=click.FloatRange(0),
    help="Seconds between progress lines when stderr is not a terminal (default 10).")  # fmt: skip
@click.option("--print-config", is_flag=True, expose_value=False, is_eager=True,
    callback=_print_config, help="Print the default configuration and exit.")  # fmt: skip
def dataset(output: Path, quiet: bool, progress_every: float | None, **flags: Any) -> None:
    """Simulate N random runs (MODE 1) or N runs of one arm (MODE 2) into a data set.

    With --robot NAME or --urdf FILE the arm is that URDF robot: its joint and base motions
    vary, its structure does not.
    """
    import warnings

    from aaria_pin.apps.dataset.generate import DatasetJob, DatasetJobStoppedError, generate_dataset
    from aaria_pin.apps.dataset.outcome import job_outcome
    from aaria_pin.apps.dataset.progress import estimate_report, progress_report
    from aaria_pin.apps.dataset.spec_sources import DatasetSources
    from aaria_pin.errors import MeshWarning

    job = DatasetJob(  # its ParameterError names the flag through the aaria group
        **{name: flags.pop(name) for name in _JOB_FLAGS},
        progress=progress_report(quiet, progress_every),
        estimate=estimate_report(quiet),
        command=shlex.join(["aaria", *sys.argv[1:]]),
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", MeshWarning)
        spec = DatasetSources(**flags).spec()
    for warning in caught:  # missing meshes told once, as a line; others as they came
        if issubclass(warning.category, MeshWarning):
            click.echo(f"aaria: warning: {warning.message}", err=True)
        else:
            warnings.warn_explicit(
                warning.message, warning.category, warning.filename, warning.lineno
            )
    try:
        report = generate_dataset(output, spec, job)
    except DatasetJobStoppedError as exc:
        click.echo(f"\naaria: {exc}" if sys.stderr.isatty() else f"aaria: {exc}", err=True)
        raise SystemExit(exc.exit_status) from None
    text, failures = job_outcome(report, spec.n_runs, job.resume)
    click.echo(text)
    if failures:
        click.echo("\n".join(failures), err=True)
        raise SystemExit(1)
