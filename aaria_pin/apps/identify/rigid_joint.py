"""Two rigid bodies joined by an unknown joint, one IMU on each: the joint's type, axis and place.

For robots whose joints have no encoders (simulated recordings:
:func:`~aaria_pin.apps.identify.rigid_joint_motion.simulate_jointed_bodies`).
:func:`identify_joint` finds, from the two IMUs' signals (one clock), without the joint's
values:

* the type: the two gyroscopes related by one constant rotation (Kabsch residual at the noise)
  is a rigid or prismatic link (then the accelerometers after the lever arm's fit tell which:
  a slide leaves a residual along its axis); else revolute;
* a revolute joint's axis in both IMUs' frames by the hinge constraint (Seel, Raisch, Schauer
  2012): the angular velocity's part across the axis has one norm on both sides,
  ``|ω_A × j_A| = |ω_B × j_B|``; and its position: the point on the axis has one acceleration
  seen from both sides, ``|f_A + Γ_A(o_A)| = |f_B + Γ_B(o_B)|`` with
  ``Γ(o) = ω×(ω×o) + ω̇×o``, then moved along the axis to the point nearest the two IMUs
  (a point along the axis is not determined);
* a prismatic joint's axis in A's frame: the principal direction of what the rigid lever arm
  leaves of B's specific force (the slide's acceleration ``q̈·u`` dominates it).

Both IMUs' signals are smoothed by a least-squares cubic B-spline (knots 0.02 s apart) and read
at A's stamps, so rates may differ; the clocks are taken as one (a time offset, if any, from
:func:`~aaria_pin.apps.identify.rigid.identify_rigid` on a rigid pair of the same recording).
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from aaria_pin.apps.identify.rigid import (
    UNDETERMINED,
    Signals,
    identify_rigid,
    imu_signals,
    rotation_between,
)
from aaria_pin.apps.identify.rigid_fit import blockwise, lever_matrices, skew_rows
from aaria_pin.apps.identify.rigid_spline import coefficient_count, fit_spline, spline_basis
from aaria_pin.core.arguments import checked
from aaria_pin.core.recording import RecordedRun
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = ["RIGID_RATIO", "SLIDE_RATIO", "JointFit", "identify_chain", "identify_joint"]

RIGID_RATIO = 5.0
"""A gyroscope residual of the constant-rotation fit below this many times the gyroscopes' own
noise is a link whose rotation does not change (rigid or prismatic)."""


SLIDE_RATIO = 3.0
"""B's accelerometer residual of the rigid pair fit (:func:`~aaria_pin.apps.identify.rigid.
identify_rigid`) over A's above which a link that does not turn slides (prismatic)."""


@dataclass(frozen=True)
class JointFit:
    """A joint found from two IMUs.

    Attributes:
        imu_a: the IMU on body 1
        imu_b: the IMU on body 2
        kind: ``rigid``, ``revolute`` or ``prismatic``
        axis_a: (3,) the axis in A's frame (rigid: zeros)
        axis_b: (3,) the axis in B's frame (prismatic: A's axis turned into B's)
        point_a: (3,) the revolute axis' point nearest the IMUs, in A's frame [m] (rigid: B's
            origin in A's frame; prismatic: zeros)
        point_b: (3,) the same point in B's frame [m]
        gyro_noise: the gyroscopes' noise, from their spline fits [rad/s]
        rigid_residual: the constant-rotation fit's gyroscope residual RMS [rad/s]
        hinge_residual: the hinge constraint's residual RMS [rad/s] (revolute)
        axis_sigma: (2,) σ of the revolute axis' direction in A's and B's frames [rad]
        point_sigma: (2,) σ of the point across the axis in A's and B's frames [m]
    """

    imu_a: str
    imu_b: str
    kind: str
    axis_a: Array
    axis_b: Array
    point_a: Array
    point_b: Array
    gyro_noise: float
    rigid_residual: float
    hinge_residual: float
    axis_sigma: Array = field(default_factory=lambda: np.zeros(2))
    point_sigma: Array = field(default_factory=lambda: np.zeros(2))

    def lines(self) -> list[str]:
        """The result as text lines."""

        def vec(v: Array, scale: float = 1.0) -> str:
            return " ".join(f"{x * scale:+.4f}" for x in v)

        lines = [
            f"joint {self.imu_a} -> {self.imu_b}: {self.kind} (gyro residual of one constant "
            f"rotation {self.rigid_residual:.3g} rad/s, noise {self.gyro_noise:.3g} rad/s)"
        ]
        if self.kind == "rigid":
            lines.append(
                f"  origin of {self.imu_b} in {self.imu_a} [mm]: [{vec(self.point_a, 1e3)}]"
            )
        else:
            lines.append(
                f"  axis in {self.imu_a}: [{vec(self.axis_a)}], in {self.imu_b}: "
                f"[{vec(self.axis_b)}]"
            )
        if self.kind == "revolute":
            deg, mm = np.degrees(self.axis_sigma), self.point_sigma * 1e3
            lines += [
                f"  axis sigma [deg]: {deg[0]:.3g} in {self.imu_a}, {deg[1]:.3g} in {self.imu_b}",
                f"  point on the axis [mm] in {self.imu_a}: [{vec(self.point_a, 1e3)}], in "
                f"{self.imu_b}: [{vec(self.point_b, 1e3)}] (sigma across the axis {mm[0]:.3g}, "
                f"{mm[1]:.3g}; along the axis: not determined)",
            ]
            lines += [f"  not determined: {text}" for text in self.undetermined]
        return lines

    @property
    def undetermined(self) -> tuple[str, ...]:
        """What of a revolute joint the motion did not show, one sentence each.

        The axis or the point whose σ exceeds the rotation or position of
        :data:`~aaria_pin.apps.identify.rigid.UNDETERMINED`.
        """
        if self.kind != "revolute":
            return ()
        texts = []
        if self.axis_sigma.max() > UNDETERMINED["rotation"]:
            texts.append(f"the axis (sigma {np.degrees(self.axis_sigma.max()):.2g} deg)")
        if self.point_sigma.max() > UNDETERMINED["position"]:
            texts.append(f"the point on the axis (sigma {self.point_sigma.max() * 1e3:.3g} mm)")
        return tuple(texts)

    def to_json(self) -> dict[str, object]:
        """The result as JSON-ready values (SI units in the keys)."""
        return {
            "imu_a": self.imu_a,
            "imu_b": self.imu_b,
            "kind": self.kind,
            "axis_a": self.axis_a.tolist(),
            "axis_b": self.axis_b.tolist(),
            "point_a_m": self.point_a.tolist(),
            "point_b_m": self.point_b.tolist(),
            "axis_sigma_rad": self.axis_sigma.tolist(),
            "point_sigma_m": self.point_sigma.tolist(),
            "gyro_noise_rad_s": self.gyro_noise,
            "rigid_residual_rad_s": self.rigid_residual,
            "hinge_residual_rad_s": self.hinge_residual,
            "undetermined": list(self.undetermined),
        }


def _smoothed(signals: Signals, at: Array, interval: float) -> tuple[Array, Array, float]:
    """An IMU's signals and their derivative at ``at`` by a least-squares cubic B-spline."""
    time, values = signals
    count = coefficient_count(float(time[-1] - time[0]), interval, 3)
    basis = spline_basis(time, float(time[0]), interval, count, 3)
    coefficients = fit_spline(time, values, float(time[0]), interval, count)
    noise = float(np.std(values[:, :3] - basis @ coefficients[:, :3]))
    value = spline_basis(at, float(time[0]), interval, count, 3) @ coefficients
    rate = spline_basis(at, float(time[0]), interval, count, 3, 1) @ coefficients
    return value, rate, noise


def _unit(angles: Array) -> Array:
    """Unit vectors from (polar, azimuth) angles, (..., 2) → (..., 3)."""
    p, a = angles[..., 0], angles[..., 1]
    return np.stack([np.sin(p) * np.cos(a), np.sin(p) * np.sin(a), np.cos(p)], axis=-1)


def _covariance(fit: Any, effective: float) -> Array:
    """The covariance of a ``least_squares`` fit's parameters from its Jacobian and residuals.

    The residuals of smoothed signals read at every sample are correlated over a knot interval:
    the variance is scaled by the samples per ``effective`` independent one (the knots).
    """
    n, size = fit.jac.shape
    variance = float(fit.fun @ fit.fun) / max(n - size, 1) * max(n / effective, 1.0)
    return np.asarray(np.linalg.pinv(fit.jac.T @ fit.jac) * variance)


def _hinge_axes(wa: Array, wb: Array, effective: float) -> tuple[Array, Array, float, Array]:
    """The axis in both frames by the hinge constraint, best of a few starts, and its σ [rad]."""
    from scipy.optimize import least_squares

    def residual(x: Array) -> Array:
        ja, jb = _unit(x[:2]), _unit(x[2:])
        return np.asarray(
            np.linalg.norm(np.cross(wa, ja), axis=1) - np.linalg.norm(np.cross(wb, jb), axis=1)
        )

    best = None
    rng = np.random.default_rng(0)
    for start in rng.uniform([0.0, -np.pi] * 2, [np.pi, np.pi] * 2, (8, 4)):
        fit = least_squares(residual, start, method="lm")
        if best is None or fit.cost < best.cost:
            best = fit
    assert best is not None
    ja, jb = _unit(best.x[:2]), _unit(best.x[2:])
    if np.corrcoef(wa @ ja, wb @ jb)[0, 1] < 0:  # one physical axis: same sense both sides
        jb = -jb
    cov = _covariance(best, effective)
    sigma = [
        np.sqrt(max(cov[k, k] + np.sin(best.x[k]) ** 2 * cov[k + 1, k + 1], 0.0)) for k in (0, 2)
    ]
    return ja, jb, float(np.sqrt(np.mean(best.fun**2))), np.array(sigma)


def _hinge_point(
    sides: tuple[tuple[Array, Array, Array], tuple[Array, Array, Array]],
    ja: Array,
    jb: Array,
    effective: float,
) -> tuple[Array, Array, Array]:
    """A point on the axis in both frames, nearest the two IMUs' origins, and σ across it [m]."""
    from scipy.optimize import least_squares

    (wa, da, fa), (wb, db, fb) = sides
    lever_a, lever_b = lever_matrices(wa, da), lever_matrices(wb, db)

    def residual(x: Array) -> Array:
        ea = fa + np.einsum("nij,j->ni", lever_a, x[:3])
        eb = fb + np.einsum("nij,j->ni", lever_b, x[3:])
        return np.asarray(np.linalg.norm(ea, axis=1) - np.linalg.norm(eb, axis=1))

    fit = least_squares(residual, np.zeros(6), method="lm")
    x, cov = fit.x, _covariance(fit, effective)
    sigma = []
    for j, block in ((ja, slice(0, 3)), (jb, slice(3, 6))):
        across = np.eye(3) - np.outer(j, j)
        sigma.append(np.sqrt(max(np.trace(across @ cov[block, block] @ across), 0.0)))
    shift = (x[:3] @ ja + x[3:] @ jb) / 2.0
    return x[:3] - shift * ja, x[3:] - shift * jb, np.array(sigma)


def _slide(
    at: Array, side_a: tuple[Array, Array], force_b: Array, interval: float
) -> tuple[Array, Array]:
    """B's place in A's frame as a path ``v(t)`` when the two do not turn relative to each other.

    ``R·f_B - f_A = (α× + ω×ω×)·v + 2·ω×v̇ + v̈ + c`` is linear in ``v``'s spline and the
    constant ``c`` (B's accelerometer bias less A's): one sparse least squares. A rigid link's
    ``v`` stays put; a prismatic joint's moves along its axis.

    Returns:
        The variances of ``v`` along its principal directions, ascending [m²], and the first
        direction (A's frame).
    """
    from scipy import sparse
    from scipy.sparse.linalg import spsolve

    (value, rate), start = side_a, float(at[0])
    omega = value[:, :3]
    count = coefficient_count(float(at[-1] - at[0]), interval, 3)
    n0, n1, n2 = (spline_basis(at, start, interval, count, 3, d) for d in range(3))
    design = sparse.hstack(
        [
            blockwise(lever_matrices(omega, rate[:, :3]), n0)
            + blockwise(2.0 * skew_rows(omega), n1)
            + sparse.kron(sparse.identity(3), n2),
            sparse.kron(sparse.identity(3), np.ones((at.size, 1))),
        ]
    ).tocsr()
    target = (force_b - value[:, 3:]).T.ravel()
    normals = design.T @ design
    normals = normals + sparse.diags(1e-9 * normals.diagonal())
    solution = spsolve(normals.tocsc(), design.T @ target)
    path = (n0 @ solution[: 3 * count].reshape(3, count).T)[n0.shape[0] // 20 : -n0.shape[0] // 20]
    values, vectors = np.linalg.eigh(np.cov(path.T))
    axis = vectors[:, -1] * np.sign(vectors[np.argmax(np.abs(vectors[:, -1])), -1])
    return values, axis


def _slide_axis(
    at: Array, side_a: tuple[Array, Array], force_b: Array, axis: Array, interval: float
) -> Array:
    """The slide's axis refined on ``v(t) = r + d(t)·u``: ``d`` a scalar spline, ``u`` a unit.

    The model of :func:`_slide` with ``v`` on one axis is bilinear in ``d`` and ``u``: a few
    rounds of two linear least squares, ``d`` (with ``r``, ``c``) for ``u`` held, then ``u``
    (with ``r``, ``c``) for ``d`` held.
    """
    from scipy import sparse
    from scipy.sparse.linalg import spsolve

    (value, rate), start = side_a, float(at[0])
    omega, n = value[:, :3], at.size
    lever, skew = lever_matrices(omega, rate[:, :3]), skew_rows(omega)
    target = force_b - value[:, 3:]
    count = coefficient_count(float(at[-1] - at[0]), interval, 3)
    bases = [spline_basis(at, start, interval, count, 3, d) for d in range(3)]
    eye = np.broadcast_to(np.eye(3), (n, 3, 3))
    for _ in range(4):
        along = [lever @ axis, 2.0 * skew @ axis, np.broadcast_to(axis, (n, 3))]
        path = sparse.vstack(
            [
                sum(sparse.diags(f[:, k]) @ b for f, b in zip(along, bases, strict=True))
                for k in range(3)
            ]
        )
        fixed = sparse.csr_matrix(
            np.concatenate([lever, eye], axis=2).transpose(1, 0, 2).reshape(3 * n, 6)
        )
        design = sparse.hstack([path, fixed]).tocsc()
        normals = design.T @ design
        normals = normals + sparse.diags(1e-9 * normals.diagonal())
        solution = spsolve(normals.tocsc(), design.T @ target.T.ravel())
        d, d1, d2 = (b @ solution[:count] for b in bases)
        d = d - d.mean()
        moving = d[:, None, None] * lever + 2.0 * d1[:, None, None] * skew + d2[:, None, None] * eye
        dense = np.concatenate([moving, lever, eye], axis=2).reshape(-1, 9)
        found = np.linalg.lstsq(dense, target.ravel(), rcond=None)[0][:3]
        axis = found / np.linalg.norm(found)
    return np.asarray(axis * np.sign(axis[np.argmax(np.abs(axis))]))


@checked
def identify_joint(
    source: RecordedRun | Mapping[str, Signals],
    imu_a: str,
    imu_b: str,
    knot_interval: float = 0.02,
) -> JointFit:
    """The joint between the body of IMU A and the body of IMU B, from their signals alone.

    Args:
        source: a recording or ``{name: (time [s], (N, 6) signals)}`` (one clock)
        imu_a: the IMU on the first body
        imu_b: the IMU on the second body
        knot_interval: the smoothing splines' knot spacing [s]

    Returns:
        The joint's type, axis and (revolute) a point on it.

    Raises:
        ParameterError: an IMU not in the source, or recordings that do not overlap.
    """
    a, b = imu_signals(source, imu_a), imu_signals(source, imu_b)
    first, last = max(a[0][0], b[0][0]) + 0.05, min(a[0][-1], b[0][-1]) - 0.05
    at = a[0][(a[0] >= first) & (a[0] <= last)]
    if at.size < 50:
        raise ParameterError(
            f"IMUs {imu_a} and {imu_b} share {at.size} samples; allowed: at least 50",
            parameter="imu",
            value=imu_b,
        )
    (va, ra, noise_a), (vb, rb, noise_b) = (_smoothed(s, at, knot_interval) for s in (a, b))
    wa, wb = va[:, :3], vb[:, :3]
    noise = float(np.hypot(noise_a, noise_b))
    rotation = rotation_between(wa, wb)
    rigid = float(np.sqrt(np.mean(np.sum((wa - wb @ rotation.T) ** 2, axis=1) / 3.0)))
    zero = np.zeros(3)
    if rigid < RIGID_RATIO * noise:
        pair = identify_rigid(source, imu_a, imu_b)
        if pair.noise[3] < SLIDE_RATIO * pair.noise[1]:
            return JointFit(
                imu_a, imu_b, "rigid", zero, zero, pair.position, zero, noise, rigid, 0.0
            )
        force_b = vb[:, 3:] @ rotation.T
        _, axis = _slide(at, (va, ra), force_b, knot_interval * 5)
        axis = _slide_axis(at, (va, ra), force_b, axis, knot_interval * 2)
        return JointFit(
            imu_a, imu_b, "prismatic", axis, rotation.T @ axis, zero, zero, noise, rigid, 0.0
        )
    effective = float(at[-1] - at[0]) / knot_interval
    ja, jb, hinge, axis_sigma = _hinge_axes(wa, wb, effective)
    point_a, point_b, point_sigma = _hinge_point(
        ((wa, ra[:, :3], va[:, 3:]), (wb, rb[:, :3], vb[:, 3:])), ja, jb, effective
    )
    return JointFit(
        imu_a,
        imu_b,
        "revolute",
        ja,
        jb,
        point_a,
        point_b,
        noise,
        rigid,
        hinge,
        axis_sigma,
        point_sigma,
    )


def identify_chain(
    source: RecordedRun | Mapping[str, Signals], imus: Sequence[str], knot_interval: float = 0.02
) -> tuple[JointFit, ...]:
    """A chain of bodies, one IMU each, base first: the joint between each two in a row.

    Args:
        source: a recording or ``{name: (time [s], (N, 6) signals)}`` (one clock)
        imus: the IMUs from the base body to the last
        knot_interval: the smoothing splines' knot spacing [s]

    Returns:
        One fit per joint, base first.

    Raises:
        ParameterError: fewer than two IMUs, or a joint's own errors.
    """
    names = list(imus)
    if len(names) < 2:
        raise ParameterError(
            parameter="imus", value=", ".join(names) or "none", allowed="two or more IMUs"
        )
    return tuple(
        identify_joint(source, parent, child, knot_interval)
        for parent, child in itertools.pairwise(names)
    )
