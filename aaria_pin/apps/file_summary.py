"""What ``aaria info`` and ``aaria dataset-stats`` tell of a file: summaries, cards, statistics.

:func:`describe_file` reads a run file (any robot, any version) or a data set and gives its
summary as numbers and as text; with ``card=True`` a data set's card
(:mod:`aaria_pin.apps.dataset.card`: the stored one when it is current, else one computed from
the file). A run file has no card: its summary already lists all a card would (its attributes,
arrays, units), and a card's counts of runs by structure, failures and ranges drawn from belong
to a data set; ``card=True`` on a run file is refused (``parameter="card"``).
"""

from __future__ import annotations

import contextlib
import json
import os
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

__all__ = ["describe_file", "statistics_report"]


def describe_file(path: str | os.PathLike[str], card: bool = False) -> tuple[dict[str, Any], str]:
    """A run file's or a data set's summary, or a data set's card: as numbers and as text.

    Args:
        path: a run file or a data set
        card: give the data set's card instead of its summary

    Returns:
        The summary (:func:`aaria_pin.files.runfile.run_file_summary`,
        :func:`aaria_pin.files.dataset.summary.dataset_summary`) or the card's dictionary, and
        the text that says it (ending in a newline).

    Raises:
        ParameterError: ``card`` for a run file.
        InputFileError: a missing or unreadable file, or a damaged data set.
    """
    from aaria_pin.files.dataset.summary import dataset_summary
    from aaria_pin.files.detection import is_dataset_file
    from aaria_pin.files.runfile import is_recorded_file, recorded_summary, run_file_summary

    file = Path(path)
    is_dataset = is_dataset_file(file)
    with _damaged_data_set(file, is_dataset):
        if card:
            return _card(file, is_dataset)
        if is_dataset:
            summary = dataset_summary(file)
            return summary, _dataset_text(file, summary)
        if is_recorded_file(file):  # measured streams, each at its own times
            return recorded_summary(file)
        summary = run_file_summary(file)
        return summary, _run_text(file, summary)


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
            " data set (make it again)",
            parameter="file",
        ) from None


def _shape(shape: Sequence[int]) -> str:
    """A shape as ``11 × 91``."""
    return " × ".join(map(str, shape)) if len(shape) else "scalar"


def _names(names: Sequence[str]) -> str:
    """A name list for one line: the count and the names."""
    return f"{len(names)}: {', '.join(names)}" if names else "none"


def _arrays(arrays: Mapping[str, Sequence[int]], views: Mapping[str, Sequence[int]]) -> list[str]:
    """The arrays and views with their shapes, one a line."""
    width = max((len(name) for name in (*arrays, *views)), default=0) + 2
    return [f"  {name:<{width}} {_shape(shape)}" for name, shape in arrays.items()] + [
        f"  {name:<{width}} {_shape(shape)} (view)" for name, shape in views.items()
    ]


def _run_text(file: Path, summary: Mapping[str, Any]) -> str:
    """A run file's summary (keys of :func:`aaria_pin.files.runfile.run_file_summary`)."""
    rate = summary["rate"]
    lines: list[str] = []
    lines.append(
        f"{file}: {summary['kind'] or 'unknown'} run of {summary['robot'] or 'an unnamed robot'}, "
        f"{summary['samples']} samples" + (f" at {rate:g} Hz" if rate else "")
    )
    lines.append(
        f"file: {summary['format']}, {summary['layout']} layout, "
        f"format version {summary['format_version']}"
    )
    lines.append(f"joints ({_names(summary['joints'])})")
    lines.append(f"IMUs ({_names(summary['imus'])})")
    lines.append("arrays:")
    lines += _arrays(summary["arrays"], summary["views"])
    lines.append("attributes:")
    for key, value in summary["attributes"].items():
        lines.append(f"  {key}: {json.dumps(value, default=str)}")
    return "\n".join(lines) + "\n"


