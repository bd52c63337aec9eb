"""Two IMUs on one rigid body: their relative pose and time offset from their signals alone.

:func:`identify_rigid` estimates, for IMUs A and B fixed to one body and no encoder, B's
rotation ``R_AB`` (``v_A = R_AB·v_B``), B's origin in A's frame ``r`` [m], B's time offset ``δ``
[s] (B's sample stamped ``t`` is A's instant ``t + δ``), and the biases, with σ:

1. starts: ``δ`` by cross-correlating ``|ω|`` of the two gyroscopes (a rotation does not change
   it; ``|f|`` when the body does not turn), ``R`` by Kabsch/Wahba on the gyroscope vectors at
   matched instants (means removed: a bias is a constant), ``r`` and B's accelerometer bias by
   linear least squares on
   ``R·f_B - f_A = (α× + ω×ω×)·r + c`` with ω and α from a B-spline fit of A's gyroscope;
2. one nonlinear least squares over every sample of both IMUs
   (:func:`~aaria_pin.apps.identify.rigid_fit.gauss_newton`): the body's angular velocity and
   A's specific force as B-splines, with ``R``, ``r``, ``δ`` and the biases; each block's noise
   σ re-estimated from its residuals and the fit repeated, the covariance then giving σ;
3. what the data do not determine, in words: a direction of ``r``, of the rotation or the
   offset whose σ exceeds :data:`UNDETERMINED` (the position along ω when the body turned about
   one axis only: ``α×r`` and ``ω×(ω×r)`` vanish for ``r`` along it), and a fit that ended
   above the noise floor (:attr:`RigidPairFit.failure`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from aaria_pin.apps.identify.geometry_start import kabsch
from aaria_pin.apps.identify.rigid_fit import (
    FitLayout,
    FitState,
    PairData,
    gauss_newton,
    lever_matrices,
)
from aaria_pin.apps.identify.rigid_result import RigidPairFit
from aaria_pin.apps.identify.rigid_spline import coefficient_count, fit_spline, spline_basis
from aaria_pin.core.arguments import checked
from aaria_pin.core.recording import RecordedRun
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = [
    "UNDETERMINED",
    "UNDETERMINED_RATIO",
    "RigidPairFit",
    "Signals",
    "body_turns",
    "default_knot_interval",
    "identify_rigid",
    "identify_rigid_body",
    "imu_signals",
    "rotation_between",
]

UNDETERMINED = {"position": 0.01, "rotation": np.radians(1.0), "time_offset": 0.01}
"""σ above which a direction is reported as not determined [m, rad, s]."""

UNDETERMINED_RATIO = 50.0
"""A direction of position or rotation whose σ is this many times its block's best-determined
direction's is reported as not determined too (the data hold only noise about it: a position
along the one axis the body turned about is then pulled about by the gyroscopes' noise, far
beyond its σ)."""

TURNING = 10.0
"""``|ω|``'s spread over its noise (both of 0.1 s averages) above which the
body turns: the time offset's start correlates ``|ω|`` and the position is a result."""

VIBRATING_KNOTS = 0.05
"""[s] The default knot spacing of a vibrating body's splines (:func:`default_knot_interval`)."""

ABOVE_FLOOR = 5.0
"""B's residual RMS over A's (same sensor) above which the fit did not reach the noise floor."""

KNOT_INTERVAL = 0.01
"""[s] The default knot spacing of the body's splines (docs/guide/identify-rigid.md's figures)."""

KNOT_SAMPLES = 2.0
"""The fewest of A's sampling periods in a knot interval, by default (100 Hz: 0.02 s)."""

MODEL_FLOOR = 1e-4
"""B's residual RMS over its signal's RMS (same sensor) below which the fit is at the floor."""

STILL = (
    "position: the body did not turn (|w| within the gyroscope's noise), so the lever arm's "
    "accelerations are noise and the position is not a result"
)
"""The sentence of a recording without rotation."""

MIN_SAMPLES = 50
"""The fewest samples of each IMU inside the other's span."""


Signals = tuple[Array, Array]


