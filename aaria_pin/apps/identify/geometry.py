"""Identify an Aaria arm's kinematic model from its IMU signals and joint encoders.

:func:`identify_kinematics` takes a DH run's record or a recording (as
:class:`~aaria_pin.apps.identify.geometry_input.ArmSignals`: a recording's IMUs and joints on
the base IMU's stamps, its structure from the IMU names) and uses only what a real set-up has:
the sample times, the joint encoder columns ``q``, the IMU signals, which link each IMU is on
(``imu_mounts[i].parent``), and nothing of the DH table, the IMU mounting poses, the tool pose or
the base pose. It estimates

1. the structure: each module empty (its encoder does not move and no IMU sits on its link),
   revolute or prismatic (:func:`~aaria_pin.apps.identify.geometry_start.detect_kind`);
2. a start in closed form (joint axes from gyroscope differences, lengths by linear least
   squares; :func:`~aaria_pin.apps.identify.geometry_start.initial_parameters`);
3. the extended DH table (per module ``alpha, a`` and ``d`` or ``theta``, the tool length) and
   each link IMU's mounting pose, by nonlinear least squares
   (Levenberg–Marquardt) of predicted minus measured IMU signals over the run, on the exact
   model (:func:`~aaria_pin.apps.identify.geometry_model.predict_signals`, a whole-run
   forward pass of rates and specific forces), each signal weighted by 1 / its noise level
   (the record's noise parameters, else ADIS16485's). A fit that ends above the noise floor
   is a local minimum: other starts (each prismatic theta forced to each quarter turn, the
   closed-form start from more samples) are walked, the best few fitted, the smallest
   residual kept, stopping at the floor. On noisy records the base IMU's signals, inputs of
   the model, are taken as measured, its rates differentiated by the filter that errs least
   (:func:`~aaria_pin.apps.identify.geometry_signals.noisy_derivative`), and each IMU
   channel's bias is a B-spline of time projected off the fit
   (:mod:`~aaria_pin.apps.identify.geometry_bias`);
4. each parameter's standard deviation (the sandwich estimate of
   :func:`~aaria_pin.apps.identify.geometry_fit.sandwich_sigmas`), the residual RMS per
   IMU, the parameter combinations the data cannot determine (the Jacobian's null space, named
   in words: "d2 and d3 add up (only d2 + d3 is determined)"), and, when the record holds the
   truth, the errors: link types, the tool tip's position over the run from an independent
   forward kinematics (Pinocchio, :func:`~aaria_pin.core.kinematics.trajectory_signals`) of the
   estimated and the true table, and the joint axes' angles.

What the set-up defines rather than measures: the **base IMU's frame is the base frame** and the
**tool IMU's frame is the tool-tip frame** (as Aaria mounts them: ``imu_base`` at the base origin,
``imu_tool`` at the tool tip, both unrotated). A real arm has no other physical marker of either
frame, so these two mounts are not estimated (identity); the link IMUs' mounts are. The base
may move: its angular velocity and the specific force at its origin are the base IMU's signals,
its angular acceleration their spline derivative; the base pose is never used. Joint velocities
and accelerations are the derivatives of a quintic spline through the encoder values.

DH tables are not unique (the same arm has several): compare tool-tip trajectories and joint
axes, not table entries. A revolute module's ``theta`` and a prismatic module's rail length
``d`` do not act on the kinematics; the table gives 0 and the shortest rail the encoder's range
fits in. The base row (row 8) is unused by the kinematics (zeros); the tool row is
``[0, a7, 0, 0, 1]``.
"""

from __future__ import annotations