def _dataset_text(file: Path, summary: Mapping[str, Any]) -> str:
    """A data set's summary (keys of :func:`aaria_pin.files.dataset.summary.dataset_summary`)."""
    get = summary.get
    lines: list[str] = []
    robot = get("robot")
    robot_name = robot.get("name") if isinstance(robot, Mapping) else robot
    kind = get("kind")
    lines.append(
        f"{file}: data set of {get('runs')} "
        + (f"{kind} " if kind else "")
        + f"runs × {get('samples')} samples ({get('dtype')}), {get('complete')} complete, "
        f"failed {get('failed') or 'none'}"
    )
    if "format_version" in summary:
        lines.append(f"file: HDF5, format version {get('format_version')}")
    lines.append(
        f"seed {get('seed')}, vary {','.join(get('vary') or [])}, rate {get('rate')} Hz, "
        f"duration {get('duration')} s, noise {get('noise')}"
    )
    if isinstance(robot, Mapping):
        lines.append(
            f"robot {robot_name} ({robot.get('source')}), "
            f"{len(robot.get('joint_names', []))} joints, {len(robot.get('imu_names', []))} IMUs, "
            f"tool {robot.get('tool_frame')}, "
            f"{'moving' if robot.get('moving_base') else 'fixed'} base"
        )
    elif robot_name:
        lines.append(f"robot {robot_name}")
    for key, label in (("joints", "joints"), ("imus", "IMUs")):
        names = get(key)
        if isinstance(names, list):
            lines.append(f"{label} ({_names(names)})")
    if "file_bytes" in summary and "data_bytes" in summary:
        lines.append(
            f"size on disk {summary['file_bytes'] / 1e6:.1f} MB "
            f"(arrays {summary['data_bytes'] / 1e6:.1f} MB uncompressed)"
        )
    lines.append("arrays:")
    lines += _arrays(get("arrays") or {}, get("views") or {})
    lines.append(f"config: {json.dumps(get('config'), default=str)}")
    return "\n".join(lines) + "\n"


def _card(file: Path, is_dataset: bool) -> tuple[dict[str, Any], str]:
    """A data set's card, as a dictionary and as text; a run file is refused.

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
    return data_card.to_dict(), card_text(data_card)


def statistics_report(
    path: str | os.PathLike[str],
    names: Sequence[str] | None = None,
    split: str = "train",
    seed: int = 0,
    fractions: Sequence[float] = (0.8, 0.1, 0.1),
    store: bool = False,
) -> tuple[dict[str, Any], str]:
    """Per-channel mean and std of a data set's arrays over one split: numbers and a table.

    The statistics a training loop normalises with (:meth:`DatasetReader.statistics
    <aaria_pin.files.dataset.reader.DatasetReader.statistics>`): one streaming pass over the
    split's complete runs; ``store`` writes them into the file
    (``statistics/<split>/<name>/mean|std``), where ``DatasetReader.windows(...,
    normalise=True)`` finds them.

    Args:
        path: the data set
        names: arrays or views (default: the first view)
        split: ``"train"``, ``"validation"``, ``"test"`` or ``"all"`` (every complete run)
        seed: the split's seed
        fractions: of the runs in the train, validation and test splits
        store: store them in the file (replacing the split's)

    Returns:
        ``{name: {"mean": [...], "std": [...]}}`` and the table: a line per channel.

    Raises:
        InputFileError: a missing file, a folder, or not a data set.
        ParameterError: an unknown name or split, bad fractions.
        OptionConflictError: a seed or fractions other than the defaults with ``split="all"``
            (they choose a split: with every run they would be ignored).
    """
    import numpy as np

    from aaria_pin.core.conflicts import OptionConflictError
    from aaria_pin.files.dataset.reader import DatasetReader
    from aaria_pin.files.io import existing_input

    chosen = None if split == "all" else split
    if chosen is None and (seed != 0 or tuple(fractions) != (0.8, 0.1, 0.1)):
        name = "seed" if seed != 0 else "fractions"
        raise OptionConflictError(parameter=name, other="split", given_with=True, other_value="all")
    existing_input(path, None, "data set")  # a missing file or a folder in one line
    with DatasetReader(path) as reader:
        statistics = reader.statistics(
            names, split=chosen, seed=seed, fractions=fractions, store=store
        )
        runs = len(reader.split_runs(chosen, seed, fractions))
        views = reader.layout.views if reader.layout is not None else {}
    shares = ",".join(f"{share:g}" for share in fractions)
    lines = [f"{path}: split {split} (seed {seed}, fractions {shares}), {runs} runs"]
    for name, (mean, std) in statistics.items():
        lines.append(f"{name} ({' × '.join(map(str, mean.shape)) or 'scalar'} channels)")
        lines.append(f"  {'channel':<24} {'mean':>14} {'std':>14}")
        columns = views[name].columns if name in views else None
        for index in np.ndindex(mean.shape):
            label = columns[index[0]] if columns is not None else str(list(index))
            lines.append(f"  {label:<24} {mean[index]:>14.6g} {std[index]:>14.6g}")
    if store:
        lines.append(f"stored in {path} under statistics/{split}")
    document = {
        name: {"mean": m.tolist(), "std": s.tolist()} for name, (m, s) in statistics.items()
    }
    return document, "\n".join(lines)
