"""Two rigid bodies joined by an unknown joint, one IMU on each: the joint's type, axis and place.

For robots whose joints have no encoders. :func:`simulate_jointed_bodies` records an IMU on each
of two bodies, body 2 turning (revolute) or sliding (prismatic) on body 1 by a smooth random
joint motion while body 1 is carried by hand (:func:`~aaria_pin.apps.identify.rigid_motion.
hand_motion`). :func:`identify_joint` finds, from the two IMUs' signals (one clock), without the
joint's values:

* the type: the two gyroscopes related by one constant rotation (Kabsch residual at the noise)
  is a rigid or prismatic link (then the accelerometers after the lever arm's fit tell which:
  a slide leaves a residual along its axis); else revolute;
* a revolute joint's axis in both IMUs' frames by the hinge constraint (Seel, Raisch, Schauer
  2012): the angular velocity's part across the axis has one norm on both sides,
  ``|ω_A × j_A| = |ω_B × j_B|``; and its position: the point on the axis has one acceleration
  seen from both sides, ``|f_A - Γ_A(o_A)| = |f_B - Γ_B(o_B)|`` with
  ``Γ(o) = ω×(ω×o) + ω̇×o``, then moved along the axis to the point nearest the two IMUs
  (a point along the axis is not determined);
* a prismatic joint's axis in A's frame: the principal direction of what the rigid lever arm
  leaves of B's specific force (the slide's acceleration ``q̈·u`` dominates it).

Both IMUs' signals are smoothed by a least-squares cubic B-spline (knots 0.02 s apart) and read
at A's stamps, so rates may differ; the clocks are taken as one (a time offset, if any, from
:func:`~aaria_pin.apps.identify.rigid.identify_rigid` on a rigid pair of the same recording).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from aaria_pin.apps.identify.rigid import (
    Signals,
    _imu,
    _kabsch,
    _lever_matrices,
    identify_rigid,
)
from aaria_pin.apps.identify.rigid_motion import (
    GRAVITY,
    HandMotion,
    ImuMount,
    hand_motion,
)
from aaria_pin.apps.identify.rigid_spline import coefficient_count, spline_basis
from aaria_pin.core.imu_model import ImuNoiseModel
from aaria_pin.core.imu_noise import add_imu_noise
from aaria_pin.core.recording import STREAM_COLUMNS, RecordedRun, SensorStream
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = ["JOINT_TYPES", "JointFit", "UnknownJoint", "identify_joint", "simulate_jointed_bodies"]

JOINT_TYPES = ("revolute", "prismatic")
"""The joints :func:`simulate_jointed_bodies` makes and :func:`identify_joint` tells apart."""

RIGID_RATIO = 5.0
"""A gyroscope residual of the constant-rotation fit below this many times the gyroscopes' own
noise is a link whose rotation does not change (rigid or prismatic)."""


SLIDE_RATIO = 3.0
"""B's accelerometer residual of the rigid pair fit (:func:`~aaria_pin.apps.identify.rigid.
identify_rigid`) over A's above which a link that does not turn slides (prismatic)."""


@dataclass(frozen=True)
class UnknownJoint:
    """The joint between body 1 and body 2 (body 2's frame is body 1's at joint value 0).

    Attributes:
        kind: ``revolute`` or ``prismatic``
        axis: (3,) unit axis in body 1's frame
        point: (3,) a point on the axis in body 1's frame [m] (revolute)
        rate: the joint rate's RMS [rad/s or m/s]
    """

    kind: str
    axis: Array
    point: Array
    rate: float = 1.0


def _joint_motion(seed: int, rate: float, t: Array) -> tuple[Array, Array, Array]:
    """A smooth random joint value, rate and acceleration: five sinusoids of 0.2–2 Hz.

    ``rate`` is the RMS of the joint rate [rad/s or m/s].
    """
    rng = np.random.default_rng([seed, 27])
    freq = 2.0 * np.pi * rng.uniform(0.2, 2.0, 5)
    phase = rng.uniform(0.0, 2.0 * np.pi, 5)
    scale = rate / np.sqrt(5 / 2.0) / freq
    angle = freq[None] * t[:, None] + phase[None]
    return (
        (scale * np.sin(angle)).sum(1),
        (scale * freq * np.cos(angle)).sum(1),
        -(scale * freq**2 * np.sin(angle)).sum(1),
    )


def _axis_rotation(axis: Array, angle: Array) -> Array:
    """Rotations by ``angle`` about one unit axis, (n, 3, 3)."""
    from scipy.spatial.transform import Rotation

    return np.asarray(Rotation.from_rotvec(angle[:, None] * axis[None]).as_matrix())


def _body_two_signals(
    motion: HandMotion, joint: UnknownJoint, mount: ImuMount, t: Array, seed: int
) -> Array:
    """The exact signals of an IMU on body 2, (n, 6)."""
    state = motion.state(t)
    w1, a1 = state.angular_velocity, state.angular_acceleration
    q, qd, qdd = _joint_motion(seed, joint.rate, t)
    axis = np.asarray(joint.axis, dtype=np.float64)
    x = np.asarray(mount.position, dtype=np.float64)
    n = t.size
    if joint.kind == "revolute":
        turn = _axis_rotation(axis, q)  # R_12
        c = np.asarray(joint.point, dtype=np.float64)
        y = c + np.einsum("nij,j->ni", turn, x - c)
        y_rate = qd[:, None] * np.cross(axis, y - c)
        y_accel = qdd[:, None] * np.cross(axis, y - c) + qd[:, None] * np.cross(axis, y_rate)
        w1_in_2 = np.einsum("nji,nj->ni", turn, w1)
        w2 = w1_in_2 + qd[:, None] * axis
    else:
        turn = np.broadcast_to(np.eye(3), (n, 3, 3))
        y = x + q[:, None] * axis
        y_rate, y_accel = qd[:, None] * axis, qdd[:, None] * axis
        w2 = w1
    force_1 = (
        np.einsum("nji,nj->ni", state.rotation, state.acceleration - GRAVITY)
        + np.cross(a1, y)
        + np.cross(w1, np.cross(w1, y))
        + 2.0 * np.cross(w1, y_rate)
        + y_accel
    )
    force_2 = np.einsum("nji,nj->ni", turn, force_1)
    r_t = np.asarray(mount.rotation, dtype=np.float64).T
    return np.concatenate([w2 @ r_t.T, force_2 @ r_t.T], axis=1)


def simulate_jointed_bodies(
    joint: UnknownJoint,
    mounts: tuple[ImuMount, ImuMount],
    duration: float = 20.0,
    model: ImuNoiseModel | None = None,
    seed: int = 0,
) -> RecordedRun:
    """A recording of an IMU on body 1 (``mounts[0]``) and one on body 2 (``mounts[1]``).

    Args:
        joint: the joint (its frame: body 1's)
        mounts: the IMUs on body 1 and on body 2 (body 2's frame at joint value 0)
        duration: the span of stamps [s]
        model: the IMU noise model (None: exact)
        seed: the seed of the motions and of the noise

    Returns:
        Two ``imu`` streams.

    Raises:
        ParameterError: an unknown joint kind.
    """
    if joint.kind not in JOINT_TYPES:
        raise ParameterError(parameter="kind", value=joint.kind, allowed=", ".join(JOINT_TYPES))
    from aaria_pin.apps.identify.rigid_motion import exact_imu_signals

    motion = hand_motion(seed)
    streams = []
    for k, mount in enumerate(mounts):
        stamps = mount.start + np.arange(int(np.floor(duration * mount.rate)) + 1) / mount.rate
        at = stamps + mount.time_offset
        if k == 0:
            signals = exact_imu_signals(motion, mount, at)
        else:
            signals = _body_two_signals(motion, joint, mount, at, seed)
        if model is not None:
            rng = np.random.default_rng([seed, 28, k])
            signals = add_imu_noise(signals[:, None], mount.rate, rng, model)[:, 0]
        streams.append(SensorStream(mount.name, "imu", stamps, signals, STREAM_COLUMNS["imu"]))
    return RecordedRun(streams, source="simulated jointed bodies")


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
            lines.append(
                f"  point on the axis [mm] in {self.imu_a}: [{vec(self.point_a, 1e3)}], in "
                f"{self.imu_b}: [{vec(self.point_b, 1e3)}] (along the axis: not determined)"
            )
        return lines


def _smoothed(signals: Signals, at: Array, interval: float) -> tuple[Array, Array, float]:
    """An IMU's signals and their derivative at ``at`` by a least-squares cubic B-spline."""
    from scipy.sparse import identity
    from scipy.sparse.linalg import spsolve

    time, values = signals
    span = float(time[-1] - time[0])
    count = coefficient_count(span, interval, 3)
    basis = spline_basis(time, float(time[0]), interval, count, 3)
    normals = (basis.T @ basis + 1e-9 * identity(count)).tocsc()
    coefficients = np.column_stack([spsolve(normals, basis.T @ values[:, i]) for i in range(6)])
    noise = float(np.std(values[:, :3] - basis @ coefficients[:, :3]))
    value = spline_basis(at, float(time[0]), interval, count, 3) @ coefficients
    rate = spline_basis(at, float(time[0]), interval, count, 3, 1) @ coefficients
    return value, rate, noise


def _unit(angles: Array) -> Array:
    """Unit vectors from (polar, azimuth) angles, (..., 2) → (..., 3)."""
    p, a = angles[..., 0], angles[..., 1]
    return np.stack([np.sin(p) * np.cos(a), np.sin(p) * np.sin(a), np.cos(p)], axis=-1)


def _hinge_axes(wa: Array, wb: Array) -> tuple[Array, Array, float]:
    """The axis in both frames by the hinge constraint, best of a few starts."""
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
    return ja, jb, float(np.sqrt(np.mean(best.fun**2)))


def _hinge_point(
    sides: tuple[tuple[Array, Array, Array], tuple[Array, Array, Array]], ja: Array, jb: Array
) -> tuple[Array, Array]:
    """A point on the axis in both frames, nearest the two IMUs' origins."""
    from scipy.optimize import least_squares

    (wa, da, fa), (wb, db, fb) = sides
    lever_a, lever_b = _lever_matrices(wa, da), _lever_matrices(wb, db)

    def residual(x: Array) -> Array:
        ea = fa + np.einsum("nij,j->ni", lever_a, x[:3])
        eb = fb + np.einsum("nij,j->ni", lever_b, x[3:])
        return np.asarray(np.linalg.norm(ea, axis=1) - np.linalg.norm(eb, axis=1))

    x = least_squares(residual, np.zeros(6), method="lm").x
    shift = (x[:3] @ ja + x[3:] @ jb) / 2.0
    return x[:3] - shift * ja, x[3:] - shift * jb


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

    from aaria_pin.apps.identify.rigid_fit import _blockwise, _skew

    (value, rate), start = side_a, float(at[0])
    omega = value[:, :3]
    count = coefficient_count(float(at[-1] - at[0]), interval, 3)
    n0, n1, n2 = (spline_basis(at, start, interval, count, 3, d) for d in range(3))
    design = sparse.hstack(
        [
            _blockwise(_lever_matrices(omega, rate[:, :3]), n0)
            + _blockwise(2.0 * _skew(omega), n1)
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

    from aaria_pin.apps.identify.rigid_fit import _skew

    (value, rate), start = side_a, float(at[0])
    omega, n = value[:, :3], at.size
    lever, skew = _lever_matrices(omega, rate[:, :3]), _skew(omega)
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
    a, b = _imu(source, imu_a), _imu(source, imu_b)
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
    rotation = _kabsch(wa, wb)
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
    ja, jb, hinge = _hinge_axes(wa, wb)
    point_a, point_b = _hinge_point(
        ((wa, ra[:, :3], va[:, 3:]), (wb, rb[:, :3], vb[:, 3:])), ja, jb
    )
    return JointFit(imu_a, imu_b, "revolute", ja, jb, point_a, point_b, noise, rigid, hinge)
