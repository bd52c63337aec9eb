"""Compiled (numba) kernel of the trajectory kinematics: one pass over samples and joints.

The model is flattened into arrays (joint kinds, axes, parents, placements; frame parents and
placements) so the kernel knows nothing of Pinocchio. For every sample it runs the forward pass
in each joint's own axes, as Pinocchio does: angular velocity ``w``, angular acceleration ``al``
and proper acceleration ``f`` (classical acceleration minus gravity) of each joint frame, plus
its world rotation and position; then it reads the requested frames off their joints.

The trajectory kernels (:func:`sine_columns`, :func:`base_kinematics` and its
:func:`_gimbal`) and the noise pass (:func:`measure_noise`) replaced numpy array code
whose numbers the 0.1 fixtures hold: they are compiled ``exact`` (no fastmath), repeat its
operations in its order, and call ``sin``/``cos``, which on the project's machine give numpy's
numbers bit for bit (4 million arguments up to 10⁵ rad checked; ``tests/core/
test_trajectory_kernels.py`` holds each kernel equal to the array code). On a machine where
numpy's ``sin``/``cos`` took another path (e.g. a SIMD library numba does not use), those
last bits could differ and the fixture tests would say so.

The kernels are compiled on first use and cached on disk, once per install; a first compile says
so on stderr (:func:`aaria_pin.core._compile.kernel`).
"""

from __future__ import annotations

import numpy as np

from aaria_pin.core._compile import kernel

REVOLUTE, PRISMATIC, FREEFLYER = 0, 1, 2


@kernel
def _rotation(axis: np.ndarray, angle: float, out: np.ndarray) -> None:  # pragma: no cover
    """Rotation matrix about a unit axis (Rodrigues)."""
    c, s = np.cos(angle), np.sin(angle)
    x, y, z = axis[0], axis[1], axis[2]
    v = 1.0 - c
    out[0, 0] = c + x * x * v
    out[0, 1] = x * y * v - z * s
    out[0, 2] = x * z * v + y * s
    out[1, 0] = y * x * v + z * s
    out[1, 1] = c + y * y * v
    out[1, 2] = y * z * v - x * s
    out[2, 0] = z * x * v - y * s
    out[2, 1] = z * y * v + x * s
    out[2, 2] = c + z * z * v


