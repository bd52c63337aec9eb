"""Compiled (numba) kernel of the torque drive: forward dynamics and its integration in one call.

The model is flattened into arrays (:func:`aaria_pin.core.forward.flatten_dynamics`): for each
joint its kind (revolute, prismatic, or the free-flyer of a moving base), unit axis, parent,
column, placement in its parent (``jointPlacements``) and its body's mass, centre of mass and
rotational inertia about it. One evaluation (:func:`joint_accelerations`) works in world
coordinates at the world origin, where spatial vectors of different bodies add without
transforms:

- forward pass: each joint's world pose, its motion subspace ``S`` (revolute about ``k``:
  angular ``ω = R·k``, linear ``p × ω``; prismatic: linear ``R·k``), velocity
  ``v_j = v_parent + S·qd`` and acceleration ``a_j = a_parent + v_parent × S·qd`` (joints'
  ``qdd = 0``; the universe accelerates at ``-g``, the base adds its own prescribed
  acceleration), and the body's force ``f = I·a + v ×* I·v`` (RNEA with ``qdd = 0``);
- backward pass: forces and composite inertias (mass ``m``, first moment ``h = m·c``,
  rotational inertia about the origin ``J``) summed into the parents; the bias of a joint is
  ``S·f``, the mass matrix ``M[i, j] = S_j·(I_crb,i·S_i)`` (CRBA);
- with stops (policy ``clamp``), each joint beyond its limits gets the one-sided spring-damper
  ``-k·(q - clip(q, lower, upper)) - c·qd``, ``k = m_i·ω²``, ``c = 2·m_i·ω`` (``m_i`` the
  joint's effective inertia ``1 / (M⁻¹)_ii``, from the Cholesky factor;
  :func:`aaria_pin.core.forward.stop_torques`);
- ``(M + diag(armature))·qdd = tau - friction(qd) + stop - bias`` solved by Cholesky.

:func:`integrate` runs the whole run: classical Runge–Kutta (or semi-implicit Euler) with
``substeps`` steps per sample, torques and the base state linear between samples (the base's
quaternion normalized after interpolation), exactly as
:func:`aaria_pin.core.forward.reference_forward_simulate` does with Pinocchio calls.

Compiled on first use and cached on disk (:func:`aaria_pin.core._compile.kernel`).
"""

from __future__ import annotations

import numpy as np

from aaria_pin.core._articulated_kernel import (
    _pose_from_base,
    articulated_at,
    articulated_stops,
    friction_at,
)
from aaria_pin.core._compile import kernel
from aaria_pin.core._kinematics_kernel import FREEFLYER, REVOLUTE, _rotation

RK4, EULER = 0, 1


@kernel(exact=True)
def _cross(a: np.ndarray, b: np.ndarray, out: np.ndarray) -> None:  # pragma: no cover
    """Out = a × b (3-vectors; out may not alias a or b)."""
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]


@kernel(exact=True)
def _inertia_times(m, h, J, motion, out):  # type: ignore[no-untyped-def]  # pragma: no cover
    """Out = I·motion, I at the origin (m, h = m·c, J), motion (linear, angular)."""
    for i in range(3):
        out[i] = m * motion[i]
        out[3 + i] = J[i, 0] * motion[3] + J[i, 1] * motion[4] + J[i, 2] * motion[5]
    w, v = motion[3:], motion[:3]
    out[0] += w[1] * h[2] - w[2] * h[1]
    out[1] += w[2] * h[0] - w[0] * h[2]
    out[2] += w[0] * h[1] - w[1] * h[0]
    out[3] += h[1] * v[2] - h[2] * v[1]
    out[4] += h[2] * v[0] - h[0] * v[2]
    out[5] += h[0] * v[1] - h[1] * v[0]


@kernel(exact=True)
def _to_world(R, p, local, out):  # type: ignore[no-untyped-def]  # pragma: no cover
    """A motion in a frame (R, p) (linear, angular) as a motion at the world origin."""
    for i in range(3):
        out[3 + i] = R[i, 0] * local[3] + R[i, 1] * local[4] + R[i, 2] * local[5]
        out[i] = R[i, 0] * local[0] + R[i, 1] * local[1] + R[i, 2] * local[2]
    out[0] += p[1] * out[5] - p[2] * out[4]
    out[1] += p[2] * out[3] - p[0] * out[5]
    out[2] += p[0] * out[4] - p[1] * out[3]


