"""``aaria info``: a summary of a run file or a data set."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import click


@click.command()
@click.argument("file", type=click.Path(path_type=Path, dir_okay=False))
@click.option("--json", "as_json", is_flag=True, help="Print the summary as JSON.")
def info(file: Path, as_json: bool) -> None:
    """Summarise a run file or a data set: runs, shapes, sizes, seed, config, completeness."""
    from aaria_pin.files.dataset_file import is_dataset_file
    from aaria_pin.files.dataset_reader import dataset_summary
    from aaria_pin.files.runfile import generic_run_summary, is_generic_run_file, run_file_summary

    is_dataset = is_dataset_file(file)
    if is_dataset:
        summary: dict[str, Any] = dataset_summary(file)
    elif is_generic_run_file(file):
        summary = generic_run_summary(file)
    else:
        summary = run_file_summary(file)
    if as_json:
        click.echo(json.dumps(summary, indent=2, default=str))
        return
    if is_dataset:
        click.echo(
            f"{file}: data set of {summary['runs']} runs × {summary['samples']} samples "
            f"({summary['dtype']}), {summary['complete']} complete, "
            f"failed {summary['failed'] or 'none'}"
        )
        click.echo(
            f"seed {summary['seed']}, vary {','.join(summary['vary'] or [])}, "
            f"rate {summary['rate']} Hz, duration {summary['duration']} s, noise {summary['noise']}"
        )
        if "robot" in summary:
            robot = summary["robot"]
            click.echo(
                f"robot {robot['name']} ({robot['source']}), {len(robot['joint_names'])} joints, "
                f"{len(robot['imu_names'])} IMUs, tool {robot['tool_frame']}, "
                f"{'moving' if robot['moving_base'] else 'fixed'} base"
            )
        click.echo(
            f"size on disk {summary['file_bytes'] / 1e6:.1f} MB "
            f"(arrays {summary['data_bytes'] / 1e6:.1f} MB uncompressed)"
        )
        for name, shape in summary["arrays"].items():
            click.echo(f"  {name:<12} {' × '.join(map(str, shape))}")
        click.echo(f"config: {json.dumps(summary['config'])}")
    else:
        click.echo(f"{file}: run file ({summary['format']}), {summary['samples']} samples")
        if "joints" in summary:
            click.echo(f"  joints: {', '.join(summary['joints'])}")
            click.echo(f"  IMUs: {', '.join(summary['imus']) or 'none'}")
        for name, shape in summary["arrays"].items():
            click.echo(f"  {name:<12} {' × '.join(map(str, shape))}")
        for key, value in summary["attributes"].items():
            click.echo(f"  {key}: {value}")