def imu_signals(source: RecordedRun | Mapping[str, Signals], name: str) -> Signals:
    """An IMU's (time [s], (N, 6) signals) from a recording or a mapping, checked.

    Args:
        source: a recording (its ``imu`` streams) or ``{name: (time, signals)}``
        name: the IMU

    Returns:
        Its stamps (N,) [s] and ``[wx wy wz fx fy fz]`` rows (N, 6) [rad/s, m/s²], float64.

    Raises:
        ParameterError: a name not in the source, a stream that is not an IMU's, arrays of the
            wrong shape, values not finite or stamps not increasing.
    """
    if isinstance(source, RecordedRun):
        stream = source.stream(name)
        if stream.kind != "imu":
            raise ParameterError(
                f"stream {name} is a {stream.kind} stream; allowed: an IMU stream",
                parameter="imu",
                value=name,
            )
        return stream.time, stream.values
    if name not in source:
        raise ParameterError(parameter="imu", value=name, allowed=", ".join(source) or "none")
    time = np.asarray(source[name][0], dtype=np.float64)
    values = np.asarray(source[name][1], dtype=np.float64)
    if time.ndim != 1 or values.shape != (time.size, 6):
        raise ParameterError(
            f"IMU {name} has {time.shape} stamps and {values.shape} values; allowed: (N,) "
            "and (N, 6)",
            parameter="imu",
            value=name,
        )
    if not (np.isfinite(values).all() and np.isfinite(time).all() and (np.diff(time) > 0).all()):
        raise ParameterError(
            f"IMU {name} has values not finite or stamps not increasing; allowed: finite "
            "values at increasing stamps",
            parameter="imu",
            value=name,
        )
    return time, values