@kernel(exact=True)
def workspace(nj, n):  # type: ignore[no-untyped-def]  # pragma: no cover
    """The arrays one evaluation works in, for ``nj`` joints (with the universe), ``n`` columns.

    Per joint: world rotation and position, motion subspace, velocity, acceleration, force,
    composite inertia (mass, first moment, rotational inertia); the mass matrix; scratch
    6-vectors and 3 × 3 matrices; and rows of length ``max(n, 7)``: the right-hand side, then
    (for :func:`_at`) the base's interpolated configuration, velocity, acceleration and the
    torques.
    """
    return (
        np.zeros((nj, 3, 3)),
        np.zeros((nj, 3)),
        np.zeros((nj, 6)),
        np.zeros((nj, 6)),
        np.zeros((nj, 6)),
        np.zeros((nj, 6)),
        np.zeros(nj),
        np.zeros((nj, 3)),
        np.zeros((nj, 3, 3)),
        np.zeros((n, n)),
        np.zeros((8, 6)),
        np.zeros((4, 3, 3)),
        np.zeros((5, max(n, 7))),
    )


@kernel(exact=True)
def dynamics_terms(model, qb, vb, ab, q, v, work):  # type: ignore[no-untyped-def]  # pragma: no cover
    """The joints' mass matrix and bias at one state, the base prescribed (module docstring).

    Fills the workspace's mass matrix ``work[9]`` (n × n, both triangles) and its right-hand
    side row ``work[12][0]`` with ``-bias`` (the RNEA torques with ``qdd = 0``: gravity,
    Coriolis, the base's acceleration). ``model`` is the tuple of
    :func:`~aaria_pin.core.forward.flatten_dynamics`; ``qb``, ``vb``, ``ab`` the base's
    configuration (7,), velocity and acceleration (6,, local, Pinocchio's convention; unused on
    a fixed base); ``work`` a :func:`workspace`.
    """
    kinds, axes, parents, columns, PR, Pp, mass, lever, Ic, gravity = model
    R, p, S, vel, acc, f, cm, ch, cJ, A, six, three, _ = work
    nj = kinds.shape[0]
    Rot, M0 = three[0], three[1]
    d, c = six[0, :3], six[0, 3:]
    vJ, aJ, Iv, F, rhs = six[1], six[2], six[3], six[4], work[12][0]
    vel[0] = 0.0
    acc[0] = 0.0
    R[0] = 0.0
    f[0] = 0.0
    cm[0] = 0.0
    ch[0] = 0.0
    cJ[0] = 0.0
    A[:] = 0.0
    for i in range(3):
        R[0, i, i] = 1.0
        acc[0, i] = -gravity[i]
    for j in range(1, nj):
        pa = parents[j]
        kind = kinds[j]
        # the joint's motion in its own frame: M0 (rotation), d (translation)
        if kind == FREEFLYER:
            _pose_from_base(qb, M0, d)
        elif kind == REVOLUTE:
            _rotation(axes[j], q[columns[j]], M0)
            d[:] = 0.0
        else:
            M0[:] = 0.0
            for i in range(3):
                M0[i, i] = 1.0
                d[i] = axes[j, i] * q[columns[j]]
        # world pose: R_pa·(PR·M0), p_pa + R_pa·(Pp + PR·d)
        for i in range(3):
            for k in range(3):
                Rot[i, k] = PR[j, i, 0] * M0[0, k] + PR[j, i, 1] * M0[1, k] + PR[j, i, 2] * M0[2, k]
            c[i] = Pp[j, i] + PR[j, i, 0] * d[0] + PR[j, i, 1] * d[1] + PR[j, i, 2] * d[2]
        for i in range(3):
            for k in range(3):
                R[j, i, k] = (
                    R[pa, i, 0] * Rot[0, k] + R[pa, i, 1] * Rot[1, k] + R[pa, i, 2] * Rot[2, k]
                )
            p[j, i] = p[pa, i] + R[pa, i, 0] * c[0] + R[pa, i, 1] * c[1] + R[pa, i, 2] * c[2]
        if kind == FREEFLYER:
            _to_world(R[j], p[j], vb, vJ)
            _to_world(R[j], p[j], ab, aJ)
        else:
            S[j] = 0.0
            for i in range(3):
                e = R[j, i, 0] * axes[j, 0] + R[j, i, 1] * axes[j, 1] + R[j, i, 2] * axes[j, 2]
                if kind == REVOLUTE:
                    S[j, 3 + i] = e
                else:
                    S[j, i] = e
            if kind == REVOLUTE:
                _cross(p[j], S[j, 3:], S[j, :3])
            for i in range(6):
                vJ[i] = S[j, i] * v[columns[j]]
                aJ[i] = 0.0
        # v_j = v_pa + vJ; a_j = a_pa + aJ + v_pa × vJ
        wp, lp = vel[pa, 3:], vel[pa, :3]
        for i in range(6):
            vel[j, i] = vel[pa, i] + vJ[i]
            acc[j, i] = acc[pa, i] + aJ[i]
        acc[j, 0] += wp[1] * vJ[2] - wp[2] * vJ[1] + lp[1] * vJ[5] - lp[2] * vJ[4]
        acc[j, 1] += wp[2] * vJ[0] - wp[0] * vJ[2] + lp[2] * vJ[3] - lp[0] * vJ[5]
        acc[j, 2] += wp[0] * vJ[1] - wp[1] * vJ[0] + lp[0] * vJ[4] - lp[1] * vJ[3]
        acc[j, 3] += wp[1] * vJ[5] - wp[2] * vJ[4]
        acc[j, 4] += wp[2] * vJ[3] - wp[0] * vJ[5]
        acc[j, 5] += wp[0] * vJ[4] - wp[1] * vJ[3]
        if kind == FREEFLYER:  # the prescribed base's own body enters no joint's equation
            cm[j] = 0.0
            ch[j] = 0.0
            cJ[j] = 0.0
            f[j] = 0.0
            continue
        # the body's inertia at the world origin: m, h = m·c, J = R·Ic·Rᵀ + m(|c|²1 - c·cᵀ)
        m = mass[j]
        for i in range(3):
            c[i] = (
                p[j, i]
                + R[j, i, 0] * lever[j, 0]
                + R[j, i, 1] * lever[j, 1]
                + R[j, i, 2] * lever[j, 2]
            )
        cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2]
        for i in range(3):
            for k in range(3):
                Rot[i, k] = (
                    R[j, i, 0] * Ic[j, 0, k] + R[j, i, 1] * Ic[j, 1, k] + R[j, i, 2] * Ic[j, 2, k]
                )
        for i in range(3):
            ch[j, i] = m * c[i]
            for k in range(3):
                cJ[j, i, k] = (
                    Rot[i, 0] * R[j, k, 0]
                    + Rot[i, 1] * R[j, k, 1]
                    + Rot[i, 2] * R[j, k, 2]
                    - m * c[i] * c[k]
                )
            cJ[j, i, i] += m * cc
        cm[j] = m
        # f = I·a + v ×* (I·v)
        _inertia_times(m, ch[j], cJ[j], acc[j], f[j])
        _inertia_times(m, ch[j], cJ[j], vel[j], Iv)
        w, lv = vel[j, 3:], vel[j, :3]
        f[j, 0] += w[1] * Iv[2] - w[2] * Iv[1]
        f[j, 1] += w[2] * Iv[0] - w[0] * Iv[2]
        f[j, 2] += w[0] * Iv[1] - w[1] * Iv[0]
        f[j, 3] += w[1] * Iv[5] - w[2] * Iv[4] + lv[1] * Iv[2] - lv[2] * Iv[1]
        f[j, 4] += w[2] * Iv[3] - w[0] * Iv[5] + lv[2] * Iv[0] - lv[0] * Iv[2]
        f[j, 5] += w[0] * Iv[4] - w[1] * Iv[3] + lv[0] * Iv[1] - lv[1] * Iv[0]
    # backward: forces and composite inertias into the parents; bias; mass matrix
    for j in range(nj - 1, 0, -1):
        pa = parents[j]
        if kinds[j] != FREEFLYER:
            col = columns[j]
            bias = 0.0
            for i in range(6):
                bias += S[j, i] * f[j, i]
            rhs[col] = -bias
            _inertia_times(cm[j], ch[j], cJ[j], S[j], F)
            k = j
            while k > 0 and kinds[k] != FREEFLYER:
                value = 0.0
                for i in range(6):
                    value += S[k, i] * F[i]
                A[columns[k], col] = value
                A[col, columns[k]] = value
                k = parents[k]
        cm[pa] += cm[j]
        for i in range(3):
            ch[pa, i] += ch[j, i]
            for k in range(3):
                cJ[pa, i, k] += cJ[j, i, k]
        for i in range(6):
            f[pa, i] += f[j, i]


