"""``aaria dataset``: many random runs into one HDF5 data set, in parallel."""

from __future__ import annotations

import shlex
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from aaria_pin.cli._options import fourier_options, robot_source_options, table_source_options
from aaria_pin.core.seeds import MAX_SEED

if TYPE_CHECKING:
    from aaria_pin.apps.dataset.engine import DatasetEstimate
    from aaria_pin.apps.dataset.urdf import UrdfSource

_FILE = click.Path(path_type=Path, dir_okay=False)


def _progress(quiet: bool, every: float) -> Callable[[int, int, float], None] | None:
    """The progress report: a bar on a terminal, else a plain line every ``every`` seconds.

    A batch job's log (stderr not a terminal) gets lines ``aaria: 120/10000 runs, 35.2 runs/s,
    ETA 281 s`` at most every ``every`` seconds, and the last one when the job ends.
    """
    if quiet:
        return None
    terminal = sys.stderr.isatty()
    last = [-float("inf")]

    def show(done: int, total: int, seconds: float) -> None:
        rate = done / seconds if seconds > 0 else 0.0
        eta = (total - done) / rate if rate > 0 else float("nan")
        if terminal:
            width = 30
            filled = int(width * done / max(total, 1))
            click.echo(
                f"\r[{'#' * filled}{'.' * (width - filled)}] {done}/{total} runs, "
                f"{rate:.1f} runs/s, ETA {eta:.0f} s ",
                err=True,
                nl=done == total,
            )
        elif seconds - last[0] >= every or done == total:
            last[0] = seconds
            click.echo(f"aaria: {done}/{total} runs, {rate:.1f} runs/s, ETA {eta:.0f} s", err=True)

    return show


def _estimate(quiet: bool) -> Callable[[DatasetEstimate], None] | None:
    """Print a job's estimated size and time once (to stderr)."""
    if quiet:
        return None

    def show(estimate: DatasetEstimate) -> None:
        seconds = "under 1 s" if estimate.seconds < 1 else f"about {estimate.seconds:.0f} s"
        click.echo(
            f"aaria: estimate for {estimate.runs} runs: {_size(estimate.bytes)}, {seconds} "
            f"(the runs, not start-up) on {estimate.workers} workers "
            f"({estimate.run_seconds * 1e3:.0f} ms a run)",
            err=True,
        )

    return show