@kernel
def trajectory_kinematics(  # type: ignore[no-untyped-def]  # pragma: no cover
    kinds,
    axes,
    parents,
    columns,
    placement_R,
    placement_p,
    q,
    qd,
    qdd,
    base_R,
    base_p,
    base_w,
    base_wd,
    base_a,
    gravity,
    imu_joint,
    imu_R,
    imu_p,
    imu_slot,
    imu_out,
    pose_joint,
    pose_R,
    pose_p,
    pose_out,
):
    """Fill ``imu_out[:, imu_slot]`` (T, ·, 6) and ``pose_out`` (T, P, 4, 4) for every sample.

    Joint 0 is the universe; ``kinds[j]`` is REVOLUTE, PRISMATIC or FREEFLYER (whose motion is
    the base's: ``base_R`` (T, 3, 3), ``base_p`` (T, 3), body rates ``base_w``/``base_wd``
    (T, 3) and world acceleration ``base_a`` (T, 3)).
    """
    n_joints = kinds.shape[0]
    # per joint: w (0:3), al (3:6), f (6:9) in its own axes; world R (9:18, row-major), p (18:21)
    S = np.zeros((n_joints, 21))
    M = np.empty((3, 3))
    Rot = np.empty((3, 3))
    d = np.empty(3)
    g = np.empty(3)
    for i in range(3):  # the universe: at rest, proper acceleration -g
        S[0, 6 + i] = -gravity[i]
        S[0, 9 + 4 * i] = 1.0
    for t in range(q.shape[0]):
        for j in range(1, n_joints):
            kind = kinds[j]
            if kind == FREEFLYER:
                for i in range(3):
                    S[j, i] = base_w[t, i]
                    S[j, 3 + i] = base_wd[t, i]
                    S[j, 18 + i] = base_p[t, i]
                    acc = 0.0
                    for k in range(3):
                        S[j, 9 + 3 * i + k] = base_R[t, i, k]
                        acc += base_R[t, k, i] * (base_a[t, k] - gravity[k])
                    S[j, 6 + i] = acc
                continue
            pa = parents[j]
            column = columns[j]
            qj, qdj, qddj = q[t, column], qd[t, column], qdd[t, column]
            k0, k1, k2 = axes[j, 0], axes[j, 1], axes[j, 2]
            # M: the joint frame in the parent frame; d: its origin in the parent frame
            if kind == REVOLUTE:
                _rotation(axes[j], qj, Rot)
                for i in range(3):
                    for k in range(3):
                        M[i, k] = (
                            placement_R[j, i, 0] * Rot[0, k]
                            + placement_R[j, i, 1] * Rot[1, k]
                            + placement_R[j, i, 2] * Rot[2, k]
                        )
                    d[i] = placement_p[j, i]
            else:
                for i in range(3):
                    for k in range(3):
                        M[i, k] = placement_R[j, i, k]
                    e = (
                        placement_R[j, i, 0] * k0
                        + placement_R[j, i, 1] * k1
                        + placement_R[j, i, 2] * k2
                    )
                    d[i] = placement_p[j, i] + e * qj
            wp0, wp1, wp2 = S[pa, 0], S[pa, 1], S[pa, 2]
            ap0, ap1, ap2 = S[pa, 3], S[pa, 4], S[pa, 5]
            # proper acceleration at the joint origin, parent axes: f + al × d + w × (w × d)
            c0 = wp1 * d[2] - wp2 * d[1]
            c1 = wp2 * d[0] - wp0 * d[2]
            c2 = wp0 * d[1] - wp1 * d[0]
            g[0] = S[pa, 6] + ap1 * d[2] - ap2 * d[1] + wp1 * c2 - wp2 * c1
            g[1] = S[pa, 7] + ap2 * d[0] - ap0 * d[2] + wp2 * c0 - wp0 * c2
            g[2] = S[pa, 8] + ap0 * d[1] - ap1 * d[0] + wp0 * c1 - wp1 * c0
            if kind == PRISMATIC:  # Coriolis and the joint's own acceleration, along e = C·k
                e0 = (
                    placement_R[j, 0, 0] * k0
                    + placement_R[j, 0, 1] * k1
                    + placement_R[j, 0, 2] * k2
                )
                e1 = (
                    placement_R[j, 1, 0] * k0
                    + placement_R[j, 1, 1] * k1
                    + placement_R[j, 1, 2] * k2
                )
                e2 = (
                    placement_R[j, 2, 0] * k0
                    + placement_R[j, 2, 1] * k1
                    + placement_R[j, 2, 2] * k2
                )
                g[0] += 2.0 * (wp1 * e2 - wp2 * e1) * qdj + e0 * qddj
                g[1] += 2.0 * (wp2 * e0 - wp0 * e2) * qdj + e1 * qddj
                g[2] += 2.0 * (wp0 * e1 - wp1 * e0) * qdj + e2 * qddj
            for i in range(3):  # into the joint's axes: Mᵀ · (parent quantities)
                S[j, i] = M[0, i] * wp0 + M[1, i] * wp1 + M[2, i] * wp2
                S[j, 3 + i] = M[0, i] * ap0 + M[1, i] * ap1 + M[2, i] * ap2
                S[j, 6 + i] = M[0, i] * g[0] + M[1, i] * g[1] + M[2, i] * g[2]
            if kind == REVOLUTE:
                w0, w1, w2 = S[j, 0], S[j, 1], S[j, 2]
                v0, v1, v2 = k0 * qdj, k1 * qdj, k2 * qdj
                S[j, 3] += k0 * qddj + w1 * v2 - w2 * v1
                S[j, 4] += k1 * qddj + w2 * v0 - w0 * v2
                S[j, 5] += k2 * qddj + w0 * v1 - w1 * v0
                S[j, 0] += v0
                S[j, 1] += v1
                S[j, 2] += v2
            for i in range(3):  # world pose: R = R_parent · M, p = p_parent + R_parent · d
                r0, r1, r2 = S[pa, 9 + 3 * i], S[pa, 10 + 3 * i], S[pa, 11 + 3 * i]
                S[j, 18 + i] = S[pa, 18 + i] + r0 * d[0] + r1 * d[1] + r2 * d[2]
                for k in range(3):
                    S[j, 9 + 3 * i + k] = r0 * M[0, k] + r1 * M[1, k] + r2 * M[2, k]
        for index in range(imu_joint.shape[0]):
            j = imu_joint[index]
            slot = imu_slot[index]
            r0, r1, r2 = imu_p[index, 0], imu_p[index, 1], imu_p[index, 2]
            w0, w1, w2 = S[j, 0], S[j, 1], S[j, 2]
            a0, a1, a2 = S[j, 3], S[j, 4], S[j, 5]
            c0 = w1 * r2 - w2 * r1
            c1 = w2 * r0 - w0 * r2
            c2 = w0 * r1 - w1 * r0
            g[0] = S[j, 6] + a1 * r2 - a2 * r1 + w1 * c2 - w2 * c1
            g[1] = S[j, 7] + a2 * r0 - a0 * r2 + w2 * c0 - w0 * c2
            g[2] = S[j, 8] + a0 * r1 - a1 * r0 + w0 * c1 - w1 * c0
            for i in range(3):
                C0, C1, C2 = imu_R[index, 0, i], imu_R[index, 1, i], imu_R[index, 2, i]
                imu_out[t, slot, i] = C0 * w0 + C1 * w1 + C2 * w2
                imu_out[t, slot, 3 + i] = C0 * g[0] + C1 * g[1] + C2 * g[2]
        for index in range(pose_joint.shape[0]):
            j = pose_joint[index]
            for i in range(3):
                r0, r1, r2 = S[j, 9 + 3 * i], S[j, 10 + 3 * i], S[j, 11 + 3 * i]
                pose_out[t, index, i, 3] = (
                    S[j, 18 + i]
                    + r0 * pose_p[index, 0]
                    + r1 * pose_p[index, 1]
                    + r2 * pose_p[index, 2]
                )
                for k in range(3):
                    pose_out[t, index, i, k] = (
                        r0 * pose_R[index, 0, k]
                        + r1 * pose_R[index, 1, k]
                        + r2 * pose_R[index, 2, k]
                    )
                pose_out[t, index, 3, i] = 0.0
            pose_out[t, index, 3, 3] = 1.0


