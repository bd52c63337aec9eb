"""Joint motions from given samples: a user's trajectory on a run's time grid, checked.

- :func:`trajectory_from_samples`: a user's motion given as samples of q (and optionally qd,
  qdd): derivatives by a spline through (or, with ``smoothing``, near) the samples, resampled
  on a run's time grid when the given times are not already one.
- :func:`check_trajectory`: a trajectory checked against a run's time grid and joint limits.
- :func:`fit_samples`: given samples (e.g. a trajectory file's) as a robot's joint motion:
  columns matched by name or order, mimic joints following their leaders, the run's grid.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.core.arguments import checked
from aaria_pin.core.oscillation import RANGE_TOLERANCE
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import (
    DEFAULT_RATE,
    MAX_SAMPLES,
    JointTrajectory,
    piece_times,
    sample_count,
    sample_times,
)
from aaria_pin.errors import InputFileError, ParameterError

__all__ = [
    "GivenSamples",
    "JointColumns",
    "check_trajectory",
    "fit_samples",
    "sample_columns",
    "trajectory_from_samples",
]


def _column_matrix(values: ArrayLike, n_samples: int, name: str) -> Array:
    """(T,) or (T, n) finite values as (T, n)."""
    array = np.asarray(values, dtype=float)
    if array.ndim == 1:
        array = array[:, None]
    if array.ndim != 2 or array.shape[0] != n_samples or array.shape[1] < 1:
        raise ParameterError(
            parameter=name, value=np.shape(values), allowed=f"({n_samples}, n) with n >= 1"
        )
    if not np.all(np.isfinite(array)):
        row = int(np.argwhere(~np.isfinite(array))[0, 0])
        raise ParameterError(
            parameter=name, value="not finite", allowed="finite numbers", element=f"row {row}"
        )
    return array


@checked
def trajectory_from_samples(
    time: ArrayLike,
    q: ArrayLike,
    qd: ArrayLike | None = None,
    qdd: ArrayLike | None = None,
    *,
    rate: float,
    smoothing: float = 0.0,
) -> JointTrajectory:
    """A joint trajectory on a run's time grid from samples of q (and optionally qd, qdd).

    The output grid starts at 0 and steps by ``1/rate`` over the samples' span
    (:func:`~aaria_pin.core.trajectory.sample_times` of ``time[-1] - time[0]``); it is the
    given times shifted to start at 0 when those are already such a grid (within 1e-9 of a
    step), and the given values are then returned as they are. Derivatives not given come from
    a quintic spline of q: through every sample when ``smoothing`` is 0 (scipy's
    ``make_interp_spline``), else the smoothest whose residuals have an RMS of ``smoothing``
    (``UnivariateSpline`` with ``s = T·smoothing²``, which FITPACK meets within 0.1 %). Given
    derivatives on other times are resampled by a cubic spline through them.

    Args:
        time: sample times, (T,), strictly increasing [s]
        q: joint values, (T,) or (T, n) [rad or m]
        qd: joint velocities, same shape, or None [rad/s or m/s]
        qdd: joint accelerations, same shape, or None [rad/s² or m/s²]
        rate: the output sample rate [Hz]
        smoothing: RMS of the noise of q allowed to be smoothed away [rad or m], >= 0

    Returns:
        The trajectory.

    Raises:
        ParameterError: times not strictly increasing or not finite, fewer than 6 samples
            (a quintic spline needs 6), shapes that do not match, values not finite, a
            negative smoothing, a rate or span :func:`sample_times` refuses.
    """
    from scipy.interpolate import UnivariateSpline, make_interp_spline

    times = np.asarray(time, dtype=float)
    if times.ndim != 1 or times.size < 6:
        raise ParameterError(
            parameter="time", value=np.shape(time), allowed="(T,) with T >= 6 samples"
        )
    if times.size > MAX_SAMPLES:
        raise ParameterError(
            parameter="time", value=times.size, allowed=f"at most {MAX_SAMPLES} samples"
        )
    if not np.all(np.isfinite(times)):
        raise ParameterError(parameter="time", value="not finite", allowed="finite times")
    steps = np.diff(times)
    if not np.all(steps > 0):
        row = int(np.argmax(steps <= 0)) + 1
        raise ParameterError(
            parameter="time",
            value=float(times[row]),
            allowed="strictly increasing times",
            element=f"row {row}",
        )
    if not (np.isfinite(smoothing) and smoothing >= 0):
        raise ParameterError(parameter="smoothing", value=smoothing, allowed=">= 0")
    n_samples = times.size
    values = _column_matrix(q, n_samples, "q")
    given = {
        name: None if x is None else _column_matrix(x, n_samples, name)
        for name, x in (("qd", qd), ("qdd", qdd))
    }
    for name, x in given.items():
        if x is not None and x.shape != values.shape:
            raise ParameterError(parameter=name, value=x.shape, allowed=f"{values.shape} as q")
    grid = sample_times(float(times[-1] - times[0]), rate)
    same_grid = grid.size == n_samples and np.allclose(
        times - times[0], grid, rtol=0.0, atol=1e-9 / rate
    )
    at = times[0] + grid
    if smoothing == 0:
        spline = make_interp_spline(times, values, k=5, axis=0)
        derivatives = [spline.derivative(1), spline.derivative(2)]
        q_out = values.copy() if same_grid else spline(at)
        qd_out, qdd_out = (d(at) for d in derivatives)
    else:
        s = n_samples * smoothing**2
        splines = [UnivariateSpline(times, column, k=5, s=s) for column in values.T]
        q_out = np.column_stack([sp(at) for sp in splines])
        qd_out = np.column_stack([sp.derivative(1)(at) for sp in splines])
        qdd_out = np.column_stack([sp.derivative(2)(at) for sp in splines])
    outputs = {"qd": qd_out, "qdd": qdd_out}
    for name, x in given.items():
        if x is not None:
            outputs[name] = x.copy() if same_grid else make_interp_spline(times, x, k=3)(at)
    return JointTrajectory(grid, np.asarray(q_out), outputs["qd"], outputs["qdd"])


# --- a run's motion: checked, stored, sliced into pieces, re-made ---------------------------------


def check_trajectory(
    trajectory: JointTrajectory,
    samples: int,
    rate: float,
    lower: ArrayLike,
    upper: ArrayLike,
    joint_names: tuple[str, ...] | list[str],
) -> JointTrajectory:
    """A given joint trajectory checked against a run: its samples, columns, finite numbers, range.

    Args:
        trajectory: the motion, q, qd and qdd each (T, n)
        samples: T, the run's number of samples
        rate: the run's sample rate [Hz]
        lower: each joint's lowest position, (n,) [rad or m] (-inf: unchecked)
        upper: each joint's highest position, (n,) [rad or m] (inf: unchecked)
        joint_names: the n joints, in column order

    Returns:
        The trajectory as C-ordered float arrays, ``time`` the run's time grid.

    Raises:
        ParameterError: (``trajectory``) another shape, a value not finite, or a joint that
            leaves its range, in one line naming the joint.
    """
    n_joints = len(joint_names)
    arrays = {}
    for name in ("q", "qd", "qdd"):
        array = np.ascontiguousarray(getattr(trajectory, name), dtype=float)
        if array.shape != (samples, n_joints):
            raise ParameterError(
                parameter="trajectory",
                value=f"{name} of shape {array.shape}",
                allowed=f"({samples}, {n_joints}): the run's samples × its joints",
            )
        if not np.all(np.isfinite(array)):
            row, column = (int(i) for i in np.argwhere(~np.isfinite(array))[0])
            raise ParameterError(
                parameter="trajectory",
                value="not finite",
                allowed="finite numbers",
                element=f"{name} row {row}, joint {joint_names[column]}",
            )
        arrays[name] = array
    low = np.broadcast_to(np.asarray(lower, dtype=float), (n_joints,))
    high = np.broadcast_to(np.asarray(upper, dtype=float), (n_joints,))
    q_min, q_max = arrays["q"].min(axis=0), arrays["q"].max(axis=0)
    outside = (q_min < low - RANGE_TOLERANCE) | (q_max > high + RANGE_TOLERANCE)
    if np.any(outside):
        j = int(np.argmax(outside))
        raise ParameterError(
            f"trajectory joint {joint_names[j]} moves over [{q_min[j]:.4g}, {q_max[j]:.4g}]; "
            f"allowed: within its range [{low[j]:.4g}, {high[j]:.4g}]",
            parameter="trajectory",
            value=[float(f"{q_min[j]:.4g}"), float(f"{q_max[j]:.4g}")],
            allowed=f"within [{low[j]:.4g}, {high[j]:.4g}]",
            element=joint_names[j],
        )
    return JointTrajectory(piece_times(0, samples, rate), arrays["q"], arrays["qd"], arrays["qdd"])


_UNIFORM = 1e-9
"""Relative spread of given time steps within which their rate is taken as the run's."""


