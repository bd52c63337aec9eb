"""``aaria simulate``: one run of a DH arm or a URDF robot to an HDF5 or .mat run file."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from aaria_pin.cli._options import (
    drive_overrides,
    fourier_options,
    given,
    grid_options,
    hardware_options,
    integration_options,
    load_table_source,
    robot_source_options,
    sampling_overrides,
    shown,
    table_source_options,
)
from aaria_pin.core.seeds import MAX_SEED

_FILE = click.Path(path_type=Path, dir_okay=False)
_DRIVES = click.Choice(["motion", "torque", "pd", "computed-torque"])


@click.command(
    epilog="""\b
Examples:
  aaria simulate --preset aaria-fig2 -o fig2.h5             # the joint table's sines
  aaria simulate --preset aaria-fig2 --motion fourier --duration 30 --rate 200 -o f.h5
  aaria simulate --robot ur5 --motion fourier --harmonics 3 --base-frequency 0.2 -o ur5.h5
  aaria simulate --robot ur5 --trajectory motion.csv -o mine.h5   # time,<joint>,... columns
  aaria simulate --from f.h5 --seed 3 -o again.h5           # the same motion, other noise
  aaria simulate --from ds.h5 --run 4 -o run4.h5           # run 4 of a data set, re-made
  aaria simulate --robot ur5 --imu-model bmi088 --hardware hw.toml -o real.h5
  aaria simulate --dh table.csv --drive torque --torques tau.npy -o fwd.mat
  aaria simulate --robot ur5 --drive computed-torque --hardware hw.toml -o ct.h5"""
)
@table_source_options
@robot_source_options
@click.option("--joints", "joints_file", type=_FILE, help="Joint oscillation table (senSenJ).")
@click.option("--base", "base_file", type=_FILE, help="Base oscillation table (senSenB).")
@click.option("--imu-mount", "mount_file", type=_FILE,
              help="IMU mounting poses: .npy (14 × 4 × 4) or a run file.")  # fmt: skip
@click.option("--from", "from_run", type=_FILE,
              help="Re-make the run stored in this run file (any kind); the options given beside"
              " it replace the stored ones.")  # fmt: skip
@click.option("--run", "run_index", type=click.IntRange(0), help="With --from a data set: its run.")
@grid_options()
@click.option("--seed", type=click.IntRange(0, MAX_SEED), help="Seed of the IMU noise (default 0).")
@click.option("--density", type=float, help="Density of every body [kg/m^3] (default 2700).")
@shown("--drive", default="motion", type=_DRIVES,
       help="Follow the motion; move under --torques by forward dynamics; or track the motion"
       " with a joint controller (PD, or computed torque: inverse dynamics + PD; gains from"
       " --hardware [controller]).")  # fmt: skip
@click.option("--torques", "torques_file", type=_FILE,
              help="Joint torques for --drive torque: a run file (its tau), or a T x n table (CSV,"
              " .npy, .mat 'tau'); a DH arm's by module (T x 6).")  # fmt: skip
@integration_options
@click.option(
    "--motion",
    type=click.Choice(["sine", "fourier"]),
    help="Joint motion: sine (the joint table; the default) or fourier (per joint a random "
    "finite Fourier series within its position, speed and acceleration limits, the "
    "excitation used for identification). With --from: as stored unless given.",
)
@fourier_options
@click.option(
    "--trajectory",
    type=_FILE,
    help="Joint motion from a file: time and one column per joint (CSV with a header "
    "time,<joint>,..., .npy T x (1+n), or HDF5 time/q such as a run file); columns matched by "
    "joint name when named; derivatives by a quintic spline unless given (qd_<joint>, "
    "qdd_<joint>). Its span and rate are the run's unless --duration/--rate are given.",
)
@click.option(
    "--smoothing",
    type=click.FloatRange(min=0),
    help="For --trajectory: RMS [rad or m] of the noise the spline may smooth away (default 0: "
    "through every sample).",
)
@click.option("--noise/--no-noise", default=None, help="IMU noise on (default) or off.")
@hardware_options
@shown("--compress", default="none", type=click.Choice(["none", "gzip", "lzf"]),
       help="HDF5 filter of the time series (gzip: smaller, MATLAB-readable, slower).")  # fmt: skip
@click.option("-o", "--output", type=_FILE, required=True, help="Run file: .h5 or .mat.")
def simulate(output: Path, compress: str, **flags: Any) -> None:
    """Simulate an arm on a moving base: joint values, IMUs, torques, base wrench.

    The arm is a DH arm (--preset, --dh; 14 IMU slots, the senSen layout) or any URDF robot
    (--robot, --urdf; two IMUs per moving link plus base and tool), or the run stored in a run
    file (--from, any kind). Every run is written in the one run layout (.h5 or .mat).

    The joints follow the joint table's sines, a Fourier excitation (--motion fourier: per
    joint a random finite Fourier series within its position, speed and acceleration limits)
    or a given trajectory (--trajectory FILE).
    """
    from aaria_pin.aaria.run_motion import MotionChoice
    from aaria_pin.aaria.run_source import dh_file_overrides, dh_run_request
    from aaria_pin.apps.run_summary import run_summary as summary
    from aaria_pin.core._malloc import tune_malloc
    from aaria_pin.core.conflicts import OptionConflictError
    from aaria_pin.files.runfile import write_run_pieces

    tune_malloc()
    params = click.get_current_context().params
    from_run, preset, dh_file = flags["from_run"], flags["preset"], flags["dh_file"]
    stored, kind = None, None
    if from_run is not None:
        from aaria_pin.apps.remake import run_kind
        from aaria_pin.files.runfile import read_run_inputs
        from aaria_pin.files.source import open_record

        run = flags["run_index"]  # a data set's run, or a run file's inputs (not its series)
        stored = read_run_inputs(from_run) if run is None else open_record(from_run, run)
        kind = run_kind(stored)
    elif flags["run_index"] is not None:
        raise click.UsageError("--run K goes with --from DATA_SET")
    if flags["robot"] is not None or flags["urdf_file"] is not None:
        kind = "urdf"
    if kind == "urdf":
        from aaria_pin.cli._simulate_urdf import simulate_urdf_command

        return simulate_urdf_command(params, stored)
    if kind not in (None, "dh"):
        return _remake_as_stored(params, stored, str(kind))
    for key, flag in (("tool_frame", "--tool"), ("imu_layout_file", "--imu-layout"),
                      ("fixed_base", "--fixed-base")):  # fmt: skip
        if flags[key] not in (None, False):
            raise click.UsageError(f"{flag} is for URDF robots (--robot or --urdf)")
    overrides = sampling_overrides(params, stored)
    overrides.update(dh_file_overrides(flags))
    overrides.update(drive_overrides(params))
    for key in ("preset", "dh_file"):  # the run file has its table
        if stored is not None and given(key):
            raise OptionConflictError(parameter=key, other="from_run", given_with=True)
    choice = MotionChoice.from_options(params)
    remade = None if stored is None else (stored, str(from_run))
    source = None if remade else load_table_source(preset, dh_file, flags["convention"])
    chunks = dh_run_request(choice, overrides, source, preset, remade).pieces()
    compression = None if compress == "none" else compress
    record, samples, peak = write_run_pieces(output, chunks, compression)
    click.echo(summary(output, record, samples, peak, robot=False))


def _remake_as_stored(params: dict[str, Any], stored: Any, kind: str) -> None:
    """``aaria simulate --from`` a wrist or pick-and-place run: re-make it as it was.

    Raises:
        click.UsageError: any option beside ``--from``, ``-o`` and ``--compress`` (they are DH
            or URDF options).
    """
    from aaria_pin.apps.remake import remake_file_record
    from aaria_pin.files.runfile import write_run

    for option in simulate.params:
        kept = option.name in ("from_run", "run_index", "output", "compress", None)
        if not kept and given(option.name):
            raise click.UsageError(f"{max(option.opts, key=len)} does not apply to a {kind} run"
                                   " (--from)")  # fmt: skip
    record = remake_file_record(stored, params["from_run"])
    output, compress, meta = params["output"], params["compress"], record.metadata
    write_run(output, record, compression=None if compress == "none" else compress)
    peak = abs(record.tau).max()
    click.echo(f"wrote {output}: {meta.robot} ({kind}), {record.n_samples} samples at {meta.rate:g}"
               f" Hz, peak |tau| {peak:.4g} (N*m, N for a prismatic joint)")  # fmt: skip
