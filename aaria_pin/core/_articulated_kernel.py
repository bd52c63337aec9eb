"""Compiled (numba) forward dynamics by the articulated-body algorithm, the base prescribed.

The ``aba`` dynamics of the torque drive (``forward_simulate(..., articulated=True)``,
:data:`aaria_pin.core.forward.DYNAMICS`): the joints' accelerations of
:func:`aaria_pin.core._forward_kernel.joint_accelerations` (the CRBA mass matrix solved by
Cholesky against the RNEA bias, the ``kernel`` dynamics), found in O(n) by Featherstone's
articulated-body algorithm, in world coordinates at the world origin, where a child's
articulated inertia adds to its parent's with no transform (Pinocchio's ABA works in the same
frame). Three passes over the joints (model arrays of :func:`~aaria_pin.core.forward.
flatten_dynamics`):

- out: each joint's world pose, motion subspace ``S``, velocity and the acceleration with the
  joints' ``qdd = 0`` (the universe at ``-g``, the prescribed base at its own), each body's
  spatial inertia at the origin ``I`` (6 × 6, linear then angular) and force
  ``f = I·a + v ×* I·v``: the RNEA forces with ``qdd = 0``. With those, the accelerations the
  recursion carries are only what the ``qdd`` add, ``δa_j = δa_parent + S_j·qdd_j`` (zero at
  the prescribed base), and the textbook's bias accelerations ``c`` are already in ``f``;
- in: ``U = I^A·S``, ``D = Sᵀ·U + armature``, ``u = tau - friction - Sᵀ·f``, then
  ``I^A_parent += I^A - U·Uᵀ/D`` and ``f_parent += f + U·u/D``;
- out: ``qdd = (u - Uᵀ·δa_parent)/D``.

Why it replaced the CRBA kernel for new runs (measured in compiled loops on a shared 2-core
machine): one evaluation at a fractional sample (``_at``, interpolation included) takes 1.0-1.3
µs on ur5 against 2.6-2.9 µs for the CRBA kernel (1.4-1.8 against 3.2-4.4 µs on panda); whole
runs are 2.2× faster (``benchmarks/bench_forward.py``: 0.75× MuJoCo's ``rollout`` on ur5, the
CRBA kernel 1.67×). The three passes alone take 0.6 µs on ur5; the O(n²) mass matrix and its
Cholesky factor (0.5-0.9 µs of the CRBA evaluation) go. The rest is how it is written: one
kernel with its arrays indexed directly, because numba counts the references of every array a
call between kernels passes and of every view (``R[j]``, a slice of a row): written as five
small kernels the same passes took 1.5-1.7 µs, and the interpolation by
:func:`~aaria_pin.core._forward_kernel.base_at` 0.24 µs more. The stops of the ``clamp`` policy
need ``(M⁻¹)_ii`` of a joint beyond them: its column ``M⁻¹·e_i`` is two more O(n) passes with
the articulated inertias already found (:func:`articulated_stops`, a separate kernel: with a
CRBA fallback in the same path the drive was 1.5× slower).
"""

from __future__ import annotations

import numpy as np

from aaria_pin.core._compile import kernel
from aaria_pin.core._kinematics_kernel import FREEFLYER, REVOLUTE


@kernel(exact=True)
def _pose_from_base(qb, R, p):  # type: ignore[no-untyped-def]  # pragma: no cover
    """The base's rotation and position from ``[x y z qx qy qz qw]`` (quaternion unit)."""
    x, y, z, w = qb[3], qb[4], qb[5], qb[6]
    R[0, 0] = 1 - 2 * (y * y + z * z)
    R[0, 1] = 2 * (x * y - z * w)
    R[0, 2] = 2 * (x * z + y * w)
    R[1, 0] = 2 * (x * y + z * w)
    R[1, 1] = 1 - 2 * (x * x + z * z)
    R[1, 2] = 2 * (y * z - x * w)
    R[2, 0] = 2 * (x * z - y * w)
    R[2, 1] = 2 * (y * z + x * w)
    R[2, 2] = 1 - 2 * (x * x + y * y)
    for i in range(3):
        p[i] = qb[i]


