"""``aaria simulate``: one run of an Aaria arm to an HDF5 or .mat run file."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from aaria_pin.cli._options import load_table_source, table_source_options

_FILE = click.Path(path_type=Path, dir_okay=False)


def _inputs_from_run(path: Path) -> dict[str, Any]:
    from aaria_pin.runfile import read_run

    record = read_run(path)
    attrs = record.attributes
    return {
        "dh_table": record.senSenDH,
        "joint_table": record.senSenJ,
        "base_table": record.senSenB,
        "duration": attrs.get("duration"),
        "rate": attrs.get("rate"),
        "seed": attrs.get("seed"),
        "noise": attrs.get("noise"),
    }


@click.command()
@table_source_options
@click.option("--joints", "joints_file", type=_FILE, help="Joint oscillation table (senSenJ).")
@click.option("--base", "base_file", type=_FILE, help="Base oscillation table (senSenB).")
@click.option("--from", "from_run", type=_FILE, help="Re-make the run stored in this run file.")
@click.option("--duration", type=float, help="Run length [s] (default 10).")
@click.option("--rate", type=float, help="Sample rate [Hz] (default 100).")
@click.option("--seed", type=int, help="Seed of the IMU noise (default 0).")
@click.option("--no-noise", is_flag=True, default=None, help="Exact IMU signals, no noise.")
@click.option("-o", "--output", type=_FILE, required=True, help="Run file: .h5 or .mat.")
def simulate(
    preset: str | None,
    dh_file: Path | None,
    convention: str,
    joints_file: Path | None,
    base_file: Path | None,
    from_run: Path | None,
    duration: float | None,
    rate: float | None,
    seed: int | None,
    no_noise: bool | None,
    output: Path,
) -> None:
    """Simulate an arm on a moving base: joint values, 14 IMUs, torques, base wrench."""
    from aaria_pin.errors import ParameterError
    from aaria_pin.io import read_table
    from aaria_pin.runfile import write_run
    from aaria_pin.simulate import DEFAULT_DURATION, DEFAULT_RATE, simulate_run

    if from_run is not None:
        if preset or dh_file or joints_file or base_file:
            raise click.UsageError("--from takes the tables from the run file; drop --preset/--dh")
        inputs = _inputs_from_run(from_run)
    else:
        table, table_convention, name = load_table_source(preset, dh_file, convention)
        if table_convention != "aaria":
            raise ParameterError(
                f"table {name!r} is a {table_convention} DH table; allowed: an Aaria 8 × 5 table"
            )
        inputs = {
            "dh_table": table,
            "joint_table": read_table(joints_file, "senSenJ") if joints_file else None,
            "base_table": read_table(base_file, "senSenB") if base_file else None,
        }
    stored = {"duration": DEFAULT_DURATION, "rate": DEFAULT_RATE, "seed": 0, "noise": True}
    stored.update({k: v for k, v in inputs.items() if k in stored and v is not None})
    record = simulate_run(
        inputs["dh_table"],
        inputs["joint_table"],
        inputs["base_table"],
        duration=duration if duration is not None else stored["duration"],
        rate=rate if rate is not None else stored["rate"],
        seed=seed if seed is not None else int(stored["seed"]),
        noise=False if no_noise else bool(stored["noise"]),
    )
    write_run(output, record)
    n = record.senSen.shape[0]
    click.echo(
        f"wrote {output}: {n} samples at {record.attributes['rate']:g} Hz, "
        f"noise {'on' if record.attributes['noise'] else 'off'}, "
        f"peak |tau| {abs(record.tau).max():.4g}"
    )