def body_turns(signals: Signals, average: float = 0.1) -> bool:
    """Whether the body turns: its gyroscope's averaged ``|ω|`` varies above that average's noise.

    "Above" is :data:`TURNING` times.

    The noise is the sample-to-sample one, which counts vibration too: on a quadrotor (Xsens
    DOTs at 120 Hz, ansfl/Quadrotor-Dead-Reckoning-with-Multiple-Inertial-Sensors, 56 s and
    190 s flights) the raw ``|ω|``'s spread was 4.3-4.6 times it while the drone turned at
    0.36 rad/s RMS, and the body was taken for still (its fits that did not converge then
    passed as results); averaged over 0.1 s the vibration (above 5 Hz) falls away and the
    turns stay: 13.7-14.5 times. (Averaged per axis instead, 7-9 times: the vibration's
    lower part stays in both.)

    Args:
        signals: the IMU's stamps [s] and ``(N, 6)`` signals, the gyroscope's first [rad/s]
        average: the span of the averages [s] (0: the samples themselves)
    """
    time, values = signals
    speed = np.linalg.norm(values[:, :3], axis=1)
    noise = np.std(np.diff(speed)) / np.sqrt(2.0)
    period = float(np.median(np.diff(time))) if time.size > 1 else 1.0
    width = int(np.clip(round(average / period), 1, max(speed.size // 4, 1)))
    averaged = np.convolve(speed, np.full(width, 1.0 / width), mode="valid")
    return bool(np.std(averaged) > TURNING * noise / np.sqrt(width))


def default_knot_interval(signals: Signals) -> float:
    """The knot spacing of the body's splines from A's signals [s].

    :data:`KNOT_INTERVAL`, and at least :data:`KNOT_SAMPLES` of A's sampling periods; a body
    whose turns stand out of its gyroscope's variation only on 0.1 s averages vibrates
    (:func:`body_turns`), and its knots are :data:`VIBRATING_KNOTS` apart: splines that follow
    the vibration take its angular accelerations into the lever arm's. On the quadrotor of
    :func:`body_turns` (two Xsens DOTs about 4 cm apart, 56 s) the pair came out 416 mm apart
    with σ 7 mm at 0.017 s, (33, 95, -5) mm at 0.05 s (its 95 along the direction reported
    not determined), and its time offset 43 ms off at 0.2 s.

    Args:
        signals: A's stamps [s] and ``(N, 6)`` signals
    """
    interval = max(KNOT_INTERVAL, KNOT_SAMPLES * float(np.median(np.diff(signals[0]))))
    if body_turns(signals) and not body_turns(signals, 0.0):
        interval = max(interval, VIBRATING_KNOTS)
    return interval


def _correlation_offset(a: Signals, b: Signals, max_offset: float) -> float:
    """B's time offset by cross-correlating the two IMUs' ``|ω|`` (``|f|`` if not turning) [s].

    Both magnitudes are the same on one rigid body whatever the IMUs' rotation (``|f|`` up to
    the lever arm's accelerations, which a body that does not turn does not have).
    """
    rate = 2.0 * max(1.0 / np.median(np.diff(a[0])), 1.0 / np.median(np.diff(b[0])))
    first, last = max(a[0][0], b[0][0]), min(a[0][-1], b[0][-1])
    grid = np.arange(first, last, 1.0 / rate)
    if grid.size < MIN_SAMPLES:
        return 0.0  # no overlap to correlate: the caller finds too few shared samples
    columns = slice(0, 3) if body_turns(a) else slice(3, 6)
    speeds = []
    for time, values in (a, b):
        speed = np.interp(grid, time, np.linalg.norm(values[:, columns], axis=1))
        speeds.append(speed - speed.mean())
    n = grid.size
    size = 1 << int(np.ceil(np.log2(2 * n)))
    spectrum = np.fft.rfft(speeds[0], size) * np.conj(np.fft.rfft(speeds[1], size))
    correlation = np.fft.irfft(spectrum, size)
    lags = np.arange(-(n - 1), n)
    values = np.concatenate([correlation[-(n - 1) :], correlation[:n]])
    keep = np.abs(lags) <= max_offset * rate
    lags, values = lags[keep], values[keep]
    k = int(np.argmax(values))
    shift = 0.0
    if 0 < k < values.size - 1:
        left, mid, right = values[k - 1 : k + 2]
        shift = 0.5 * (left - right) / (left - 2.0 * mid + right)
    return float((lags[k] + shift) / rate)


def rotation_between(target: Array, source: Array) -> Array:
    """The rotation R minimising Σ|target - R·source|² over mean-free rows (a bias is a mean).

    Args:
        target: (n, 3) vectors, e.g. A's angular velocities [rad/s]
        source: (n, 3) the same vectors in the other frame

    Returns:
        R (3, 3), ``target ≈ R·source`` (Kabsch, :func:`~aaria_pin.apps.identify.
        geometry_start.kabsch`).
    """
    return kabsch(target - target.mean(0), source - source.mean(0)).T


def _start(data: PairData, layout: FitLayout, offset: float) -> tuple[FitState, Array]:
    """The starting point and the blocks' noise σ from the starts' residuals."""
    basis = spline_basis(data.time_a, layout.start, layout.interval, layout.count, 3)
    fitted = fit_spline(data.time_a, data.signals_a, layout.start, layout.interval, layout.count)
    omega, force = fitted[:, :3], fitted[:, 3:]
    tau = data.time_b + offset
    n0, n1 = (spline_basis(tau, layout.start, layout.interval, layout.count, 3, d) for d in (0, 1))
    w, w1, s = n0 @ omega, n1 @ omega, n0 @ force
    rotation = rotation_between(w, data.signals_b[:, :3])
    gyro_b = data.signals_b[:, :3] - w @ rotation
    lever = lever_matrices(w, w1)
    left = np.concatenate([lever, np.broadcast_to(np.eye(3), lever.shape)], axis=2)
    right = data.signals_b[:, 3:] @ rotation.T - s
    solution = np.linalg.lstsq(left.reshape(-1, 6), right.ravel(), rcond=None)[0]
    position, bias_in_a = solution[:3], solution[3:]
    accel_b = right - np.einsum("nij,j->ni", lever, position) - bias_in_a
    sigma = np.array(
        [
            np.std(data.signals_a[:, :3] - basis @ omega),
            np.std(data.signals_a[:, 3:] - basis @ force),
            np.std(gyro_b - gyro_b.mean(0)),
            np.std(accel_b),
        ]
    )
    bias = np.zeros((layout.bias_count, 3))
    state = FitState(
        omega,
        force,
        rotation,
        position,
        offset,
        bias,
        bias + gyro_b.mean(0),
        bias + rotation.T @ bias_in_a,
    )
    return state, np.maximum(sigma, 1e-9)


def _undetermined(covariance: Array) -> tuple[str, ...]:
    """Sentences for the directions of position, rotation and offset not determined.

    Above :data:`UNDETERMINED`, or :data:`UNDETERMINED_RATIO` times the block's best.
    """
    found = []
    for name, block, unit, scale in (
        ("position", slice(3, 6), "mm", 1e3),
        ("rotation", slice(0, 3), "deg", np.degrees(1.0)),
    ):
        values, vectors = np.linalg.eigh(covariance[block, block])
        sigmas = np.sqrt(np.maximum(values, 0.0))
        limit = min(UNDETERMINED[name], UNDETERMINED_RATIO * float(sigmas[0]))
        for sigma, vector in zip(sigmas, vectors.T, strict=True):
            if sigma > limit:
                direction = np.round(vector * np.sign(vector[np.argmax(abs(vector))]), 2) + 0.0
                axis = " ".join(f"{x:+.2f}" for x in direction)
                why = (
                    " (the lever arm's accelerations do not change along it: the body turned "
                    "about that axis only, or not at all)"
                    if name == "position"
                    else ""
                )
                found.append(
                    f"{name} along [{axis}] in A's axes, sigma {sigma * scale:.3g} {unit}{why}"
                )
    sigma = float(np.sqrt(max(covariance[6, 6], 0.0)))
    if sigma > UNDETERMINED["time_offset"]:
        found.append(f"time offset, sigma {sigma * 1e3:.3g} ms (too little angular acceleration)")
    return tuple(found)


@checked
def identify_rigid(
    source: RecordedRun | Mapping[str, Signals],
    imu_a: str,
    imu_b: str,
    knot_interval: float | None = None,
    bias_interval: float | None = None,
    max_offset: float = 1.0,
) -> RigidPairFit:
    """B's pose and time offset relative to A, two IMUs on one rigid body, from signals alone.

    Args:
        source: a recording (its ``imu`` streams) or ``{name: (time [s], (N, 6) signals)}``
        imu_a: the reference IMU
        imu_b: the IMU located
        knot_interval: the knot spacing of the body's angular velocity and specific force [s]
            (None: :func:`default_knot_interval`; with fewer than :data:`KNOT_SAMPLES` of A's
            sampling periods A's samples alone set the splines and leave no residual)
        bias_interval: the knot spacing of the biases [s] (None: constant over the run)
        max_offset: the largest time offset searched for [s]

    Returns:
        The fit; a fit that did not converge, or ended above the noise floor, has its
        ``failure`` sentence (its numbers are not a result).

    Raises:
        ParameterError: an IMU not in the source, A or B with fewer than
            :data:`MIN_SAMPLES` samples inside the other's span, or an interval or offset out
            of range.
    """
    bias_interval = np.inf if bias_interval is None else bias_interval
    for name, value, allowed in (
        ("knot_interval", 1.0 if knot_interval is None else knot_interval, "a finite number > 0 s"),
        ("bias_interval", bias_interval, "a number > 0 s (None: constant)"),
        ("max_offset", max_offset, "a finite number >= 0 s"),
    ):
        low_ok = value >= 0.0 if name == "max_offset" else value > 0.0
        if not (low_ok and (name == "bias_interval" or np.isfinite(value))):
            raise ParameterError(parameter=name, value=value, allowed=allowed)
    a, b = imu_signals(source, imu_a), imu_signals(source, imu_b)
    if knot_interval is None:
        knot_interval = default_knot_interval(a)
    offset = _correlation_offset(a, b, max_offset)
    margin = max(0.05, 4.0 * knot_interval)
    inside = (b[0] + offset > a[0][0] + margin) & (b[0] + offset < a[0][-1] - margin)
    if inside.sum() < MIN_SAMPLES or a[0].size < MIN_SAMPLES:
        raise ParameterError(
            f"IMUs {imu_a} and {imu_b} share {int(inside.sum())} samples away from the "
            f"recording's ends ({margin:g} s each); allowed: at least {MIN_SAMPLES} (a longer "
            "recording)",
            parameter="imu",
            value=imu_b,
        )
    data = PairData(a[0], a[1], b[0][inside], b[1][inside])
    span = float(a[0][-1] - a[0][0])
    bias_interval = min(bias_interval, span * 2.0)
    layout = FitLayout(
        float(a[0][0]),
        knot_interval,
        coefficient_count(span, knot_interval, 3),
        bias_interval,
        coefficient_count(span, bias_interval, 1),
    )
    state, sigma = _start(data, layout, offset)
    outcome = gauss_newton(data, layout, state, sigma)
    sizes = np.array([a[0].size, a[0].size, data.time_b.size, data.time_b.size])
    unknowns = 6 * layout.count + 7 + 9 * layout.bias_count
    dof = 6 * sizes.sum() / (6 * sizes.sum() - unknowns)
    for _ in range(2):
        blocks = np.split(outcome.residuals, np.cumsum(3 * sizes)[:-1])
        sigma = sigma * np.sqrt([np.mean(e**2) * dof for e in blocks])
        outcome = gauss_newton(data, layout, outcome.state, sigma)
    turn = np.eye(7)
    turn[:3, :3] = outcome.state.rotation  # the step R·exp(Δφ) is about B's axes: to A's
    covariance = turn @ outcome.covariance[:7, :7] @ turn.T
    spread = np.sqrt(np.maximum(np.diag(covariance), 0.0))
    fitted = outcome.state
    blocks = np.split(outcome.residuals, np.cumsum(3 * sizes)[:-1])
    noise = sigma * np.sqrt([np.mean(e**2) for e in blocks])
    still = () if body_turns(a) else (STILL,)
    return RigidPairFit(
        imu_a,
        imu_b,
        fitted.rotation,
        spread[:3],
        fitted.position,
        spread[3:6],
        fitted.offset,
        float(spread[6]),
        fitted.gyro_bias_a.mean(0),
        fitted.gyro_bias_b.mean(0),
        fitted.accel_bias_b.mean(0),
        noise,
        (int(a[0].size), int(data.time_b.size)),
        outcome.iterations,
        outcome.converged,
        _undetermined(covariance) + still,
        covariance,
        _failure(
            noise,
            imu_a,
            imu_b,
            outcome.converged or bool(still),  # still: its position wanders, said already
            np.sqrt(np.mean(np.square(b[1]).reshape(-1, 2, 3), (0, 2))),
        ),
        knot_interval,
    )


def _failure(noise: Array, imu_a: str, imu_b: str, converged: bool, level: Array) -> str:
    """The sentence of a fit above the noise floor (B's residual :data:`ABOVE_FLOOR`× A's).

    A's residual is no floor when A's samples alone set the body's splines (noise-free or
    stored signals: ~1e-16): B's residual is then what the splines do not follow between A's
    samples and the storage's rounding, and counts as at the floor below :data:`MODEL_FLOOR`
    of B's signal (a pair not on one body leaves residuals of the order of the signal).
    """
    if not converged:
        return (
            f"the fit of {imu_b} on {imu_a} did not converge (a local minimum, or two IMUs not "
            "on one rigid body)"
        )
    for k, sensor, unit in ((0, "gyroscope", "rad/s"), (1, "accelerometer", "m/s^2")):
        ratio = noise[2 + k] / max(noise[k], 1e-300)
        if ratio > ABOVE_FLOOR and noise[2 + k] > MODEL_FLOOR * level[k]:
            return (
                f"{imu_b}'s {sensor} residual is {noise[2 + k]:.3g} {unit}, {ratio:.0f}x "
                f"{imu_a}'s: above the noise floor (a local minimum, two IMUs not on one rigid "
                "body, or parts of very different noise)"
            )
    return ""


def identify_rigid_body(
    source: RecordedRun | Mapping[str, Signals],
    imus: Sequence[str] | None = None,
    knot_interval: float | None = None,
    bias_interval: float | None = None,
) -> tuple[RigidPairFit, ...]:
    """Every IMU of one rigid body located relative to the first: one pair fit each.

    Args:
        source: a recording or ``{name: (time [s], (N, 6) signals)}``
        imus: the IMUs, the reference first (None: every IMU of the source, in order)
        knot_interval: the knot spacing of the body's signals [s] (None: as :func:`identify_rigid`)
        bias_interval: the knot spacing of the biases [s] (None: constant over the run)

    Returns:
        The fits of IMU 2, 3, … relative to IMU 1.

    Raises:
        ParameterError: fewer than two IMUs, or a fit's own errors.
    """
    if imus is None:
        names = (
            [s.name for s in source.of_kind("imu")]
            if isinstance(source, RecordedRun)
            else list(source)
        )
    else:
        names = list(imus)
    if len(names) < 2:
        raise ParameterError(
            parameter="imus", value=", ".join(names) or "none", allowed="two or more IMUs"
        )
    return tuple(
        identify_rigid(source, names[0], other, knot_interval, bias_interval) for other in names[1:]
    )