@dataclass(frozen=True)
class JointColumns:
    """The joint columns a robot's motion fills, for matching given samples to them.

    Attributes:
        names: the motion's columns (a DH arm's six modules, a URDF robot's joints)
        given: the columns given samples must fill (the arm's modules; the joints no mimic)
        followers: mimic columns, column → (leader column, multiplier, offset): filled from
            their leader where the samples do not give them
    """

    names: tuple[str, ...]
    given: tuple[int, ...]
    followers: Mapping[int, tuple[int, float, float]] = field(default_factory=dict)


@dataclass(frozen=True)
class GivenSamples:
    """A motion given as samples (e.g. read from a trajectory file).

    Attributes:
        source: where they come from (named in errors, e.g. the file's path)
        time: sample times, T [s]
        q: joint values, T × m [rad or m]
        qd: joint velocities, T × m, or None (by a spline)
        qdd: joint accelerations, T × m, or None (by a spline)
        names: the joint of each column, or None (columns in order)
    """

    source: str
    time: Array
    q: Array
    qd: Array | None = None
    qdd: Array | None = None
    names: tuple[str, ...] | None = None


def fit_samples(
    given: GivenSamples,
    joints: JointColumns,
    *,
    rate: float | None = None,
    duration: float | None = None,
    fallback_rate: float = DEFAULT_RATE,
    smoothing: float = 0.0,
) -> tuple[JointTrajectory, float, float]:
    """A robot's joint motion from given samples: columns matched, mimic joints filled.

    Columns are matched by name when the samples name their joints, else taken in order
    (:func:`sample_columns`); columns not given are zero, except a mimic joint, which follows
    its leader (``multiplier·q_leader + offset``). The samples are put on the run's grid by
    :func:`trajectory_from_samples`.

    Args:
        given: the samples
        joints: the robot's joint columns
        rate: the run's rate [Hz]; None: the samples' own if their steps are uniform, else
            ``fallback_rate``
        duration: the run's length [s] (at most the samples' span); None: their span
        fallback_rate: the rate of samples of uneven steps when ``rate`` is None [Hz]
        smoothing: RMS [rad or m] of the noise the spline may smooth away

    Returns:
        ``(trajectory, duration, rate)``: the motion (T × the robot's columns) and the run's
        grid.

    Raises:
        InputFileError: samples that do not fit the robot (parameter ``given``).
        ParameterError: a duration longer than the samples' span.
    """
    time = np.asarray(given.time, dtype=float)
    columns = sample_columns(given.source, given.q.shape[1], given.names, joints)
    if rate is None:
        steps = np.diff(time)
        uniform = np.ptp(steps) <= _UNIFORM * np.mean(steps)
        rate = (time.size - 1) / float(time[-1] - time[0]) if uniform else fallback_rate
    try:
        fitted = trajectory_from_samples(
            time, given.q, given.qd, given.qdd, rate=rate, smoothing=smoothing
        )
    except ParameterError as exc:
        raise InputFileError(
            f"{given.source}: {exc}", parameter="given", element=given.source
        ) from None
    samples = fitted.q.shape[0]
    span = float(time[-1] - time[0])
    if duration is not None:
        wanted = sample_count(float(duration), rate, None)
        if wanted > samples:
            raise ParameterError(
                parameter="duration",
                value=duration,
                allowed=f"at most {span:g} s, the span of {given.source}",
            )
        samples = wanted
    full = [np.zeros((samples, len(joints.names))) for _ in range(3)]
    for target, source in zip(full, (fitted.q, fitted.qd, fitted.qdd), strict=True):
        target[:, columns] = source[:samples]
    for column, (leader, multiplier, offset) in joints.followers.items():
        if column not in columns:
            for target in full:
                target[:, column] = multiplier * target[:, leader]
            full[0][:, column] += offset
    trajectory = JointTrajectory(fitted.time[:samples], *full)
    return trajectory, span if duration is None else float(duration), float(rate)