def _size(count: float) -> str:
    for unit in ("B", "kB", "MB", "GB"):
        if count < 1000:
            return f"{count:.0f} {unit}" if unit == "B" else f"{count:.1f} {unit}"
        count /= 1000
    return f"{count:.1f} TB"


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
  aaria dataset -n 1000 --config ranges.toml -o ds.h5    # ranges, noise: aaria template config
  aaria dataset -n 1000 --seed 7 -o random.h5 --resume   # go on after Ctrl-C or a crash
  aaria dataset -n 100000 --scheduler tcp://head:8786 -o big.h5"""
)
@click.option("-n", "n_runs", type=int, required=True, help="Number of runs N.")
@click.option("-o", "--output", type=_FILE, required=True, help="Data set file (.h5).")
@click.option(
    "--seed",
    type=click.IntRange(0, MAX_SEED),
    default=0,
    show_default=True,
    help="Seed of the whole data set: run k is the same for a given seed and k, whatever the"
    " workers.",
)
@click.option("--workers", type=click.IntRange(1, 1024), help="Local worker processes [cores].")
@click.option(
    "--scheduler",
    help="Address of a Dask distributed scheduler (tcp://host:8786), instead of local workers.",
)
@click.option(
    "--shards",
    type=click.Path(path_type=Path, file_okay=False),
    help="With --scheduler: folder of the workers' shard files [the output's folder].",
)
@click.option("--duration", type=float, default=10.0, show_default=True, help="Run length [s].")
@click.option("--rate", type=float, default=100.0, show_default=True, help="Sample rate [Hz].")
@click.option("--noise/--no-noise", default=True, show_default=True, help="IMU noise.")
@click.option(
    "--dtype",
    type=click.Choice(["float32", "float64"]),
    default="float32",
    show_default=True,
    help="Number type of the stored series (time, joints, IMU signals, torques, poses); the"
    " input tables stay float64.",
)
@click.option(
    "--config",
    "config_file",
    type=_FILE,
    help="TOML file of ranges and of the IMU noise ([noise]; see aaria template config).",
)
@click.option(
    "--vary",
    help="What is random, comma separated (default: structure,joints,base less the parts given"
    " by --preset/--dh, --joints, --base).",
)
@table_source_options
@robot_source_options
@click.option("--joints", "joints_file", type=_FILE, help="Fixed joint oscillation table.")
@click.option("--base", "base_file", type=_FILE, help="Fixed base oscillation table.")
@click.option(
    "--motion",
    type=click.Choice(["sine", "fourier"]),
    default="sine",
    show_default=True,
    help="Joint motion of each run: the joint table's sines, or a Fourier excitation drawn from"
    " the run's joint stream (per joint a finite Fourier series within its limits; stored as"
    " the table fourier_coefficients).",
)
@fourier_options
@click.option(
    "--resume",
    is_flag=True,
    help="Continue an interrupted data set file (the same settings); a complete one is left"
    " as it is.",
)
@click.option("--overwrite", is_flag=True, help="Replace an existing file.")
@click.option("--quiet", is_flag=True, help="No estimate, no progress bar or lines.")
@click.option(
    "--progress-every",
    type=click.FloatRange(0),
    default=10.0,
    show_default=True,
    help="Seconds between progress lines when stderr is not a terminal.",
)
@click.option(
    "--print-config",
    is_flag=True,
    expose_value=False,
    is_eager=True,
    callback=_print_config,
    help="Print the default configuration and exit.",
)
def dataset(
    n_runs: int,
    output: Path,
    seed: int,
    workers: int | None,
    scheduler: str | None,
    shards: Path | None,
    duration: float,
    rate: float,
    noise: bool,
    dtype: str,
    config_file: Path | None,
    vary: str | None,
    preset: str | None,
    dh_file: Path | None,
    convention: str,
    robot: str | None,
    urdf_file: Path | None,
    tool_frame: str | None,
    imu_layout_file: Path | None,
    fixed_base: bool,
    joints_file: Path | None,
    base_file: Path | None,
    motion: str,
    harmonics: int | None,
    base_frequency: float | None,
    resume: bool,
    overwrite: bool,
    quiet: bool,
    progress_every: float,
) -> None:
    """Simulate N random runs (MODE 1) or N runs of one arm (MODE 2) into a data set.

    With --robot NAME or --urdf FILE the arm is that URDF robot: its joint and base motions
    vary, its structure does not.
    """
    from aaria_pin.aaria.presets import get_preset
    from aaria_pin.apps.dataset.config import load_dataset_config
    from aaria_pin.apps.dataset.engine import (
        DatasetJobStoppedError,
        DatasetSpec,
        DhDatasetSpec,
        UrdfDatasetSpec,
        generate_dataset,
    )
    from aaria_pin.errors import ParameterError
    from aaria_pin.files.io import read_table

    if workers is not None and scheduler is not None:
        raise click.UsageError("give --workers or --scheduler, not both")
    if shards is not None and scheduler is None:
        raise click.UsageError("--shards needs --scheduler")
    if convention != "aaria":
        raise ParameterError(
            parameter="convention",
            value=convention,
            allowed="aaria (a data set's arms are Aaria tables; a standard or modified table"
            " can be simulated with aaria simulate, or its robot made with aaria urdf)",
        )
    source = _urdf_source(robot, urdf_file, tool_frame, imu_layout_file, fixed_base)
    if source is not None and (preset is not None or dh_file is not None):
        raise click.UsageError("give a DH arm (--preset/--dh) or a URDF robot, not both")
    fixed = {
        "structure": preset is not None or dh_file is not None or source is not None,
        "joints": joints_file is not None,
        "base": base_file is not None,
    }
    if source is not None and not source.moving_base:
        if base_file is not None:
            raise click.UsageError("--base moves the base; not allowed with --fixed-base")
        fixed["base"] = True
    if vary is None:
        parts = tuple(part for part, given in fixed.items() if not given)
    else:
        parts = tuple(part.strip() for part in vary.split(",") if part.strip())
        clash = [part for part in parts if fixed.get(part)]
        if "base" in clash and fixed_base:
            raise ParameterError("--fixed-base: the base cannot vary; allowed: --vary joints")
        if clash:
            raise ParameterError(
                f"--vary {clash[0]} and a fixed {clash[0]} table were both given; allowed: one"
            )
    if source is None and "structure" not in parts and not fixed["structure"]:
        raise click.UsageError("a structure that does not vary needs --preset or --dh")
    dh_table = joint_table = base_table = None
    name = ""
    if preset is not None or dh_file is not None:
        if preset is not None and dh_file is not None:
            raise click.UsageError("give at most one of --preset NAME or --dh FILE")
        if preset is not None:
            chosen = get_preset(preset)
            if chosen.convention != "aaria":
                raise ParameterError(f"preset {preset!r} is not an Aaria table; allowed: aaria-*")
            dh_table, joint_table, base_table = chosen.table, chosen.joint_table, chosen.base_table
            if motion == "fourier":
                joint_table = None  # the excitation replaces the preset's sines
            name = preset
        else:
            assert dh_file is not None
            dh_table = read_table(dh_file, "senSenDH")
    if joints_file is not None:
        joint_table = read_table(joints_file, "senSenJ" if source is None else "joint_table")
    if base_file is not None:
        base_table = read_table(base_file, "senSenB")
    if config_file is not None:
        from aaria_pin.files.paths import existing_input

        existing_input(config_file, None, "config")  # a FIFO: one line, never a wait
    config, noise_model = load_dataset_config(config_file)
    settings: dict[str, Any] = {
        "n_runs": n_runs,
        "seed": seed,
        "duration": duration,
        "rate": rate,
        "noise": noise,
        "dtype": dtype,
        "config": config,
        "noise_model": noise_model,
        "vary": parts,
        "joint_table": joint_table,
        "base_table": base_table,
        "motion": motion,
        "harmonics": harmonics,
        "base_frequency": base_frequency,
    }
    spec: DatasetSpec = (
        DhDatasetSpec(**settings, dh_table=dh_table, name=name)
        if source is None
        else UrdfDatasetSpec(**settings, robot=source)
    )
    try:
        report = generate_dataset(
            output,
            spec,
            workers=workers,
            scheduler=scheduler,
            shards=shards,
            resume=resume,
            overwrite=overwrite,
            progress=_progress(quiet, progress_every),
            estimate=_estimate(quiet),
            command=shlex.join(["aaria", *sys.argv[1:]]),
        )
    except DatasetJobStoppedError as exc:
        click.echo(f"\naaria: {exc}" if sys.stderr.isatty() else f"aaria: {exc}", err=True)
        raise SystemExit(exc.exit_status) from None
    if resume and report.written == 0 and report.complete == n_runs and not report.failures:
        click.echo(f"{report.path}: already complete ({n_runs}/{n_runs} runs); nothing to do")
        return
    in_shards = f", {report.shards} shards" if report.shards else ""
    click.echo(
        f"wrote {report.path}: {report.complete}/{n_runs} runs complete "
        f"({report.written} in this job{in_shards}, {report.seconds:.1f} s)"
    )
    if report.failures:
        for run, message in sorted(report.failures.items()):
            click.echo(f"run {run} failed: {message}", err=True)
        click.echo(f"failed runs: {sorted(report.failures)}", err=True)
        raise SystemExit(1)


