"""Compiled (numba) kernel of the closed-loop drives: a digital joint controller in the loop.

The controller ticks once per integration sub-step (``h``): at each tick it reads its sensors,
computes a torque and holds it until the next tick (zero-order hold, as a digital drive does);
between ticks the plant is integrated as the torque drive integrates it
(:func:`aaria_pin.core._forward_kernel.step`, the base prescribed and linear between samples).
At a tick:

- the reference: cubic Hermite between the two samples around the tick, from the values and
  velocities (``q_r``) and from the velocities and accelerations (``qd_r``); ``qdd_r`` linear.
  At a sample it is the sample itself;
- the encoders (on): ``q_m = o + Δ·round((q + n)/Δ)`` (:func:`~aaria_pin.core.encoder.
  encoder_reading`), the velocity their backward difference over the tick, low-passed by a
  first-order filter ``v_f += α·(v_raw - v_f)``; off: the true state;
- the law: ``pd``: ``τ_c = Kp·(q_r - q_m) + Kd·(qd_r - v_m)``; ``computed-torque``:
  ``τ_c = (M(q_m) + diag(armature))·(qdd_r + Kp·e + Kd·ė) + b(q_m, v_m) + friction(qd_r)``
  (the controller's model is the nominal one, at the measured state; friction fed forward at
  the reference's velocity, which does not chatter as the measured one would);
- the joint-torque loop (a torque sensor on, feedback ``k > 0``): the error between the
  link-side torque the command asks for (the command itself for ``pd``; ``M·u + b`` for
  ``computed-torque``, whose armature and friction terms are the motor's) and the sensor's
  reading of the link-side torque at the tick before, ``τ_s = Q((1 + s)·τ_link + b + n)``
  (:func:`~aaria_pin.core.torque_sensor.torque_reading`,
  ``τ_link = τ - armature·qdd - friction(qd)``), low-passed, ``z += β·(target - τ_s - z)``,
  and ``τ = τ_c + k·z``: it makes up the friction and armature torque the motor loses
  (at rest, ``1/(1 + k)`` of it is left). Unfiltered, a one-tick-old reading makes a loop
  with a pole near ``-k`` (diverged at ``k = 9``). Filtered (``β = 1 - exp(-2π·f_t·h)``), on
  ur5 with Coulomb 8 N·m and viscous 2 N·m·s/rad (3 s, ``tests/core/test_control.py``), ``pd``
  tracked at 2.7, 0.67 and 0.55 mrad RMS with ``k`` = 0, 4, 9, but at ``k = 9`` the motors sat
  at their limit on 10 % of the samples (chatter); ``computed-torque``, which feeds the
  friction forward already, went from 4.4e-6 to 5.4e-5 rad at ``k = 4`` (the loop reacts, one
  tick late, to the feed-forward's misses at velocity reversals): keep ``k`` small, for ``pd``;
- the motor torque saturated at its limit.

After each sample the run is checked: a non-finite state, or a joint farther than ``lost[0]``
from its reference or moving ``lost[1]`` faster or slower than it, ends the integration, and the
kernel returns that sample (the caller names it). Every kernel here is compiled without
``fastmath`` (``exact``): a NaN then compares false as IEEE says, and a run's numbers do not
depend on whether a kernel was compiled in this process or loaded from numba's cache (with
``fastmath`` they did, in the last bits: found by review, a run compiled fresh and its
``--from`` re-make from the cache differed by 1.7e-12 in ``qdd``).
"""

from __future__ import annotations

import numpy as np

from aaria_pin.core._compile import kernel
from aaria_pin.core._forward_kernel import (
    _at,
    base_at,
    dynamics_terms,
    friction_at,
    scratch,
    step,
    workspace,
)

PD, COMPUTED_TORQUE = 0, 1
"""The laws' codes: their places in :data:`aaria_pin.core.control.LAWS`."""