def sample_columns(
    source: str, n_columns: int, names: tuple[str, ...] | None, joints: JointColumns
) -> list[int]:
    """The robot's column of each column of given samples.

    By name when the samples name their joints (every joint of ``joints.given`` named, no
    other name); else all the robot's columns in order, or those of ``joints.given`` in order.

    Raises:
        InputFileError: the columns do not fit the robot, in one line (parameter ``given``:
            the samples of :func:`fit_samples`).
    """
    joint_names = joints.names
    wanted = ", ".join(joint_names[j] for j in joints.given)
    if names is not None:
        unknown = [name for name in names if name not in joint_names]
        if unknown:
            allowed = f"the robot's joints ({', '.join(joint_names)})"
            raise InputFileError(
                f"{source}: joint {unknown[0]!r} is not the robot's; allowed: {allowed}",
                parameter="given",
                allowed=allowed,
                element=source,
            )
        columns = [joint_names.index(name) for name in names]
        missing = [joint_names[j] for j in joints.given if j not in columns]
        if missing:
            raise InputFileError(
                f"{source}: has no column for joint {missing[0]}; allowed: a column for each "
                f"of {wanted}",
                parameter="given",
                allowed=wanted,
                element=source,
            )
        return columns
    if n_columns == len(joint_names):
        return list(range(n_columns))
    if n_columns == len(joints.given):
        return list(joints.given)
    counts = sorted({len(joint_names), len(joints.given)})
    allowed = " or ".join(str(c) for c in counts) + f" joint columns ({wanted})"
    raise InputFileError(
        f"{source}: has {n_columns} joint columns; allowed: {allowed}",
        parameter="given",
        allowed=allowed,
        element=source,
    )