@kernel
def free_flyer_state(  # type: ignore[no-untyped-def]  # pragma: no cover
    base_R, base_p, base_v, base_a, base_w, base_wd, q_out, v_out, a_out
):
    """Pinocchio's free-flyer entries of q, v, a for every sample.

    ``q = [p, quat xyzw]`` (Shepperd's method, w >= 0), ``v = [Rᵀṗ, ω]``,
    ``a = [Rᵀp̈ - ω × Rᵀṗ, ω̇]``, from the base rotation, position, world velocity and
    acceleration and body angular velocity and acceleration.
    """
    for t in range(base_R.shape[0]):
        R = base_R[t]
        trace = R[0, 0] + R[1, 1] + R[2, 2]
        if trace >= R[0, 0] and trace >= R[1, 1] and trace >= R[2, 2]:
            root = np.sqrt(1.0 + trace)
            half = 0.5 / root
            x, y, z, w = (
                (R[2, 1] - R[1, 2]) * half,
                (R[0, 2] - R[2, 0]) * half,
                (R[1, 0] - R[0, 1]) * half,
                0.5 * root,
            )
        elif R[0, 0] >= R[1, 1] and R[0, 0] >= R[2, 2]:
            root = np.sqrt(1.0 + 2.0 * R[0, 0] - trace)
            half = 0.5 / root
            x, y, z, w = (
                0.5 * root,
                (R[1, 0] + R[0, 1]) * half,
                (R[0, 2] + R[2, 0]) * half,
                (R[2, 1] - R[1, 2]) * half,
            )
        elif R[1, 1] >= R[2, 2]:
            root = np.sqrt(1.0 + 2.0 * R[1, 1] - trace)
            half = 0.5 / root
            x, y, z, w = (
                (R[1, 0] + R[0, 1]) * half,
                0.5 * root,
                (R[2, 1] + R[1, 2]) * half,
                (R[0, 2] - R[2, 0]) * half,
            )
        else:
            root = np.sqrt(1.0 + 2.0 * R[2, 2] - trace)
            half = 0.5 / root
            x, y, z, w = (
                (R[0, 2] + R[2, 0]) * half,
                (R[2, 1] + R[1, 2]) * half,
                0.5 * root,
                (R[1, 0] - R[0, 1]) * half,
            )
        sign = -1.0 if w < 0.0 else 1.0
        q_out[t, 0], q_out[t, 1], q_out[t, 2] = base_p[t, 0], base_p[t, 1], base_p[t, 2]
        q_out[t, 3], q_out[t, 4], q_out[t, 5], q_out[t, 6] = sign * x, sign * y, sign * z, sign * w
        w0, w1, w2 = base_w[t, 0], base_w[t, 1], base_w[t, 2]
        u0 = R[0, 0] * base_v[t, 0] + R[1, 0] * base_v[t, 1] + R[2, 0] * base_v[t, 2]
        u1 = R[0, 1] * base_v[t, 0] + R[1, 1] * base_v[t, 1] + R[2, 1] * base_v[t, 2]
        u2 = R[0, 2] * base_v[t, 0] + R[1, 2] * base_v[t, 1] + R[2, 2] * base_v[t, 2]
        v_out[t, 0], v_out[t, 1], v_out[t, 2] = u0, u1, u2
        v_out[t, 3], v_out[t, 4], v_out[t, 5] = w0, w1, w2
        for i in range(3):
            a_out[t, i] = R[0, i] * base_a[t, 0] + R[1, i] * base_a[t, 1] + R[2, i] * base_a[t, 2]
            a_out[t, 3 + i] = base_wd[t, i]
        a_out[t, 0] -= w1 * u2 - w2 * u1
        a_out[t, 1] -= w2 * u0 - w0 * u2
        a_out[t, 2] -= w0 * u1 - w1 * u0