@kernel(exact=True)
def reference_at(reference, i, w, dt, out):  # type: ignore[no-untyped-def]  # pragma: no cover
    """The reference between samples i and i + 1 at weight w (dt the sample period [s]).

    ``out`` (3, n): values and velocities cubic Hermite, accelerations linear.
    """
    q, qd, qdd = reference
    i1 = min(i + 1, q.shape[0] - 1)
    w2 = w * w
    w3 = w2 * w
    h00 = 2 * w3 - 3 * w2 + 1
    h10 = w3 - 2 * w2 + w
    h01 = -2 * w3 + 3 * w2
    h11 = w3 - w2
    for m in range(q.shape[1]):
        out[0, m] = h00 * q[i, m] + h10 * dt * qd[i, m] + h01 * q[i1, m] + h11 * dt * qd[i1, m]
        out[1, m] = h00 * qd[i, m] + h10 * dt * qdd[i, m] + h01 * qd[i1, m] + h11 * dt * qdd[i1, m]
        out[2, m] = (1 - w) * qdd[i, m] + w * qdd[i1, m]


@kernel(exact=True)
def _measured(x, y, tick, h, sensing, memory, out):  # type: ignore[no-untyped-def]  # pragma: no cover
    """The encoders' values and the velocity the controller estimates (``out`` rows 0, 1)."""
    on, offset, count, noise, alpha = sensing[0], sensing[1], sensing[2], sensing[3], sensing[4]
    n = x.shape[0]
    if not on:
        for m in range(n):
            out[0, m] = x[m]
            out[1, m] = y[m]
        return
    for m in range(n):
        seen = x[m] + noise[tick, m]
        if count[m] > 0:
            seen = count[m] * np.round(seen / count[m])
        reading = offset[m] + seen
        if memory[3, m] == 0:  # the first tick: the drive starts from a known state
            memory[1, m] = y[m]
        else:
            raw = (reading - memory[0, m]) / h
            memory[1, m] += alpha[m] * (raw - memory[1, m])
        memory[0, m] = reading
        out[0, m] = reading
        out[1, m] = memory[1, m]


@kernel(exact=True)
def _command(model, law, kp, kd, nq, rows, motor, work, out):  # type: ignore[no-untyped-def]  # pragma: no cover
    """The controller's torque ``out`` (n,) at a tick (the base's state already in ``work``).

    ``rows`` (7, n): the reference (values, velocities, accelerations), the measured values and
    velocities, a scratch row, and (written here) the link-side torque the command asks for,
    the torque loop's target: the command itself for ``pd``, ``M·u + b`` for
    ``computed-torque`` (its armature and friction terms are the motor's own).
    """
    n = out.shape[0]
    ref_q, ref_qd, ref_qdd, q_m, v_m, u = rows[0], rows[1], rows[2], rows[3], rows[4], rows[5]
    target = rows[6]
    if law == PD:
        for m in range(n):
            out[m] = kp[m] * (ref_q[m] - q_m[m]) + kd[m] * (ref_qd[m] - v_m[m])
            target[m] = out[m]
        return
    line = work[12]
    dynamics_terms(model, line[1, :nq], line[2, :6], line[3, :6], q_m, v_m, work)
    A, rhs = work[9], line[0]
    for m in range(n):
        u[m] = ref_qdd[m] + kp[m] * (ref_q[m] - q_m[m]) + kd[m] * (ref_qd[m] - v_m[m])
    for m in range(n):
        s = -rhs[m]
        for c in range(n):
            s += A[m, c] * u[c]
        target[m] = s
        if motor[0]:
            s += motor[1][m] * u[m] + friction_at(motor, m, ref_qd[m])
        out[m] = s


