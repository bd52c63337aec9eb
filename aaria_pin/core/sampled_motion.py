"""Joint motions from given samples: a user's trajectory on a run's time grid, checked.

- :func:`trajectory_from_samples`: a user's motion given as samples of q (and optionally qd,
  qdd): derivatives by a spline through (or, with ``smoothing``, near) the samples, resampled
  on a run's time grid when the given times are not already one.
- :func:`check_trajectory`: a trajectory checked against a run's time grid and joint limits.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import (
    MAX_SAMPLES,
    JointTrajectory,
    piece_times,
    sample_times,
)
from aaria_pin.errors import ParameterError

__all__ = ["check_trajectory", "trajectory_from_samples"]


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
    outside = (q_min < low - 1e-12) | (q_max > high + 1e-12)
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
