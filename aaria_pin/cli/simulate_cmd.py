"""``aaria simulate``: one run of an Aaria arm to an HDF5 or .mat run file."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from aaria_pin.cli._options import (
    load_robot_source,
    load_table_source,
    robot_source_options,
    table_source_options,
)

_FILE = click.Path(path_type=Path, dir_okay=False)
MAX_SEED = 2**63 - 1


def _read_mounts(path: Path) -> Any:
    from aaria_pin.errors import InputFileError

    if path.suffix.lower() == ".npy":
        import numpy as np

        try:
            return np.load(path, allow_pickle=False)
        except (OSError, ValueError) as exc:
            raise InputFileError(f"{path}: cannot be read as .npy ({exc})") from None
    from aaria_pin.runfile import read_run

    return read_run(path).imu_mount


@click.command()
@table_source_options
@robot_source_options
@click.option("--joints", "joints_file", type=_FILE, help="Joint oscillation table (senSenJ).")
@click.option("--base", "base_file", type=_FILE, help="Base oscillation table (senSenB).")
@click.option(
    "--imu-mount",
    "mount_file",
    type=_FILE,
    help="IMU mounting poses: .npy (14 × 4 × 4) or a run file.",
)
@click.option(
    "--from",
    "from_run",
    type=_FILE,
    help="Re-make the run stored in this run file; the options given beside it replace "
    "the stored ones.",
)
@click.option("--duration", type=float, help="Run length [s] (default 10).")
@click.option("--rate", type=float, help="Sample rate [Hz] (default 100).")
@click.option("--seed", type=click.IntRange(0, MAX_SEED), help="Seed of the IMU noise (default 0).")
@click.option("--density", type=float, help="Density of every body [kg/m^3] (default 2700).")
@click.option(
    "--drive",
    type=click.Choice(["motion", "torque"]),
    default="motion",
    show_default=True,
    help="Follow the joint table, or move under --torques by forward dynamics.",
)
@click.option(
    "--torques",
    "torques_file",
    type=click.Path(path_type=Path, dir_okay=False),
    help="T x 6 joint torques by module (CSV, .npy, .mat 'tau', or a run file) for --drive torque.",
)
@click.option("--noise/--no-noise", default=None, help="IMU noise on (default) or off.")
@click.option(
    "--compress",
    type=click.Choice(["none", "gzip", "lzf"]),
    default="none",
    show_default=True,
    help="HDF5 filter of the time series (gzip: smaller, MATLAB-readable, slower).",
)
@click.option("-o", "--output", type=_FILE, required=True, help="Run file: .h5 or .mat.")
def simulate(
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
    mount_file: Path | None,
    from_run: Path | None,
    duration: float | None,
    rate: float | None,
    seed: int | None,
    density: float | None,
    drive: str,
    torques_file: Path | None,
    noise: bool | None,
    compress: str,
    output: Path,
) -> None:
    """Simulate an arm on a moving base: joint values, IMUs, torques, base wrench.

    The arm is a DH arm (--preset, --dh, or --from an Aaria run file; 14 IMU slots, the senSen
    layout) or any URDF robot (--robot, --urdf, or --from a generic run file; two IMUs per
    moving link plus base and tool, the generic layout).
    """
    from aaria_pin._malloc import tune_malloc
    from aaria_pin.dh_robot import BodyDimensions
    from aaria_pin.errors import ParameterError
    from aaria_pin.io import read_table
    from aaria_pin.presets import get_preset
    from aaria_pin.runfile import write_run
    from aaria_pin.simulate import simulate_from_run_file, simulate_run

    tune_malloc()
    urdf_given = robot is not None or urdf_file is not None
    if urdf_given or (from_run is not None and _is_generic(from_run)):
        _simulate_urdf(
            robot,
            urdf_file,
            tool_frame,
            imu_layout_file,
            fixed_base,
            joints_file,
            base_file,
            from_run,
            duration,
            rate,
            seed,
            noise,
            compress,
            output,
            refused={
                "--preset": preset,
                "--dh": dh_file,
                "--imu-mount": mount_file,
                "--density": density,
                "--torques": torques_file,
                "--drive torque": "torque" if drive == "torque" else None,
            },
        )
        return
    for flag, value in (("--tool", tool_frame), ("--imu-layout", imu_layout_file)):
        if value is not None:
            raise click.UsageError(f"{flag} is for URDF robots (--robot or --urdf)")
    if fixed_base:
        raise click.UsageError("--fixed-base is for URDF robots (--robot or --urdf)")
    given = {"duration": duration, "rate": rate, "seed": seed, "noise": noise}
    overrides: dict[str, Any] = {key: value for key, value in given.items() if value is not None}
    if joints_file is not None:
        overrides["joint_table"] = read_table(joints_file, "senSenJ")
    if base_file is not None:
        overrides["base_table"] = read_table(base_file, "senSenB")
    if mount_file is not None:
        overrides["imu_mount"] = _read_mounts(mount_file)
    if density is not None:
        overrides["dims"] = BodyDimensions(density=density)
    if (drive == "torque") != (torques_file is not None):
        raise click.UsageError("--drive torque and --torques FILE go together")
    if torques_file is not None:
        if torques_file.suffix.lower() in (".h5", ".hdf5"):
            from aaria_pin.runfile import read_run

            overrides["torques"] = read_run(torques_file).tau
        else:
            overrides["torques"] = read_table(torques_file, "tau")
    if from_run is not None:
        if preset or dh_file:
            raise click.UsageError(
                "--from takes the DH table from the run file; drop --preset/--dh"
            )
        record = simulate_from_run_file(from_run, **overrides)
    else:
        table, table_convention, name = load_table_source(preset, dh_file, convention)
        if table_convention != "aaria":
            raise ParameterError(
                f"table {name!r} is a {table_convention} DH table; allowed: an Aaria 8 × 5 table"
            )
        if preset is not None:
            chosen = get_preset(preset)
            overrides.setdefault("joint_table", chosen.joint_table)
            overrides.setdefault("base_table", chosen.base_table)
        record = simulate_run(table, **overrides)
    write_run(output, record, compression=None if compress == "none" else compress)
    click.echo(
        f"wrote {output}: {record.senSen.shape[0]} samples at {record.attributes['rate']:g} Hz, "
        f"noise {'on' if record.attributes['noise'] else 'off'}, "
        f"peak |tau| {abs(record.tau).max():.4g}"
    )


def _is_generic(path: Path) -> bool:
    from aaria_pin.runfile import is_generic_run_file

    return is_generic_run_file(path)


def _simulate_urdf(
    robot: str | None,
    urdf_file: Path | None,
    tool_frame: str | None,
    imu_layout_file: Path | None,
    fixed_base: bool,
    joints_file: Path | None,
    base_file: Path | None,
    from_run: Path | None,
    duration: float | None,
    rate: float | None,
    seed: int | None,
    noise: bool | None,
    compress: str,
    output: Path,
    refused: dict[str, Any],
) -> None:
    """``aaria simulate --robot/--urdf``: one run of a URDF robot to a generic run file."""
    import warnings

    from aaria_pin.imu_layout import read_imu_layout
    from aaria_pin.io import read_table
    from aaria_pin.runfile import write_generic_run
    from aaria_pin.urdf_run import simulate_urdf_from_run_file, simulate_urdf_run

    for flag, value in refused.items():
        if value is not None:
            raise click.UsageError(f"{flag} is for DH arms; not allowed with a URDF robot")
    if compress != "none":
        raise click.UsageError("--compress is for DH arms; a URDF robot's run is uncompressed")
    if output.suffix.lower() not in (".h5", ".hdf5"):
        raise click.UsageError(f"{output}: a URDF robot's run is written as HDF5 (.h5, .hdf5)")
    if fixed_base and base_file is not None:
        raise click.UsageError("--base moves the base; not allowed with --fixed-base")
    if from_run is not None and tool_frame is not None:
        raise click.UsageError(
            "--tool with --from: the run file's IMU layout was made for its tool; re-simulate "
            "with --robot/--urdf instead"
        )
    given = {"duration": duration, "rate": rate, "seed": seed, "noise": noise}
    overrides: dict[str, Any] = {key: value for key, value in given.items() if value is not None}
    if tool_frame is not None:
        overrides["tool_frame"] = tool_frame
    if imu_layout_file is not None:
        overrides["imu_layout"] = read_imu_layout(imu_layout_file)
    if joints_file is not None:
        overrides["joint_table"] = read_table(joints_file, "joint_table")
    if base_file is not None:
        overrides["base_table"] = read_table(base_file, "senSenB")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        if from_run is not None:
            if robot is not None or urdf_file is not None:
                raise click.UsageError(
                    "--from takes the URDF from the run file; drop --robot/--urdf"
                )
            if fixed_base:
                overrides["moving_base"] = False
            record = simulate_urdf_from_run_file(from_run, **overrides)
        else:
            text, folder, source = load_robot_source(robot, urdf_file)
            record = simulate_urdf_run(
                text, urdf_dir=folder, source=source, moving_base=not fixed_base, **overrides
            )
    for warning in caught:
        click.echo(f"aaria: warning: {warning.message}", err=True)
    for joint, (peak, limit) in record.attributes["effort_exceeded"].items():
        click.echo(
            f"aaria: warning: joint {joint!r} reaches |tau| {peak:.4g}, beyond its URDF effort "
            f"limit {limit:.4g} (N*m or N)",
            err=True,
        )
    write_generic_run(output, record)
    click.echo(
        f"wrote {output}: {record.attributes['robot']}, {len(record.joint_names)} joints, "
        f"{len(record.imu_mounts)} IMUs, {record.signals.shape[0]} samples at "
        f"{record.attributes['rate']:g} Hz, noise {'on' if record.attributes['noise'] else 'off'}, "
        f"peak |tau| {abs(record.tau).max():.4g}"
    )