@kernel(exact=True)
def _tick(model, base, k, x, y, tick, h, control, sensing, motor, memory, rows, work, held, out):  # type: ignore[no-untyped-def]  # pragma: no cover
    """One tick: ``out`` the controller's command, ``held[0]`` the motor torque held after it.

    ``rows[0:3]`` hold the reference at the tick; ``memory`` (5, n) the encoders' last reading,
    the filtered velocity, the link-side torque of the tick before, whether there was a tick
    before (1) or not (0) (a flag, not NaN: the kernels are compiled with ``fastmath``, under
    which a NaN test may be folded away), and the torque loop's filtered error.
    """
    law, kp, kd, feedback, beta, limit = control
    ts_on, scale, bias = sensing[5], sensing[6], sensing[7]
    resolution, ts_noise = sensing[8], sensing[9]
    base_at(base, k, work)
    _measured(x, y, tick, h, sensing, memory, rows[3:5])
    _command(model, law, kp, kd, base[0].shape[1], rows, motor, work, out)
    for m in range(out.shape[0]):
        applied = out[m]
        if ts_on and feedback[m] > 0 and memory[3, m] > 0:
            seen = (1.0 + scale[m]) * memory[2, m] + bias[m] + ts_noise[tick, m]
            if resolution[m] > 0:
                seen = resolution[m] * np.round(seen / resolution[m])
            memory[4, m] += beta[m] * (rows[6, m] - seen - memory[4, m])
            applied = out[m] + feedback[m] * memory[4, m]
        held[0, m] = min(max(applied, -limit[m]), limit[m])
        memory[3, m] = 1.0


@kernel(exact=True)
def _link_torque(held, k1, y, motor, memory):  # type: ignore[no-untyped-def]  # pragma: no cover
    """Keep the link-side torque of this tick for the torque sensor's next reading."""
    for m in range(y.shape[0]):
        value = held[0, m]
        if motor[0]:
            value -= motor[1][m] * k1[m] + friction_at(motor, m, y[m])
        memory[2, m] = value


@kernel(exact=True)
def integrate_closed(model, base, reference, h, substeps, method, motor, stop, control, sensing, q, v, a, command, memory, first, last, lost, articulated):  # type: ignore[no-untyped-def]  # noqa: E501  # pragma: no cover  # fmt: skip
    """Integrate samples ``first`` to ``last`` under the controller (module docstring).

    Fills ``q``, ``v`` (T, n) from ``first`` (its state given) to ``last``, ``a`` and
    ``command`` (the controller's torque at each sample's tick) from ``first`` to ``last - 1``
    (and ``last`` when it is the run's last sample); the plant is evaluated by ABA
    (``articulated``, an :func:`~aaria_pin.core._articulated_kernel.articulated_workspace`).
    ``sensing``'s noise rows are this span's ticks, in order (the final tick of the run last);
    ``memory`` carries the controller's state from span to span. Returns -1, or the first sample
    where the run lost its reference (``lost``: position [rad or m] and speed [rad/s or m/s]
    bounds) or is not finite.
    """
    T, n = reference[0].shape
    dt = h * substeps
    dk = 1.0 / substeps
    work = workspace(model[0].shape[0], n)
    steps = scratch(n)
    rows = np.empty((7, n))
    held = np.empty((1, n))
    out = np.empty(n)
    y_tick = np.empty(n)
    x, y = q[first].copy(), v[first].copy()
    tick = 0
    for i in range(first, last):
        for s in range(substeps):
            w = s / substeps
            reference_at(reference, i, w, dt, rows)
            _tick(
                model, base, i + w, x, y, tick, h, control, sensing, motor, memory, rows, work,
                held, out,
            )  # fmt: skip
            y_tick[:] = y
            step(
                model, base, held, True, i + w, dk, h, method, x, y, motor, stop, work, steps,
                articulated,
            )  # fmt: skip
            _link_torque(held, steps[0], y_tick, motor, memory)
            if s == 0:
                a[i] = steps[0]
                command[i] = out
            tick += 1
        q[i + 1], v[i + 1] = x, y
        ref_q, ref_qd = reference[0], reference[1]
        for m in range(n):
            error = abs(x[m] - ref_q[i + 1, m])  # exact: NaN fails every comparison
            rate_error = abs(y[m] - ref_qd[i + 1, m])
            if not (error <= lost[0, m] and rate_error <= lost[1, m]):
                return i + 1
    if last == T - 1:
        reference_at(reference, T - 1, 0.0, dt, rows)
        _tick(
            model, base, float(T - 1), q[T - 1], v[T - 1], tick, h, control, sensing, motor,
            memory, rows, work, held, command[T - 1],
        )  # fmt: skip
        _at(
            model, base, held, True, float(T - 1), q[T - 1], v[T - 1], motor, stop, work,
            a[T - 1], articulated,
        )  # fmt: skip
    return -1
