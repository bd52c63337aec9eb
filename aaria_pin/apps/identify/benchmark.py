"""The identification benchmark over data sets: per run the identification, then accuracy by group.

:func:`benchmark_datasets` identifies every complete run of one or more DH data sets
(``aaria dataset``), each run from its own record in a process of a pool (each process opens
the file itself, as the data set's workers wrote it), and :func:`accuracy_table` groups the
runs by the data set's ``noise`` attribute, run length and rate: what share of arms has every
link type right, the tool tip's position RMS error over the run (median, 95th percentile,
largest), the share within 1 mm and 1 cm, and the seconds per arm; with ``dynamics`` also the
dynamic identification's held-out relative torque error. A run whose identification fails is
counted in its group with its error message (never dropped).

Example::

    from aaria_pin.apps.identify.benchmark import accuracy_table, benchmark_datasets

    runs = benchmark_datasets(["clean.h5", "noisy.h5"], workers=2)
    for group in accuracy_table(runs):
        print(group["noise"], group["duration_s"], group["tool_tip_rms_median_m"])
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from aaria_pin.apps.identify._json import json_number
from aaria_pin.apps.pool import completed

__all__ = [
    "WITHIN",
    "RunAccuracy",
    "accuracy_lines",
    "accuracy_table",
    "benchmark_datasets",
    "group_label",
    "identify_dataset_run",
    "tool_tip_cdf",
]

WITHIN = (1e-3, 1e-2)
"""[m] the tool-tip RMS thresholds the table gives the share of arms within."""


@dataclass(frozen=True)
class RunAccuracy:
    """The identification of one data set run against the truth it holds.

    Attributes:
        dataset: the data set file
        run: the run's index in it
        noise: whether the run's IMU signals are noisy (the data set's ``noise`` attribute)
        duration: run length [s]
        rate: sample rate [Hz]
        link_types: the true link type per module (``"120012"``)
        link_types_right: every module's link type estimated right
        tool_tip_rms: RMS of the tool tip's position error over the run [m] (NaN: no valid table)
        tool_tip_max: its largest value [m]
        axis_angle_max: the largest joint axis angle error [rad]
        seconds: time of the kinematic identification [s]
        dynamics_holdout_relative_rms: with dynamics, the largest held-out relative torque RMS
            over the joints, else None
        dynamics_seconds: time of the dynamic identification [s], or None
        error: the one-line error of a run whose identification failed, else None
        sigma_coverage: per DH parameter kind, the determined parameters within 2σ of the
            truth and their count (:func:`~aaria_pin.apps.identify.geometry_truth.sigma_coverage`)
    """

    dataset: str
    run: int
    noise: bool
    duration: float
    rate: float
    link_types: str
    link_types_right: bool
    tool_tip_rms: float
    tool_tip_max: float
    axis_angle_max: float
    seconds: float
    dynamics_holdout_relative_rms: float | None = None
    dynamics_seconds: float | None = None
    error: str | None = None
    sigma_coverage: dict[str, tuple[int, int]] | None = None

    def to_json(self) -> dict[str, Any]:
        """A JSON-ready dict (NaN as None)."""
        return {
            key: (None if isinstance(value, float) and not np.isfinite(value) else value)
            for key, value in asdict(self).items()
        }


def identify_dataset_run(
    path: str | os.PathLike[str], run: int, dynamics: bool = False, holdout: float = 0.2
) -> RunAccuracy:
    """Identify one run of a data set (kinematics, and with ``dynamics`` the inertial parameters).

    Errors of the identification itself (an :class:`~aaria_pin.errors.AariaError`) are
    returned in :attr:`RunAccuracy.error`; a file that cannot be read raises.

    Args:
        path: the data set
        run: the run's index
        dynamics: also identify the base inertial parameters
        holdout: with ``dynamics``, the share of the run, at its end, held out of the fit

    Returns:
        The run's accuracy.
    """
    from aaria_pin.apps.identify.geometry import identify_kinematics
    from aaria_pin.errors import AariaError
    from aaria_pin.files.dataset.reader import DatasetReader

    with DatasetReader(path) as reader:
        record = reader.record(run)
    metadata = record.metadata
    true_table = record.tables.get("senSenDH")
    types = (
        "" if true_table is None else "".join(str(int(t)) for t in np.asarray(true_table)[:6, 4])
    )
    common: dict[str, Any] = {
        "dataset": str(path),
        "run": int(run),
        "noise": metadata.noise,
        "duration": metadata.duration,
        "rate": metadata.rate,
        "link_types": types,
    }
    nan = float("nan")
    started = time.perf_counter()
    try:
        result = identify_kinematics(record)
    except AariaError as exc:
        return RunAccuracy(
            **common,
            link_types_right=False,
            tool_tip_rms=nan,
            tool_tip_max=nan,
            axis_angle_max=nan,
            seconds=time.perf_counter() - started,
            error=" ".join(str(exc).split()),
        )
    seconds = time.perf_counter() - started
    truth = result.truth
    dynamics_error: float | None = None
    dynamics_seconds: float | None = None
    if dynamics:
        from aaria_pin.apps.identify.inertial import identify_dynamics

        started = time.perf_counter()
        worst = identify_dynamics(record, holdout=holdout).worst_holdout_relative_rms
        dynamics_seconds = time.perf_counter() - started
        dynamics_error = json_number(worst)
    return RunAccuracy(
        **common,
        link_types_right=truth is not None and all(truth.link_types_right),
        tool_tip_rms=nan if truth is None else truth.tool_tip_rms,
        tool_tip_max=nan if truth is None else truth.tool_tip_max,
        axis_angle_max=(nan if truth is None else max(truth.axis_angle_max.values(), default=0.0)),
        seconds=seconds,
        dynamics_holdout_relative_rms=dynamics_error,
        dynamics_seconds=dynamics_seconds,
        sigma_coverage=None if truth is None else dict(truth.coverage),
        error=result.failure,  # a fit above the noise floor is a failure, counted as one
    )


def _identify_task(task: tuple[str, int, bool, float]) -> RunAccuracy:
    return identify_dataset_run(*task)


def benchmark_datasets(
    paths: Sequence[str | os.PathLike[str]],
    *,
    workers: int = 1,
    dynamics: bool = False,
    limit: int | None = None,
    progress: Callable[[RunAccuracy], None] | None = None,
    holdout: float = 0.2,
) -> list[RunAccuracy]:
    """Identify every complete run of each data set, in a pool of ``workers`` processes.

    Args:
        paths: the data sets (DH arms: ``aaria dataset`` without ``--robot``/``--urdf``)
        workers: processes; 1 identifies in this process
        dynamics: also identify the base inertial parameters of each run
        limit: at most this many complete runs of each data set (the first ones)
        progress: called with each run's result as it arrives
        holdout: with ``dynamics``, the share of each run held out of the fit

    Returns:
        One result per run, in data set and run order.

    Raises:
        InputFileError: a file that is not a readable data set, or one without a complete run.
        ParameterError: a data set of URDF robots, a limit below 1.
    """
    from aaria_pin.errors import InputFileError, ParameterError
    from aaria_pin.files.dataset.reader import DatasetReader

    if limit is not None and limit < 1:
        raise ParameterError(
            f"limit is {limit}; allowed: at least 1", parameter="limit", value=limit, allowed=">= 1"
        )
    tasks: list[tuple[str, int, bool, float]] = []
    for path in paths:
        with DatasetReader(path) as reader:
            kind = reader.header.kind
            if kind != "dh":
                raise ParameterError(
                    f"{path}: data set of kind {kind!r}; allowed: DH arms (kind 'dh')",
                    parameter="dataset",
                    value=str(path),
                    allowed="a data set of DH arms",
                )
            runs = [int(k) for k in np.flatnonzero(reader.complete)]
        if not runs:
            raise InputFileError(
                f"{path}: no complete run; allowed: a data set with a complete run "
                "(aaria dataset --resume completes it)",
                parameter="file",
                value=str(path),
            )
        tasks += [(str(path), k, dynamics, holdout) for k in runs[:limit]]
    results: list[RunAccuracy] = []
    for _, result in completed(_identify_task, tasks, workers):
        if progress is not None:
            progress(result)
        results.append(result)
    order = {(path, run): i for i, (path, run, *_) in enumerate(tasks)}
    return sorted(results, key=lambda r: order[(r.dataset, r.run)])


def _finite(values: Iterable[float | None]) -> Any:
    return np.array([v for v in values if v is not None and np.isfinite(v)], dtype=float)


def accuracy_table(results: Iterable[RunAccuracy]) -> list[dict[str, Any]]:
    """Accuracy by group of runs of the same noise, length and rate.

    A run without a valid table (or whose identification failed) counts as outside every
    threshold and enters the percentiles as infinitely wrong.

    Args:
        results: from :func:`benchmark_datasets`

    Returns:
        One dict per group, sorted by noise, duration, rate: ``noise``, ``duration_s``,
        ``rate_hz``, ``runs``, ``failed``, ``link_types_right_share``,
        ``tool_tip_rms_median_m``, ``tool_tip_rms_p95_m``, ``tool_tip_rms_max_m``,
        ``within_1mm_share``, ``within_1cm_share``, ``seconds_median``, ``seconds_max``, the
        share of determined DH parameters within 2σ of the truth ``sigma_coverage_2sigma``
        (and ``sigma_coverage_by_kind``), and (when identified)
        ``dynamics_holdout_relative_rms_median`` and ``…_max``.
    """
    groups: dict[tuple[bool, float, float], list[RunAccuracy]] = {}
    for result in results:
        groups.setdefault((result.noise, result.duration, result.rate), []).append(result)
    table = []
    for (noise, duration, rate), runs in sorted(groups.items()):
        rms = np.array(
            [
                r.tool_tip_rms if np.isfinite(r.tool_tip_rms) and r.error is None else np.inf
                for r in runs
            ],
            dtype=float,
        )
        seconds = np.array([r.seconds for r in runs], dtype=float)
        row: dict[str, Any] = {
            "noise": noise,
            "duration_s": duration,
            "rate_hz": rate,
            "runs": len(runs),
            "failed": sum(r.error is not None for r in runs),
            "link_types_right_share": float(np.mean([r.link_types_right for r in runs])),
            "tool_tip_rms_median_m": json_number(np.median(rms)),
            "tool_tip_rms_p95_m": json_number(np.percentile(rms, 95, method="higher")),
            "tool_tip_rms_max_m": json_number(np.max(rms)),
            "within_1mm_share": float(np.mean(rms <= WITHIN[0])),
            "within_1cm_share": float(np.mean(rms <= WITHIN[1])),
            "seconds_median": float(np.median(seconds)),
            "seconds_max": float(np.max(seconds)),
        }
        covered: dict[str, list[int]] = {}
        for r in runs:
            for kind, (inside, count) in (r.sigma_coverage or {}).items():
                covered.setdefault(kind, [0, 0])
                covered[kind][0] += inside
                covered[kind][1] += count
        if covered:
            inside = sum(v[0] for v in covered.values())
            row["sigma_coverage_2sigma"] = inside / max(sum(v[1] for v in covered.values()), 1)
            row["sigma_coverage_by_kind"] = {
                kind: {"within_2sigma": v[0], "parameters": v[1]} for kind, v in covered.items()
            }
        dynamic = _finite(r.dynamics_holdout_relative_rms for r in runs)
        if dynamic.size:
            row["dynamics_holdout_relative_rms_median"] = float(np.median(dynamic))
            row["dynamics_holdout_relative_rms_max"] = float(np.max(dynamic))
        table.append(row)
    return table


def group_label(group: dict[str, Any]) -> str:
    """A short label of a group: ``"noise, 30 s at 200 Hz"``."""
    noise = "ADIS16485 noise" if group["noise"] else "no noise"
    return f"{noise}, {group['duration_s']:g} s at {group['rate_hz']:g} Hz"


def _mm(value: float | None) -> str:
    return "-" if value is None else f"{value * 1e3:.3g}"


def accuracy_lines(groups: Sequence[dict[str, Any]]) -> list[str]:
    """An :func:`accuracy_table` as lines of a text table (a header, then a line per group)."""
    width = max([len(group_label(g)) for g in groups] + [5])
    dynamics = any("dynamics_holdout_relative_rms_median" in g for g in groups)
    header = (
        f"{'group':<{width}} {'arms':>5} {'failed':>6} {'types right':>11} "
        f"{'tool tip RMS [mm]: median':>25} {'p95':>7} {'max':>7} {'<=1 mm':>7} {'<=1 cm':>7} "
        f"{'s/arm':>6} {'2σ cover':>8}"
    )
    lines = [header + (f" {'torque held-out rel. RMS':>24}" if dynamics else "")]
    for g in groups:
        line = (
            f"{group_label(g):<{width}} {g['runs']:>5} {g['failed']:>6} "
            f"{g['link_types_right_share']:>11.1%} {_mm(g['tool_tip_rms_median_m']):>25} "
            f"{_mm(g['tool_tip_rms_p95_m']):>7} {_mm(g['tool_tip_rms_max_m']):>7} "
            f"{g['within_1mm_share']:>7.1%} {g['within_1cm_share']:>7.1%} "
            f"{g['seconds_median']:>6.1f} {g.get('sigma_coverage_2sigma', float('nan')):>8.1%}"
        )
        if dynamics:
            value = g.get("dynamics_holdout_relative_rms_median")
            line += f" {'-' if value is None else format(value, '.3g'):>24}"
        lines.append(line)
    return lines


def tool_tip_cdf(
    runs: Sequence[RunAccuracy], groups: Sequence[dict[str, Any]]
) -> list[tuple[str, Any, Any]]:
    """The cumulative distribution of the tool-tip RMS error per group, to plot (log scale).

    Args:
        runs: the runs' results (:func:`benchmark_datasets`)
        groups: their groups (:func:`accuracy_table`)

    Returns:
        Per group its label, the sorted finite errors [m] (at least 1e-9) and the share of
        the group's arms at or below each (a failed run counts as infinitely wrong).
    """
    curves = []
    for g in groups:
        key = (g["noise"], g["duration_s"], g["rate_hz"])
        errors = np.sort(
            [
                r.tool_tip_rms if np.isfinite(r.tool_tip_rms) else np.inf
                for r in runs
                if (r.noise, r.duration, r.rate) == key
            ]
        )
        share = np.arange(1, errors.size + 1) / errors.size
        finite = np.isfinite(errors)
        label = f"{group_label(g)} ({g['runs']} arms)"
        curves.append((label, np.maximum(errors[finite], 1e-9), share[finite]))
    return curves