@kernel(exact=True)
def friction_at(motor, i, x):  # type: ignore[no-untyped-def]  # pragma: no cover
    """Joint i's friction at velocity x (``motor`` as :func:`joint_accelerations` takes it).

    ``viscous·x + (coulomb + stribeck·exp(-(x/v_s)²))·tanh(x/coulomb_velocity)``
    (:func:`~aaria_pin.core.actuator.friction`).
    """
    _, _, viscous, coulomb, smooth, stribeck, v_s = motor
    dry = coulomb[i] + stribeck[i] * np.exp(-((x / v_s[i]) ** 2))
    return viscous[i] * x + dry * np.tanh(x / smooth[i])


@kernel(exact=True)
def articulated_workspace(nj):  # type: ignore[no-untyped-def]  # pragma: no cover
    """The arrays :func:`articulated_accelerations` works in, for ``nj`` joints (with the universe).

    Per joint: articulated inertia (6 × 6), ``U``, ``1 / D``, ``u``, ``δa``, world rotation and
    position, ``S``, velocity, acceleration, force; then the base joint's own rotation and
    translation (:func:`_pose_from_base`), a 3 × 3 scratch, and the rows of the state at one
    instant: the base's configuration, velocity, acceleration and the joints' torques less
    their friction.
    """
    return (
        np.zeros((nj, 6, 6)),
        np.zeros((nj, 6)),
        np.zeros(nj),
        np.zeros(nj),
        np.zeros((nj, 6)),
        np.zeros((nj, 3, 3)),
        np.zeros((nj, 3)),
        np.zeros((nj, 6)),
        np.zeros((nj, 6)),
        np.zeros((nj, 6)),
        np.zeros((nj, 6)),
        np.zeros((3, 3)),
        np.zeros(3),
        np.zeros((3, 3)),
        np.zeros((4, max(nj, 7))),
    )