@kernel(exact=True)
def joint_accelerations(model, qb, vb, ab, q, v, torque, motor, stop, work, out):  # type: ignore[no-untyped-def]  # pragma: no cover
    """Joint accelerations ``out`` (n,) at one state, the base prescribed (module docstring).

    ``model``, ``qb``, ``vb``, ``ab``, ``work`` as :func:`dynamics_terms`; ``torque`` (n,) the
    joint torques; ``motor`` the tuple ``(on, armature, viscous, coulomb, coulomb_velocity,
    stribeck_torque, stribeck_velocity)`` (``on`` 0: no actuator); ``stop`` the tuple ``(on,
    lower, upper, omega)`` of the stops (``on`` 0: none).
    """
    on, rotor = motor[0], motor[1]
    dynamics_terms(model, qb, vb, ab, q, v, work)
    A, rhs = work[9], work[12][0]
    n = q.shape[0]
    for i in range(n):
        rhs[i] = torque[i] + rhs[i]
    if on:
        for i in range(n):
            A[i, i] += rotor[i]
            rhs[i] -= friction_at(motor, i, v[i])
    # Cholesky: A = L·Lᵀ (L in the lower triangle of A), then two triangular solves
    for i in range(n):
        for k in range(i + 1):
            s = A[i, k]
            for m2 in range(k):
                s -= A[i, m2] * A[k, m2]
            A[i, k] = np.sqrt(s) if i == k else s / A[k, k]
    if stop[0]:  # the stops, with each joint's effective inertia 1 / (M⁻¹)_ii (out: scratch)
        lower, upper, omega = stop[1], stop[2], stop[3]
        for j in range(n):
            x = q[j]
            if x < lower[j] or x > upper[j]:
                edge = lower[j] if x < lower[j] else upper[j]
                inverse = 0.0  # (M⁻¹)_jj = |L⁻¹·e_j|²
                for i in range(j, n):
                    s = 1.0 if i == j else 0.0
                    for k in range(j, i):
                        s -= A[i, k] * out[k]
                    out[i] = s / A[i, i]
                    inverse += out[i] * out[i]
                inertia = 1.0 / inverse
                rhs[j] += -inertia * omega * omega * (x - edge) - 2 * inertia * omega * v[j]
    for i in range(n):
        s = rhs[i]
        for k in range(i):
            s -= A[i, k] * out[k]
        out[i] = s / A[i, i]
    for i in range(n - 1, -1, -1):
        s = out[i]
        for k in range(i + 1, n):
            s -= A[k, i] * out[k]
        out[i] = s / A[i, i]