import time as _time
from collections.abc import Callable
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.apps.identify.geometry_bias import knot_spacing
from aaria_pin.apps.identify.geometry_fit import (
    WeightedFit,
    deficiencies,
    non_negative_lengths,
    sandwich_sigmas,
)
from aaria_pin.apps.identify.geometry_input import ArmSignals, measured_rates
from aaria_pin.apps.identify.geometry_model import ArmLayout, KinematicData, predict_signals
from aaria_pin.apps.identify.geometry_result import KinematicIdentification
from aaria_pin.apps.identify.geometry_signals import (
    clipped_samples,
    noisy_derivative,
    rounding_level,
    signal_weights,
)
from aaria_pin.apps.identify.geometry_start import (
    INIT_SAMPLES,
    other_starts,
    start_parameters,
    table_start,
)
from aaria_pin.apps.identify.geometry_structure import (
    arm_layout,
    estimated_mounts,
    joint_kinds,
    length_indices,
    table_lengths,
    table_of,
)
from aaria_pin.apps.identify.geometry_truth import truth_errors
from aaria_pin.apps.identify.geometry_warm import checked_start, closed_form_choice, start_kinds
from aaria_pin.core.arguments import checked
from aaria_pin.core.record import RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = ["identify_kinematics"]

_FIT_SAMPLES = 4000  # noisy fits gain from every sample (8.3 mm at 1000 samples, 1.2 mm at 6001)
_WALK_SAMPLES = 120
_MIN_SAMPLES = 20
_AT_FLOOR = 1.1  # a fit whose weighted RMS is within this factor of the noise floor is done
_EXACT_FLOOR = 1e-3  # the noise floor of a noise-free record (its fits end near 1e-8)
# ... stored in float32 (the default): its fits end at 5e-5 to 1.4e-3 (seeds 11-13, sine and
# Fourier motion, 30 s at 200 Hz), the rounding of the signals and of the joint accelerations
_ROUNDED_FLOOR = 1e-2
_REFITS = 3  # other starts fitted on every sample, after their walks
_FAILED = 10.0  # a fit whose weighted RMS ends above this many noise floors has failed
_POLISH = 20  # Levenberg–Marquardt iterations from a point moved along a null direction
_CORRELATION = 3.0  # [s] residuals correlated over up to this (the base's derivative filter)
_PLAUSIBLE_LENGTH = 5.0  # [m] a longer |a| or |d| is a degenerate table (lengths cancelling)


def fit_failure(end_rms: float, floor: float, table: Array, layout: ArmLayout) -> str | None:
    """Why a fit is not a result, in one line, or None.

    A fit fails when its weighted residual RMS ends above :data:`_FAILED` noise floors (the
    noise model's, or a noise-free record's :data:`_EXACT_FLOOR`, :data:`_ROUNDED_FLOOR` if
    stored in float32; the fits that ended 5-15 mm off the tool
    tip before the time axis was rebuilt ended at 7), or when a length is beyond
    :data:`_PLAUSIBLE_LENGTH` (random arms' lengths are at most 0.9 m; one Fourier-motion fit
    returned ``a2 = 25.3 m`` with ``d1 = 24.8 m``, two lengths cancelling).

    Args:
        end_rms: the fit's weighted residual RMS (1 at the noise)
        floor: the noise floor in those units
        table: the estimated 8 × 5 table
        layout: the arm's modules
    """
    if not end_rms <= _FAILED * floor:
        return (
            f"fit ended above the noise floor: weighted residual RMS {end_rms:.3g}; "
            f"allowed: at most {_FAILED * floor:.3g} ({_FAILED:g} noise floors)"
        )
    lengths = np.abs(table[table_lengths(layout)])
    if not np.all(lengths <= _PLAUSIBLE_LENGTH):
        return (
            f"degenerate table: a length of {float(np.max(lengths)):.3g} m; allowed: at most "
            f"{_PLAUSIBLE_LENGTH:g} m"
        )
    return None


def _rms(values: Array) -> float:
    return float(np.sqrt(np.mean(values**2)))


