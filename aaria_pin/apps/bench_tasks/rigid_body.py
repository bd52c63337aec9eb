"""The rigid-body baselines of the ``inverse-dynamics`` task: the classical one and the ceiling.

- :func:`rigid_body` (``rigid-body``), what a user with the task's inputs would write: the RNEA
  torques of the arm built from its table ``senSenDH``
  (:func:`~aaria_pin.aaria.dh_robot.build_dh_robot`: the Aaria modules' density-based bodies)
  on its base motion (``senSenB``), along the joint motion estimated from the encoders: a
  Savitzky-Golay filter (:func:`scipy.signal.savgol_filter`, cubic, :data:`POLYORDER`) of
  ``q_measured`` gives the joint values, their rates and accelerations. Its window, in samples,
  is the one of :data:`WINDOWS` whose predictions have the smallest median relative RMS over
  the TRAINING runs (:func:`choose_window`); the test runs are read for their inputs only. A
  Savitzky-Golay filter rather than a smoothing spline: one window, the same for every run and
  joint, chosen on data, where a spline's smoothing weight would depend on each run's scale.
- :func:`rigid_body_truth` (``rigid-body-truth``), the ceiling: the model the data set rebuilds
  from the run (:func:`~aaria_pin.apps.record_model.record_model`) along the hidden TRUE ``q``,
  ``qd``, ``qdd``: the simulator's own torques, to the float32 storage. It reads what the task
  hides, so it is not a baseline a model can be compared with, only the limit of the metric.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin.apps.bench_tasks.metrics import relative_rms
from aaria_pin.core.se3 import Array

if TYPE_CHECKING:
    from aaria_pin.files.dataset.reader import DatasetReader

__all__ = [
    "POLYORDER",
    "WINDOWS",
    "choose_window",
    "encoder_motion",
    "rigid_body",
    "rigid_body_truth",
    "table_torques",
]

POLYORDER = 3
"""The Savitzky-Golay filter's polynomial order (cubic: its second derivative is not flat)."""

WINDOWS = (5, 7, 9, 11, 15, 21, 31, 41, 61)
"""The filter's windows tried [samples] (at 100 Hz: 0.05 s to 0.61 s); longer than a run: left
out."""

_INPUTS = ("time", "q_measured", "senSenB", "senSenDH")
"""What :func:`rigid_body` reads of a run (its inputs, and the sample times)."""


def encoder_motion(q_measured: Array, rate: float, window: int) -> tuple[Array, Array, Array]:
    """Joint values, rates and accelerations from encoder readings (Savitzky-Golay).

    Args:
        q_measured: the readings, T × n [rad or m]
        rate: sample rate [Hz]
        window: the filter's window [samples], odd, above :data:`POLYORDER`, at most T

    Returns:
        ``q`` [rad or m], ``qd`` [rad/s or m/s], ``qdd`` [rad/s² or m/s²], each T × n.
    """
    from scipy.signal import savgol_filter

    readings = np.asarray(q_measured, dtype=float)
    return tuple(  # type: ignore[return-value]
        np.ascontiguousarray(
            savgol_filter(readings, window, POLYORDER, deriv=order, delta=1.0 / rate, axis=0)
        )
        for order in (0, 1, 2)
    )


def table_torques(
    run: dict[str, Any], joint_names: Sequence[str], rate: float, windows: Sequence[int]
) -> list[Array]:
    """The RNEA torques of a run's arm built from its table, one T × n array per window.

    Args:
        run: the run's arrays :data:`_INPUTS` (``DatasetReader.run``)
        joint_names: the names of the run's n joint columns (an empty module's column stays 0)
        rate: sample rate [Hz]
        windows: the filter's windows [samples]
    """
    from aaria_pin.aaria.dh_robot import build_dh_robot
    from aaria_pin.core.dynamics import inverse_dynamics
    from aaria_pin.core.oscillation import base_motion
    from aaria_pin.core.trajectory import JointTrajectory

    time = np.asarray(run["time"], dtype=float)
    robot = build_dh_robot(np.asarray(run["senSenDH"], dtype=float)).model(moving_base=True)
    base = base_motion(np.asarray(run["senSenB"], dtype=float), time)
    readings = np.asarray(run["q_measured"], dtype=float)
    columns = [list(joint_names).index(name) for name in robot.joint_names]
    result = []
    for window in windows:
        motion = [m[:, columns] for m in encoder_motion(readings, rate, window)]
        torques = np.zeros(readings.shape)
        torques[:, columns] = inverse_dynamics(robot, base, JointTrajectory(time, *motion))[0]
        result.append(torques)
    return result