@kernel(exact=True)
def base_at(base, k, work):  # type: ignore[no-untyped-def]  # pragma: no cover
    """The base's state at fractional sample index k, linear in k (quaternion normalized).

    Written into the workspace's rows 1-3 (configuration, velocity, acceleration); returns the
    sample before k, the one after and the weight of the one after.
    """
    q_base, v_base, a_base = base
    T = q_base.shape[0]
    i = min(int(k), T - 2)
    if i < 0:
        i = 0
    w = k - i
    i1 = min(i + 1, T - 1)
    line = work[12]
    qb, vb, ab = line[1, : q_base.shape[1]], line[2, :6], line[3, :6]
    for m in range(q_base.shape[1]):
        qb[m] = (1 - w) * q_base[i, m] + w * q_base[i1, m]
    if q_base.shape[1] == 7:
        norm = np.sqrt(qb[3] ** 2 + qb[4] ** 2 + qb[5] ** 2 + qb[6] ** 2)
        for m in range(3, 7):
            qb[m] /= norm
    for m in range(v_base.shape[1]):
        vb[m] = (1 - w) * v_base[i, m] + w * v_base[i1, m]
        ab[m] = (1 - w) * a_base[i, m] + w * a_base[i1, m]
    return i, i1, w


@kernel(exact=True)
def _at(model, base, tau, hold, k, q, v, motor, stop, work, out, articulated=None):  # type: ignore[no-untyped-def]  # pragma: no cover
    """Joint accelerations at fractional sample index k (the base linear in k).

    The torques ``tau`` (T, n) linear in k, or (``hold``) its first row held (a controller's
    command). With ``articulated`` (an :func:`~aaria_pin.core._articulated_kernel.
    articulated_workspace`) :func:`~aaria_pin.core._articulated_kernel.articulated_at` and
    ``articulated_stops`` evaluate (the ``aba`` dynamics); without (None),
    :func:`joint_accelerations` (the
    ``kernel`` dynamics). The test is resolved when numba compiles: a call without
    ``articulated`` is the code it was before (and one with it holds no CRBA: with both, the
    drive measured 1.5× slower on ur5).
    """
    if articulated is not None:
        articulated_at(model, base, tau, hold, k, q, v, motor, articulated, out)
        if stop[0]:
            articulated_stops(model, q, v, stop, articulated, out)
        return
    i, i1, w = base_at(base, k, work)
    line = work[12]
    nq = base[0].shape[1]
    n = tau.shape[1]
    torque = line[4, :n]
    if hold:
        for m in range(n):
            torque[m] = tau[0, m]
    else:
        for m in range(n):
            torque[m] = (1 - w) * tau[i, m] + w * tau[i1, m]
    joint_accelerations(
        model, line[1, :nq], line[2, :6], line[3, :6], q, v, torque, motor, stop, work, out
    )