@kernel(exact=True)
def articulated_at(model, base, tau, hold, k, q, v, motor, articulated, out):  # type: ignore[no-untyped-def]  # pragma: no cover
    """Joint accelerations ``out`` (n,) at fractional sample index k, by ABA (module docstring).

    Arguments as :func:`~aaria_pin.core._forward_kernel._at` takes them (the base linear in k,
    its quaternion normalized; the torques ``tau`` linear in k or, ``hold``, its first row),
    with ``articulated`` an :func:`articulated_workspace`; the stops are
    :func:`articulated_stops`'. One kernel from the interpolation to
    the accelerations: each call between kernels measured 0.25-0.8 µs here (numba counts the
    references of the arrays a call passes; the three passes of ABA cost 0.6 µs on ur5), so the
    interpolation is written here again rather than taken from
    :func:`~aaria_pin.core._forward_kernel.base_at`, whose row views cost 0.24 µs per call.
    """
    kinds, axes, parents, columns, PR, Pp, mass, lever, Ic, gravity = model
    IA, U, Dinv, u, da, R, p, S, vel, acc, f, Mb, db, B, line = articulated
    Rot = B
    rotor = motor[1]
    on = motor[0]
    nj = kinds.shape[0]
    # the instant: base and torques linear between samples i and i + 1
    q_base, v_base, a_base = base
    T = q_base.shape[0]
    i = max(min(int(k), T - 2), 0)
    w = k - i
    i1 = min(i + 1, T - 1)
    for m in range(q_base.shape[1]):
        line[0, m] = (1 - w) * q_base[i, m] + w * q_base[i1, m]
    for m in range(v_base.shape[1]):
        line[1, m] = (1 - w) * v_base[i, m] + w * v_base[i1, m]
        line[2, m] = (1 - w) * a_base[i, m] + w * a_base[i1, m]
    if q_base.shape[1] == 7:
        norm = np.sqrt(line[0, 3] ** 2 + line[0, 4] ** 2 + line[0, 5] ** 2 + line[0, 6] ** 2)
        for m in range(3, 7):
            line[0, m] /= norm
        _pose_from_base(line[0], Mb, db)
    for m in range(tau.shape[1]):
        x = tau[0, m] if hold else (1 - w) * tau[i, m] + w * tau[i1, m]
        if on:
            x -= friction_at(motor, m, v[m])
        line[3, m] = x
    # first pass (module docstring): frames, velocities, accelerations, inertias and forces
    for i in range(6):
        vel[0, i] = 0.0
        acc[0, i] = 0.0
    for i in range(3):
        acc[0, i] = -gravity[i]
        p[0, i] = 0.0
        for k in range(3):
            R[0, i, k] = 1.0 if i == k else 0.0
    for j in range(1, nj):
        pa, kind, col = parents[j], kinds[j], columns[j]
        # B = R_pa·PR; p_j = p_pa + R_pa·Pp (+ B·d)
        for i in range(3):
            for k in range(3):
                B[i, k] = (
                    R[pa, i, 0] * PR[j, 0, k]
                    + R[pa, i, 1] * PR[j, 1, k]
                    + R[pa, i, 2] * PR[j, 2, k]
                )
            p[j, i] = (
                p[pa, i] + R[pa, i, 0] * Pp[j, 0] + R[pa, i, 1] * Pp[j, 1] + R[pa, i, 2] * Pp[j, 2]
            )
        x, y, z = axes[j, 0], axes[j, 1], axes[j, 2]
        if kind == FREEFLYER:  # R_j = B·Mb, p_j += B·db; its motion the prescribed base's
            for i in range(3):
                for k in range(3):
                    R[j, i, k] = B[i, 0] * Mb[0, k] + B[i, 1] * Mb[1, k] + B[i, 2] * Mb[2, k]
                p[j, i] += B[i, 0] * db[0] + B[i, 1] * db[1] + B[i, 2] * db[2]
            for row in (2, 3):
                motion = vel if row == 2 else acc
                for i in range(3):
                    motion[j, 3 + i] = (
                        R[j, i, 0] * line[row - 1, 3]
                        + R[j, i, 1] * line[row - 1, 4]
                        + R[j, i, 2] * line[row - 1, 5]
                    )
                    motion[j, i] = (
                        R[j, i, 0] * line[row - 1, 0]
                        + R[j, i, 1] * line[row - 1, 1]
                        + R[j, i, 2] * line[row - 1, 2]
                    )
                motion[j, 0] += p[j, 1] * motion[j, 5] - p[j, 2] * motion[j, 4]
                motion[j, 1] += p[j, 2] * motion[j, 3] - p[j, 0] * motion[j, 5]
                motion[j, 2] += p[j, 0] * motion[j, 4] - p[j, 1] * motion[j, 3]
                for i in range(6):  # its parent the universe, at rest (flatten_dynamics)
                    motion[j, i] += motion[pa, i]
            continue
        # the axis in the world, B·k (a rotation about k leaves k)
        e0 = B[0, 0] * x + B[0, 1] * y + B[0, 2] * z
        e1 = B[1, 0] * x + B[1, 1] * y + B[1, 2] * z
        e2 = B[2, 0] * x + B[2, 1] * y + B[2, 2] * z
        angle = q[col]
        if kind == REVOLUTE:  # R_j = B·rotation(k, q) (Rodrigues)
            c, s = np.cos(angle), np.sin(angle)
            t = 1.0 - c
            for i in range(3):
                b0, b1, b2 = B[i, 0], B[i, 1], B[i, 2]
                R[j, i, 0] = (
                    b0 * (c + x * x * t) + b1 * (y * x * t + z * s) + b2 * (z * x * t - y * s)
                )
                R[j, i, 1] = (
                    b0 * (x * y * t - z * s) + b1 * (c + y * y * t) + b2 * (z * y * t + x * s)
                )
                R[j, i, 2] = (
                    b0 * (x * z * t + y * s) + b1 * (y * z * t - x * s) + b2 * (c + z * z * t)
                )
            S[j, 3], S[j, 4], S[j, 5] = e0, e1, e2
            S[j, 0] = p[j, 1] * e2 - p[j, 2] * e1
            S[j, 1] = p[j, 2] * e0 - p[j, 0] * e2
            S[j, 2] = p[j, 0] * e1 - p[j, 1] * e0
        else:  # prismatic: R_j = B, p_j += axis·q
            for i in range(3):
                for k in range(3):
                    R[j, i, k] = B[i, k]
            p[j, 0] += e0 * angle
            p[j, 1] += e1 * angle
            p[j, 2] += e2 * angle
            S[j, 0], S[j, 1], S[j, 2] = e0, e1, e2
            S[j, 3], S[j, 4], S[j, 5] = 0.0, 0.0, 0.0
        # v_j = v_pa + S·qd; a_j = a_pa + v_pa × S·qd
        qd = v[col]
        j0, j1, j2 = S[j, 0] * qd, S[j, 1] * qd, S[j, 2] * qd
        j3, j4, j5 = S[j, 3] * qd, S[j, 4] * qd, S[j, 5] * qd
        w0, w1, w2 = vel[pa, 3], vel[pa, 4], vel[pa, 5]
        l0, l1, l2 = vel[pa, 0], vel[pa, 1], vel[pa, 2]
        vel[j, 0], vel[j, 1], vel[j, 2] = l0 + j0, l1 + j1, l2 + j2
        vel[j, 3], vel[j, 4], vel[j, 5] = w0 + j3, w1 + j4, w2 + j5
        acc[j, 0] = acc[pa, 0] + w1 * j2 - w2 * j1 + l1 * j5 - l2 * j4
        acc[j, 1] = acc[pa, 1] + w2 * j0 - w0 * j2 + l2 * j3 - l0 * j5
        acc[j, 2] = acc[pa, 2] + w0 * j1 - w1 * j0 + l0 * j4 - l1 * j3
        acc[j, 3] = acc[pa, 3] + w1 * j5 - w2 * j4
        acc[j, 4] = acc[pa, 4] + w2 * j3 - w0 * j5
        acc[j, 5] = acc[pa, 5] + w0 * j4 - w1 * j3
        # m, h = m·c, J = R·Ic·Rᵀ + m(|c|²1 - c·cᵀ)
        m = mass[j]
        c0 = (
            p[j, 0] + R[j, 0, 0] * lever[j, 0] + R[j, 0, 1] * lever[j, 1] + R[j, 0, 2] * lever[j, 2]
        )
        c1 = (
            p[j, 1] + R[j, 1, 0] * lever[j, 0] + R[j, 1, 1] * lever[j, 1] + R[j, 1, 2] * lever[j, 2]
        )
        c2 = (
            p[j, 2] + R[j, 2, 0] * lever[j, 0] + R[j, 2, 1] * lever[j, 1] + R[j, 2, 2] * lever[j, 2]
        )
        for i in range(3):
            for k in range(3):
                Rot[i, k] = (
                    R[j, i, 0] * Ic[j, 0, k] + R[j, i, 1] * Ic[j, 1, k] + R[j, i, 2] * Ic[j, 2, k]
                )
        mc = m * (c0 * c0 + c1 * c1 + c2 * c2)
        for i in range(3):
            ci = c0 if i == 0 else (c1 if i == 1 else c2)
            for k in range(i, 3):
                ck = c0 if k == 0 else (c1 if k == 1 else c2)
                value = Rot[i, 0] * R[j, k, 0] + Rot[i, 1] * R[j, k, 1] + Rot[i, 2] * R[j, k, 2]
                value -= m * ci * ck
                if i == k:
                    value += mc
                IA[j, 3 + i, 3 + k] = value
                IA[j, 3 + k, 3 + i] = value
            for k in range(3):
                IA[j, i, k] = m if i == k else 0.0
        h0, h1, h2 = m * c0, m * c1, m * c2
        IA[j, 0, 3], IA[j, 1, 4], IA[j, 2, 5] = 0.0, 0.0, 0.0
        IA[j, 3, 0], IA[j, 4, 1], IA[j, 5, 2] = 0.0, 0.0, 0.0
        IA[j, 0, 4], IA[j, 0, 5], IA[j, 1, 5] = h2, -h1, h0
        IA[j, 1, 3], IA[j, 2, 3], IA[j, 2, 4] = -h2, h1, -h0
        IA[j, 4, 0], IA[j, 5, 0], IA[j, 5, 1] = h2, -h1, h0
        IA[j, 3, 1], IA[j, 3, 2], IA[j, 4, 2] = -h2, h1, -h0
        # f = I·a + v ×* (I·v)
        l0, l1, l2 = vel[j, 0], vel[j, 1], vel[j, 2]
        w0, w1, w2 = vel[j, 3], vel[j, 4], vel[j, 5]
        n0 = m * l0 + w1 * h2 - w2 * h1  # I·v, linear
        n1 = m * l1 + w2 * h0 - w0 * h2
        n2 = m * l2 + w0 * h1 - w1 * h0
        k0 = IA[j, 3, 3] * w0 + IA[j, 3, 4] * w1 + IA[j, 3, 5] * w2 + h1 * l2 - h2 * l1  # angular
        k1 = IA[j, 4, 3] * w0 + IA[j, 4, 4] * w1 + IA[j, 4, 5] * w2 + h2 * l0 - h0 * l2
        k2 = IA[j, 5, 3] * w0 + IA[j, 5, 4] * w1 + IA[j, 5, 5] * w2 + h0 * l1 - h1 * l0
        for i in range(6):
            value = 0.0
            for k in range(6):
                value += IA[j, i, k] * acc[j, k]
            f[j, i] = value
        f[j, 0] += w1 * n2 - w2 * n1
        f[j, 1] += w2 * n0 - w0 * n2
        f[j, 2] += w0 * n1 - w1 * n0
        f[j, 3] += w1 * k2 - w2 * k1 + l1 * n2 - l2 * n1
        f[j, 4] += w2 * k0 - w0 * k2 + l2 * n0 - l0 * n2
        f[j, 5] += w0 * k1 - w1 * k0 + l0 * n1 - l1 * n0
    # second pass: articulated inertias and forces into the parents
    for j in range(nj - 1, 0, -1):
        if kinds[j] == FREEFLYER:
            continue
        col = columns[j]
        D = 0.0
        bias = 0.0
        for i in range(6):
            x = 0.0
            for k in range(6):
                x += IA[j, i, k] * S[j, k]
            U[j, i] = x
            D += S[j, i] * x
            bias += S[j, i] * f[j, i]
        if on:
            D += rotor[col]
        inverse = 1.0 / D
        uj = line[3, col] - bias
        Dinv[j] = inverse
        u[j] = uj
        pa = parents[j]
        if pa > 0 and kinds[pa] != FREEFLYER:
            for i in range(6):
                w = U[j, i] * inverse
                for k in range(6):
                    IA[pa, i, k] += IA[j, i, k] - w * U[j, k]
                f[pa, i] += f[j, i] + w * uj
    for i in range(6):
        da[0, i] = 0.0
    for j in range(1, nj):
        pa = parents[j]
        if kinds[j] == FREEFLYER:
            for i in range(6):
                da[j, i] = 0.0
            continue
        x = u[j]
        for i in range(6):
            x -= U[j, i] * da[pa, i]
        qdd = x * Dinv[j]
        out[columns[j]] = qdd
        for i in range(6):
            da[j, i] = da[pa, i] + S[j, i] * qdd