@kernel(exact=True)
def _sine(A, bias, w, phase, now):  # type: ignore[no-untyped-def]  # pragma: no cover
    """``A·sin(w·t + phase) + bias`` and its two derivatives at ``t = now``: the one formula.

    The operations, their order and their roundings are those of the numpy expressions the
    kernels replaced (``t·w + phase``; ``A·s + bias``; ``c·(A·w)``; ``s·((-A)·w·w)``).
    """
    angle = now * w + phase
    s = np.sin(angle)
    c = np.cos(angle)
    return A * s + bias, c * (A * w), s * (-A * w * w)


@kernel(exact=True)
def sine_columns(  # type: ignore[no-untyped-def]  # pragma: no cover
    amplitude, bias, frequency, phase, time, value, velocity, acceleration
):
    """``A·sin(w·t + phase) + bias`` and its two derivatives, (T, k) each, into the outputs.

    The operations, their order and their roundings are those of the numpy expressions this
    replaced (``t·w + phase``; ``A·s + bias``; ``c·(A·w)``; ``s·((-A)·w·w)``), and numba's
    ``sin``/``cos`` give numpy's numbers on the project's machine (checked on 4 million
    arguments up to 10⁵ rad), so the values are bit for bit those of the array code.
    """
    k_count = amplitude.shape[0]
    for t in range(time.shape[0]):
        now = time[t]
        for k in range(k_count):
            value[t, k], velocity[t, k], acceleration[t, k] = _sine(
                amplitude[k], bias[k], frequency[k], phase[k], now
            )