def _urdf_source(
    robot: str | None,
    urdf_file: Path | None,
    tool_frame: str | None,
    imu_layout_file: Path | None,
    fixed_base: bool,
) -> UrdfSource | None:
    """The URDF robot of ``--robot``/``--urdf`` (None for DH arms), its missing meshes told."""
    if robot is None and urdf_file is None:
        if tool_frame is not None or imu_layout_file is not None or fixed_base:
            raise click.UsageError("--tool, --imu-layout and --fixed-base need --robot or --urdf")
        return None
    from aaria_pin.apps.dataset.urdf import UrdfSource
    from aaria_pin.cli._options import load_robot_source
    from aaria_pin.core.imu_layout import read_imu_layout
    from aaria_pin.core.urdf_robot import missing_meshes_message

    text, folder, name = load_robot_source(robot, urdf_file)
    from aaria_pin.files.paths import existing_input

    layout = (
        None
        if imu_layout_file is None
        else read_imu_layout(existing_input(imu_layout_file, None, "IMU layout"))
    )
    source = UrdfSource(text, name, str(folder), not fixed_base, tool_frame, layout)
    summary = source.load().summary  # checks the robot here, once, before any worker starts
    if summary.missing_meshes:
        click.echo(f"aaria: warning: {missing_meshes_message(summary)}", err=True)
    return source