@kernel(exact=True)
def articulated_stops(model, q, v, stop, articulated, out):  # type: ignore[no-untyped-def]  # pragma: no cover
    """Adds to ``out`` the accelerations of the stops' torques, after :func:`articulated_at`.

    ``stop`` as :func:`~aaria_pin.core._forward_kernel.joint_accelerations` takes it. A joint
    beyond its stops gets their torque (:func:`~aaria_pin.core.forward.stop_torques`) with its
    effective inertia ``1 / (M⁻¹)_ii``: the column ``M⁻¹·e_i`` from the second and third passes
    again with the torque ``e_i`` and no bias (the articulated inertias stay), and the
    accelerations move by the stop's torque times that column. Inside its stops a run is the
    run without them, bit for bit.
    """
    kinds, parents, columns = model[0], model[2], model[3]
    U, Dinv, u, da, S, f, line = (
        articulated[1],
        articulated[2],
        articulated[3],
        articulated[4],
        articulated[7],
        articulated[10],
        articulated[14],
    )
    lower, upper, omega = stop[1], stop[2], stop[3]
    nj, n = kinds.shape[0], q.shape[0]
    for m in range(n):
        x = q[m]
        if x >= lower[m] and x <= upper[m]:
            continue
        edge = lower[m] if x < lower[m] else upper[m]
        for j in range(nj):  # M⁻¹·e_m into line[3]: the passes with the torque e_m, no bias
            for i in range(6):
                f[j, i] = 0.0
        for j in range(nj - 1, 0, -1):
            if kinds[j] == FREEFLYER:
                continue
            uj = 1.0 if columns[j] == m else 0.0
            for i in range(6):
                uj -= S[j, i] * f[j, i]
            u[j] = uj
            pa = parents[j]
            if pa > 0 and kinds[pa] != FREEFLYER:
                for i in range(6):
                    f[pa, i] += f[j, i] + U[j, i] * Dinv[j] * uj
        for j in range(1, nj):
            pa = parents[j]
            if kinds[j] == FREEFLYER:
                for i in range(6):
                    da[j, i] = 0.0
                continue
            y = u[j]
            for i in range(6):
                y -= U[j, i] * da[pa, i]
            y *= Dinv[j]
            line[3, columns[j]] = y
            for i in range(6):
                da[j, i] = da[pa, i] + S[j, i] * y
        inertia = 1.0 / line[3, m]
        torque = -inertia * omega * omega * (x - edge) - 2 * inertia * omega * v[m]
        for c in range(n):
            out[c] += torque * line[3, c]