@kernel(exact=True)
def base_kinematics(  # type: ignore[no-untyped-def]  # pragma: no cover
    amplitude,
    bias,
    frequency,
    phase,
    time,
    position,
    velocity,
    acceleration,
    rotation,
    omega,
    omega_dot,
):
    """The base's sine motion along x, y, z and through X-Y-Z gimbal angles, per sample.

    Rows 0–2 of the (6,) parameters move the origin, rows 3–5 turn the gimbal
    (``R = Rx·Ry·Rz``, body rates): every value goes straight into its (T, 3) or (T, 3, 3)
    output. The expressions are those of :func:`sine_columns` and of
    ``trajectory.gimbal_xyz_motion`` written per sample, in the same order, so the numbers
    are the same bit for bit.
    """
    gimbal = np.empty(9)
    for t in range(time.shape[0]):
        now = time[t]
        for k in range(3):
            position[t, k], velocity[t, k], acceleration[t, k] = _sine(
                amplitude[k], bias[k], frequency[k], phase[k], now
            )
        for k in range(3, 6):  # the gimbal angles, rates and accelerations
            gimbal[k - 3], gimbal[k], gimbal[k + 3] = _sine(
                amplitude[k], bias[k], frequency[k], phase[k], now
            )
        _gimbal(
            gimbal[0],
            gimbal[1],
            gimbal[2],
            gimbal[3],
            gimbal[4],
            gimbal[5],
            gimbal[6],
            gimbal[7],
            gimbal[8],
            rotation[t],
            omega[t],
            omega_dot[t],
        )


@kernel(exact=True)
def _gimbal(  # type: ignore[no-untyped-def]  # pragma: no cover
    ax, ay, az, xd, yd, zd, xdd, ydd, zdd, R, omega, omega_dot
):
    """``R = Rx(ax)·Ry(ay)·Rz(az)``, body angular velocity and acceleration of one sample.

    Term for term the array expressions of ``trajectory.gimbal_xyz_motion`` (same operands,
    same order, ``cx·0 - sx·cy`` kept as written: it is ``-0.0``-exact), so the same numbers.
    """
    cx, sx = np.cos(ax), np.sin(ax)
    cy, sy = np.cos(ay), np.sin(ay)
    cz, sz = np.cos(az), np.sin(az)
    R[0, 0] = cy * cz
    R[0, 1] = -cy * sz
    R[0, 2] = sy
    r20 = -sy * cz
    r21 = sy * sz
    R[1, 0] = cx * sz - sx * r20
    R[1, 1] = cx * cz - sx * r21
    R[1, 2] = cx * 0.0 - sx * cy
    R[2, 0] = sx * sz + cx * r20
    R[2, 1] = sx * cz + cx * r21
    R[2, 2] = sx * 0.0 + cx * cy
    omega[0] = cy * cz * xd + sz * yd
    omega[1] = -cy * sz * xd + cz * yd
    omega[2] = sy * xd + zd
    omega_dot[0] = cy * cz * xdd + sz * ydd - (sy * cz * yd + cy * sz * zd) * xd + cz * zd * yd
    omega_dot[1] = -cy * sz * xdd + cz * ydd + (sy * sz * yd - cy * cz * zd) * xd - sz * zd * yd
    omega_dot[2] = sy * xdd + zdd + cy * yd * xd


@kernel(exact=True)
def measure_noise(  # type: ignore[no-untyped-def]  # pragma: no cover
    measured, exact, bias, change, start, step, white, full_scale, lsb
):
    """Standard normals to IMU measurements in place, (m, n_imu·6), per element.

    For sample ``i = start + row = k·step + r`` and column ``j``:
    ``round(clip(x·white + exact + (Δ[k]·(r/step) + b[k]), ±full_scale) / lsb)·lsb`` with
    ``x`` the standard normal held in ``measured``, ``b`` the bias knots and ``Δ`` their steps:
    the operations and their order of ``imu_noise._measure``'s array code, so its numbers
    bit for bit (``rint`` is numpy's ``round`` to even).
    """
    columns = measured.shape[1]
    for row in range(measured.shape[0]):
        index = start + row
        knot = index // step
        fraction = (index - knot * step) / step
        for j in range(columns):
            value = measured[row, j] * white[j] + exact[row, j]
            value += change[knot, j] * fraction + bias[knot, j]
            limit = full_scale[j]
            if value > limit:
                value = limit
            if value < -limit:
                value = -limit
            measured[row, j] = np.rint(value / lsb[j]) * lsb[j]