@kernel(exact=True)
def scratch(n):  # type: ignore[no-untyped-def]  # pragma: no cover
    """The rows one integration step works in: k1-k4 and the trial state (6 × n)."""
    return np.empty((6, n))


@kernel(exact=True)
def step(model, base, tau, hold, k, dk, h, method, x, y, motor, stop, work, rows, articulated=None):  # type: ignore[no-untyped-def]  # pragma: no cover
    """One step of h [s] of the state (x, y), in place, from fractional sample index k.

    RK4 or semi-implicit Euler (``dk`` the step in samples); ``rows[0]`` keeps the acceleration
    at the step's start (``rows`` from :func:`scratch`; the torques and ``articulated`` as
    :func:`_at` takes them).
    """
    n = x.shape[0]
    k1, k2, k3, k4, xt, yt = rows[0], rows[1], rows[2], rows[3], rows[4], rows[5]
    _at(model, base, tau, hold, k, x, y, motor, stop, work, k1, articulated)
    if method == EULER:
        for m in range(n):
            y[m] = y[m] + h * k1[m]
            x[m] = x[m] + h * y[m]
        return
    for m in range(n):
        xt[m] = x[m] + h / 2 * y[m]
        yt[m] = y[m] + h / 2 * k1[m]
    _at(model, base, tau, hold, k + dk / 2, xt, yt, motor, stop, work, k2, articulated)
    for m in range(n):
        xt[m] = x[m] + h / 2 * (y[m] + h / 2 * k1[m])
        yt[m] = y[m] + h / 2 * k2[m]
    _at(model, base, tau, hold, k + dk / 2, xt, yt, motor, stop, work, k3, articulated)
    for m in range(n):
        xt[m] = x[m] + h * (y[m] + h / 2 * k2[m])
        yt[m] = y[m] + h * k3[m]
    _at(model, base, tau, hold, k + dk, xt, yt, motor, stop, work, k4, articulated)
    for m in range(n):
        ym = y[m]
        x[m] = x[m] + h / 6 * (
            ym + 2 * (ym + h / 2 * k1[m]) + 2 * (ym + h / 2 * k2[m]) + (ym + h * k3[m])
        )
        y[m] = ym + h / 6 * (k1[m] + 2 * k2[m] + 2 * k3[m] + k4[m])


@kernel(exact=True)
def integrate(  # type: ignore[no-untyped-def]  # pragma: no cover
    model, base, tau, h, substeps, method, motor, stop, q, v, a, first, last, articulated=None
):
    """Integrate samples ``first`` to ``last``: RK4 or semi-implicit Euler, ``substeps`` of h [s].

    Fills ``q``, ``v`` (T, n) from ``first`` (its state given) to ``last`` and ``a`` from
    ``first`` to ``last - 1`` (and ``last`` when it is the run's last sample). A run integrated
    in several such spans is the run integrated at once, bit for bit (the state at a sample is
    all a span needs). ``articulated`` as :func:`_at` takes it (None: the ``kernel`` dynamics).
    """
    T, n = tau.shape
    work = workspace(model[0].shape[0], n)
    rows = scratch(n)
    dk = 1.0 / substeps
    x, y = q[first].copy(), v[first].copy()
    for i in range(first, last):
        for s in range(substeps):
            step(
                model,
                base,
                tau,
                False,
                i + s / substeps,
                dk,
                h,
                method,
                x,
                y,
                motor,
                stop,
                work,
                rows,
                articulated,
            )
            if s == 0:
                a[i] = rows[0]
        q[i + 1], v[i + 1] = x, y
    if last == T - 1:
        _at(
            model,
            base,
            tau,
            False,
            float(T - 1),
            q[T - 1],
            v[T - 1],
            motor,
            stop,
            work,
            a[T - 1],
            articulated,
        )