def _joint_names(reader: DatasetReader) -> tuple[str, ...]:
    """The names of a data set's joint columns.

    Raises:
        InputFileError: a data set without a layout (older than the task's).
    """
    if reader.layout is None:
        from aaria_pin.errors import InputFileError

        raise InputFileError(
            f"{reader.path} has no joint layout; allowed: a task's data set (aaria bench-task "
            "make)",
            parameter="directory",
            value=str(reader.path),
        )
    return reader.layout.joint_names


def _training_errors(task: tuple[str, int, float, tuple[int, ...]]) -> list[float]:
    """A training run's relative RMS error for each window (its target read: a training run)."""
    from aaria_pin.files.dataset.reader import DatasetReader

    path, run, rate, windows = task
    with DatasetReader(path) as reader:
        arrays = reader.run(run, [*_INPUTS, "tau"])
        names = _joint_names(reader)
    return [relative_rms(arrays["tau"], t) for t in table_torques(arrays, names, rate, windows)]


def _test_torques(task: tuple[str, int, float, tuple[int, ...]]) -> Array:
    """A test run's torques for its window (its inputs only read)."""
    from aaria_pin.files.dataset.reader import DatasetReader

    path, run, rate, windows = task
    with DatasetReader(path) as reader:
        arrays = reader.run(run, list(_INPUTS))
        names = _joint_names(reader)
    return table_torques(arrays, names, rate, windows)[0]


def choose_window(dataset: Path, train: Sequence[int], rate: float, workers: int) -> int:
    """The window of :data:`WINDOWS` with the smallest median relative RMS on training runs.

    Args:
        dataset: the task's data set
        train: the training runs (the only runs read)
        rate: sample rate [Hz]
        workers: processes

    Returns:
        The window [samples] (the shortest of equal medians).

    Raises:
        InputFileError: runs shorter than the shortest window.
    """
    from aaria_pin.apps.pool import completed
    from aaria_pin.files.dataset.reader import DatasetReader

    with DatasetReader(dataset) as reader:
        samples = reader.samples
    windows = tuple(w for w in WINDOWS if w <= samples)
    if not windows:
        from aaria_pin.errors import InputFileError

        raise InputFileError(
            f"{dataset}: runs of {samples} samples; allowed: at least {WINDOWS[0]} (the "
            "rigid-body baseline's shortest filter window)",
            parameter="directory",
            value=samples,
        )
    tasks = [(str(dataset), int(run), rate, windows) for run in train]
    errors = np.zeros((len(tasks), len(windows)))
    for index, values in completed(_training_errors, tasks, workers):
        errors[index] = values
    return windows[int(np.argmin(np.median(errors, axis=0)))]


def rigid_body(dataset: Path, card: dict[str, Any], workers: int) -> dict[int, np.ndarray]:
    """The classical baseline (see the module docstring): run index → T × 6 torques."""
    from aaria_pin.apps.pool import completed

    rate = float(card["spec"]["rate"])
    window = choose_window(dataset, card["splits"]["train"], rate, workers)
    runs = [int(k) for k in card["splits"]["test"]]
    tasks = [(str(dataset), run, rate, (window,)) for run in runs]
    return {runs[index]: torques for index, torques in completed(_test_torques, tasks, workers)}


def rigid_body_truth(dataset: Path, card: dict[str, Any], _workers: int) -> dict[int, np.ndarray]:
    """The ceiling (see the module docstring): run index → T × 6 torques."""
    from aaria_pin.apps.record_model import record_base, record_columns, record_model
    from aaria_pin.apps.torques import torque_split
    from aaria_pin.core.trajectory import BaseMotion, JointTrajectory
    from aaria_pin.files.dataset.reader import DatasetReader

    predictions: dict[int, np.ndarray] = {}
    with DatasetReader(dataset) as reader:
        for run in (int(k) for k in card["splits"]["test"]):
            record = reader.record(run)
            base = record_base(record)
            robot = record_model(record, moving_base=base is not None)
            columns = record_columns(record, robot)
            motion = [np.ascontiguousarray(np.asarray(getattr(record, name), float)[:, columns])
                      for name in ("q", "qd", "qdd")]  # fmt: skip
            time = np.asarray(record.time, dtype=float)
            trajectory = JointTrajectory(time, *motion)
            split = torque_split(robot, base or BaseMotion.resting(time.size), trajectory)
            torques = np.zeros(card["target_shape"])
            torques[:, columns] = sum(split.values())
            predictions[run] = torques
    return predictions