def _measured_data(
    signals: ArmSignals, layout: ArmLayout, base: int, start: Array | None
) -> tuple[list[ArmLayout], KinematicData, Array, Array, Array, tuple[int, ...]]:
    """The layouts with their joint kinds, the model's inputs, the signals, weights and times.

    The first layout has the detected kinds; a second one, where a start table's kinds differ
    from the detection's on unsure modules (the last item: :func:`start_kinds`), the table's.
    """
    time = signals.time
    columns = [m - 1 for m in layout.modules]
    q = np.asarray(signals.q, dtype=float)[:, columns]
    if signals.joint_rates is None:
        qd, qdd = measured_rates(time, q, 2)
    else:
        qd, qdd = (np.asarray(rate, dtype=float)[:, columns] for rate in signals.joint_rates)
    detected = joint_kinds(signals, layout, base, qd)
    kinds, decided = tuple(kind for kind, _ in detected), tuple[int, ...]()
    layouts = [ArmLayout(layout.modules, kinds, layout.link_imus, layout.tool_imu)]
    if start is not None:
        kinds, decided = start_kinds(layout.modules, detected, start)
    if decided:
        layouts.append(ArmLayout(layout.modules, kinds, layout.link_imus, layout.tool_imu))
    rate = (time.size - 1) / (time[-1] - time[0])
    weights = signal_weights(rate, signals.noise_parameters)
    omega_base = np.asarray(signals.imu[:, base, :3], dtype=float)
    force_base = np.asarray(signals.imu[:, base, 3:], dtype=float)
    if signals.noisy:
        # the base IMU's signals are inputs of the model, taken as measured (a smoothing
        # bends the motion: a bias the whole run repeats); its angular velocity differentiated
        omega_dot = noisy_derivative(time, omega_base, 1.0 / weights[0])
        # the base IMU's noise, an input, enters every prediction: as much again as the
        # predicted IMU's own (the same part), so each weight is 1 / (√2 its noise level)
        weights = weights / np.sqrt(2.0)
    else:
        (omega_dot,) = measured_rates(time, omega_base, 1)
    data = KinematicData(omega_base, omega_dot, force_base, q, qd, qdd)
    measured = np.asarray(signals.imu[:, list(layout.imus)], dtype=float)
    return layouts, data, measured, weights, time, decided


class _Fit(NamedTuple):
    """A fit from one start: its solution, residuals, Jacobian, iterations and start."""

    x: Array
    fun: Array
    jac: Array
    iterations: int
    walk: int
    walk_rms: float
    start: Array
    label: str

    @property
    def rms(self) -> float:
        return _rms(self.fun)


