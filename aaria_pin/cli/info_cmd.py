"""``aaria info``: a summary of a run file (any robot, any version) or a data set; a data card.

``aaria info --card DS.h5`` prints a data set's card (:mod:`aaria_pin.apps.dataset.card`): the
stored one when it is current, else one computed from the file. A run file has no card: its
``aaria info`` already lists all a card would (its attributes, arrays, units), and a card's
counts of runs by structure, failures and ranges drawn from belong to a data set; ``--card`` on
a run file is refused in one line (exit 2).
"""

from __future__ import annotations

import contextlib
import json
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import click


@click.command(
    epilog="""\b
Examples:
  aaria info run.h5               # a run: robot, samples, rate, joints, IMUs, arrays
  aaria info ds.h5                # a data set: runs complete and failed, settings, arrays
  aaria info --card ds.h5         # its data card
  aaria info --json ds.h5         # the summary as JSON"""
)
@click.argument("file", type=click.Path(path_type=Path, dir_okay=False))
@click.option("--json", "as_json", is_flag=True, help="Print the summary (or the card) as JSON.")
@click.option(
    "--card",
    is_flag=True,
    help="Print a data set's card: command, versions, ranges, columns with units and frames, "
    "noise, runs by structure, failures.",
)
def info(file: Path, as_json: bool, card: bool) -> None:
    """Summarise a run file or a data set: kind, robot, samples, rate, joints, IMUs, arrays.

    With --card, a data set's data card instead (the stored one when current).
    """
    from aaria_pin.files.dataset.summary import dataset_summary
    from aaria_pin.files.detection import is_dataset_file
    from aaria_pin.files.runfile import run_file_summary

    is_dataset = is_dataset_file(file)
    with _damaged_data_set(file, is_dataset):
        if card:
            _echo_card(file, is_dataset, as_json)
            return
        summary: dict[str, Any] = dataset_summary(file) if is_dataset else run_file_summary(file)
    if as_json:
        click.echo(json.dumps(summary, indent=2, default=str))
    elif is_dataset:
        _echo_dataset(file, summary)
    else:
        _echo_run(file, summary)


@contextlib.contextmanager
def _damaged_data_set(file: Path, is_dataset: bool) -> Iterator[None]:
    """A data set HDF5 cannot read as one (an array missing, a damaged index): one line.

    The toolkit's own errors pass through as they are.
    """
    from aaria_pin.errors import AariaError, InputFileError
    from aaria_pin.files._stored import first_line

    try:
        yield
    except AariaError:
        raise
    except (KeyError, OSError, RuntimeError, ValueError) as exc:
        if not is_dataset:
            raise
        raise InputFileError(
            f"{file}: a damaged data set ({first_line(exc)}); allowed: a complete aaria_pin"
            " data set (make it again)"
        ) from None


def _shape(shape: Sequence[int]) -> str:
    """A shape as ``11 × 91``."""
    return " × ".join(map(str, shape)) if len(shape) else "scalar"


def _names(names: Sequence[str]) -> str:
    """A name list for one line: the count and the names."""
    return f"{len(names)}: {', '.join(names)}" if names else "none"


def _echo_arrays(arrays: Mapping[str, Sequence[int]], views: Mapping[str, Sequence[int]]) -> None:
    """The arrays and views with their shapes, one a line."""
    width = max((len(name) for name in (*arrays, *views)), default=0) + 2
    for name, shape in arrays.items():
        click.echo(f"  {name:<{width}} {_shape(shape)}")
    for name, shape in views.items():
        click.echo(f"  {name:<{width}} {_shape(shape)} (view)")


def _echo_run(file: Path, summary: Mapping[str, Any]) -> None:
    """A run file's summary (keys of :func:`aaria_pin.files.runfile.run_file_summary`)."""
    rate = summary["rate"]
    click.echo(
        f"{file}: {summary['kind'] or 'unknown'} run of {summary['robot'] or 'an unnamed robot'}, "
        f"{summary['samples']} samples" + (f" at {rate:g} Hz" if rate else "")
    )
    click.echo(
        f"file: {summary['format']}, {summary['layout']} layout, "
        f"format version {summary['format_version']}"
    )
    click.echo(f"joints ({_names(summary['joints'])})")
    click.echo(f"IMUs ({_names(summary['imus'])})")
    click.echo("arrays:")
    _echo_arrays(summary["arrays"], summary["views"])
    click.echo("attributes:")
    for key, value in summary["attributes"].items():
        click.echo(f"  {key}: {json.dumps(value, default=str)}")


def _echo_dataset(file: Path, summary: Mapping[str, Any]) -> None:
    """A data set's summary (keys of :func:`aaria_pin.files.dataset.summary.dataset_summary`)."""
    get = summary.get
    robot = get("robot")
    robot_name = robot.get("name") if isinstance(robot, Mapping) else robot
    kind = get("kind")
    click.echo(
        f"{file}: data set of {get('runs')} "
        + (f"{kind} " if kind else "")
        + f"runs × {get('samples')} samples ({get('dtype')}), {get('complete')} complete, "
        f"failed {get('failed') or 'none'}"
    )
    if "format_version" in summary:
        click.echo(f"file: HDF5, format version {get('format_version')}")
    click.echo(
        f"seed {get('seed')}, vary {','.join(get('vary') or [])}, rate {get('rate')} Hz, "
        f"duration {get('duration')} s, noise {get('noise')}"
    )
    if isinstance(robot, Mapping):
        click.echo(
            f"robot {robot_name} ({robot.get('source')}), "
            f"{len(robot.get('joint_names', []))} joints, {len(robot.get('imu_names', []))} IMUs, "
            f"tool {robot.get('tool_frame')}, "
            f"{'moving' if robot.get('moving_base') else 'fixed'} base"
        )
    elif robot_name:
        click.echo(f"robot {robot_name}")
    for key, label in (("joints", "joints"), ("imus", "IMUs")):
        names = get(key)
        if isinstance(names, list):
            click.echo(f"{label} ({_names(names)})")
    if "file_bytes" in summary and "data_bytes" in summary:
        click.echo(
            f"size on disk {summary['file_bytes'] / 1e6:.1f} MB "
            f"(arrays {summary['data_bytes'] / 1e6:.1f} MB uncompressed)"
        )
    click.echo("arrays:")
    _echo_arrays(get("arrays") or {}, get("views") or {})
    click.echo(f"config: {json.dumps(get('config'), default=str)}")


def _echo_card(file: Path, is_dataset: bool, as_json: bool) -> None:
    """A data set's card, as text or JSON; a run file is refused.

    Raises:
        ParameterError: ``file`` is a run file.
        InputFileError: ``file`` is missing or neither a run file nor a data set.
    """
    from aaria_pin.apps.dataset.card_file import current_card
    from aaria_pin.apps.dataset.card_text import card_text
    from aaria_pin.errors import ParameterError
    from aaria_pin.files.runfile import run_file_summary

    if not is_dataset:
        run_file_summary(file)  # a missing or unreadable file is refused as such
        raise ParameterError(
            parameter="card",
            value=True,
            allowed=f"a data set file ({file} is a run file; `aaria info {file}` describes it)",
        )
    data_card = current_card(file)
    if as_json:
        click.echo(json.dumps(data_card.to_dict(), indent=2))
    else:
        click.echo(card_text(data_card), nl=False)