@checked
def identify_kinematics(
    record: RunRecord | ArmSignals,
    *,
    max_fit_samples: int = _FIT_SAMPLES,
    max_iterations: int = 100,
    with_truth: bool = True,
    progress: Callable[[str], None] | None = None,
    start: ArrayLike | None = None,
) -> KinematicIdentification:
    """Identify an Aaria arm's structure, DH table and IMU mounts from a DH run's signals.

    Uses only ``time``, ``q`` (encoders), ``imu`` and each IMU's ``parent`` (module docstring:
    what is measured, what is defined, the steps), as :class:`ArmSignals` holds them.

    Args:
        record: a DH run's record (``read_run``, ``DatasetReader(...).record(k)``,
            ``simulate_run``): 6 joint columns by module, a base, a tool and link IMUs; or
            the signals of one (:meth:`ArmSignals.of_record`) or of a recording
            (:meth:`ArmSignals.of_recorded`)
        max_fit_samples: at most this many samples, evenly spread over the run, enter the
            nonlinear fit (residual RMS and truth errors use every sample)
        max_iterations: most Levenberg–Marquardt iterations of the nonlinear fit
        with_truth: compare with the truth the record holds (``senSenDH``), if any (a
            recording holds none)
        progress: called with a line per stage and per start (``start 1 (closed form):
            weighted RMS 1.02 after 5 iterations, 3.1 s``), for a log
        start: a start table, 8 × 5 (``senSenDH``'s layout: a prediction, an earlier
            estimate): its link types where the detection is unsure and their closed form
            fits better, its angles and lengths as the first start (its fit's prior anchored
            at the table), the usual starts after it unless its fit ends at the
            noise floor (:mod:`~aaria_pin.apps.identify.geometry_warm`: what and why)

    Returns:
        The identification.

    Raises:
        ParameterError: not a DH run with base and tool IMUs, a moving module without an IMU
            on its link, no moving module, fewer than 20 samples, or a start table that is
            not 8 × 5 finite numbers with link types 0, 1 or 2.
    """
    started = _time.perf_counter()
    table_given = None if start is None else checked_start(start)
    signals = record if isinstance(record, ArmSignals) else ArmSignals.of_record(record)
    if signals.n_samples < _MIN_SAMPLES:
        raise ParameterError(
            f"record has {signals.n_samples} samples; allowed: at least {_MIN_SAMPLES}",
            parameter="record",
            value=signals.n_samples,
            allowed=f"at least {_MIN_SAMPLES} samples",
        )
    layout, base = arm_layout(signals)
    layouts, data, measured, weights, time, unsure = _measured_data(
        signals, layout, base, table_given
    )
    layout, n_samples, decided = layouts[0], data.q.shape[0], tuple[int, ...]()

    def say(line: str) -> None:
        if progress is not None:
            progress(f"{line}, {_time.perf_counter() - started:.1f} s")

    # samples with a clipped IMU channel are left out of the fit (geometry_signals.clipped_samples)
    clipped = clipped_samples(np.asarray(signals.imu), signals.noise_parameters)
    kept = np.logical_not(clipped)
    usable = np.flatnonzero(kept) if np.sum(kept) >= _MIN_SAMPLES else np.arange(n_samples)

    def spread(count: int) -> Array:
        picks = np.linspace(0, usable.size - 1, min(count, usable.size)).astype(int)
        return usable[np.unique(picks)]

    start = spread(INIT_SAMPLES)
    part, part_measured = data.subsample(start), measured[start]
    x0 = None
    if unsure:
        # the table's link types differ from an unsure detection's: the closed-form start
        # under both, the smaller residual kept (geometry_warm: why)
        chosen, x0 = closed_form_choice(layouts, part, part_measured, weights)
        layout, decided = layouts[chosen], unsure if chosen else ()
        which = "start table" if chosen else "detection"
        say(f"link types of unsure modules {', '.join(map(str, unsure))}: the {which}'s")
    modules = zip(layout.modules, layout.kinds, strict=True)
    say(
        f"structure: {', '.join(f'{m} {k}' for m, k in modules)}; "
        f"{len(layout.imus)} IMUs fitted on {min(max_fit_samples, n_samples)} samples"
    )
    lengths = length_indices(layout)
    spacings = None
    if signals.noisy:
        rate = (time.size - 1) / (time[-1] - time[0])
        spacings = knot_spacing(signals.noise_parameters, rate)
    problem = WeightedFit(layout, data, measured, weights, lengths, time, spacings)
    # The walk along equivalent tables takes many short steps and does not need many
    # samples: it runs on the start's few, then the fit ends on more.
    walk_index, fit_index = spread(_WALK_SAMPLES), spread(max_fit_samples)
    # the weights are 1 / the noise level: a fit at the noise floor has a weighted RMS near 1
    exact = _EXACT_FLOOR if rounding_level(measured) is None else _ROUNDED_FLOOR
    floor = _AT_FLOOR * (1.0 if signals.noisy else exact)

    def fit_from(x_start: Array, anchor: Array, label: str) -> _Fit:
        x, fun, _, walk = problem.fit(x_start, anchor, walk_index, max_iterations, biases=False)
        walk_rms = _rms(fun)
        x, fun, jac, iterations = problem.fit(x, anchor, fit_index, max_iterations)
        say(f"start {len(fits) + 1} ({label}): weighted RMS {_rms(fun):.3g} after {iterations} "
            "iterations")  # fmt: skip
        return _Fit(x, fun, jac, iterations, walk, walk_rms, x_start, label)

    fits: list[_Fit] = []
    if table_given is not None:
        x_table, _ = table_start(layout, part, part_measured, weights, table_given)
        fits.append(fit_from(x_table, x_table, "start table"))
    if not fits or fits[0].rms > floor:
        if x0 is None:
            x0 = start_parameters(layout, part, part_measured, weights, lengths)
        fits.append(fit_from(x0, x0, "closed form"))
    best = min(fits, key=lambda f: f.rms)
    if best.rms > floor:
        # a local minimum: other starts (the quarter turns of prismatic thetas the gyroscopes
        # cannot give, a start from more samples), each walked on few samples; the best few
        # walks fitted on all, the smallest residual kept, stopping at the noise floor
        walked: list[tuple[float, int, Array, Array, int]] = []
        say(f"above the noise floor ({floor:.3g}): walking other starts")
        for other in other_starts(layout, data, measured, weights, spread, fits[-1].start):
            z, z_fun, _, z_walk = problem.fit(other, other, walk_index, max_iterations, False)
            walked.append((_rms(z_fun), len(walked), z, other, z_walk))
        for z_rms, _, z, other, z_walk in sorted(walked, key=lambda item: item[:2])[:_REFITS]:
            z, z_fun, z_jac, z_iterations = problem.fit(z, other, fit_index, max_iterations)
            fits.append(_Fit(z, z_fun, z_jac, z_iterations, z_walk, z_rms, other, "other"))
            say(
                f"start {len(fits)} (of {len(walked)} walked): weighted RMS "
                f"{fits[-1].rms:.3g} after {z_iterations} iterations"
            )
            best = min(best, fits[-1], key=lambda f: f.rms)
            if best.rms <= floor:
                break
    starts = len(fits)
    x, fun, jac, iterations, walk, start_rms = best[:6]
    names = layout.parameter_names(signals.imu_names)
    found, sigmas, basis, covariance = deficiencies(jac, names, layout.n_dh)
    moved = non_negative_lengths(x, basis, lengths)
    table = table_of(layout, moved, data.q)
    if not np.all(np.abs(table[table_lengths(layout)]) <= _PLAUSIBLE_LENGTH):
        moved = problem.shorten(moved, basis, names, walk_index)
    # a null direction is a symmetry to first order only: keep the move if the signals stay
    # as well fitted, after a short polish from the moved point if they do not at once
    if not np.array_equal(moved, x):
        fitted = problem.cost(x, fit_index)
        allowed = 1.01 * fitted + 1e-9 * fun.size
        polished = None
        if problem.cost(moved, fit_index) > allowed:
            polished = problem.fit(moved, moved, fit_index, _POLISH)
            moved = polished[0]
            ratio = problem.cost(moved, fit_index) / max(fitted, 1e-300)
            say(f"lengths moved, polished in {polished[3]} iterations: cost {ratio:.3g} times")
        if problem.cost(moved, fit_index) <= allowed:
            x = moved
            if polished is not None:
                fun, jac = polished[1], polished[2]
                found, sigmas, basis, covariance = deficiencies(jac, names, layout.n_dh)
    fit_rate = (fit_index.size - 1) / max(float(time[fit_index[-1]] - time[fit_index[0]]), 1e-300)
    window = round(_CORRELATION * fit_rate)
    robust = sandwich_sigmas(covariance, jac, fun, 6 * len(layout.imus), window)
    sigmas = np.where(np.isfinite(sigmas), robust, np.nan)
    predicted, _ = predict_signals(x, layout, data)
    error = predicted - measured
    residual_rms = {
        signals.imu_names[imu]: {
            "gyro_rad_s": float(np.sqrt(np.mean(error[:, slot, :3] ** 2))),
            "accel_m_s2": float(np.sqrt(np.mean(error[:, slot, 3:] ** 2))),
        }
        for slot, imu in enumerate(layout.imus)
    }
    table = table_of(layout, x, data.q)
    end_rms = _rms(fun)
    fit_summary = {
        "samples": int(fit_index.size),
        "iterations": iterations,
        "walk_iterations": walk,
        "starts": starts,
        "start": best.label,
        "closed_form": any(done.label == "closed form" for done in fits),
        "link_types_from_start": list(decided),
        "walk_rms_weighted": start_rms,
        "end_rms_weighted": end_rms,
        "seconds": _time.perf_counter() - started,
        "valid_table": bool(np.all(table[table_lengths(layout)] >= 0.0)),
        "defined": "base IMU frame = base frame; tool IMU frame = tool-tip frame",
        "failure": fit_failure(end_rms, floor / _AT_FLOOR, table, layout),
    }
    return KinematicIdentification(
        table,
        tuple(int(t) for t in table[:6, 4]),
        estimated_mounts(signals, layout, x),
        names,
        x,
        sigmas,
        residual_rms,
        found,
        (
            truth_errors(signals.truth, table, (layout, x, sigmas))
            if with_truth and signals.truth is not None
            else None
        ),
        fit_summary,
    )
