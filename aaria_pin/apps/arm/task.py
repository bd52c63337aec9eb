"""The pick-and-place task: waypoints from the planar IK and the hand, a smooth joint path.

The arm starts at a home pose (:func:`home_pose`), then goes through the report's task in
seven phases:

``approach`` (to above the cylinder, finger open), ``descend`` (lift down to the grasp
height), ``grasp`` (finger closes on the cylinder), ``lift`` (lift up), ``move`` (to above the
place), ``place`` (lift down), ``release`` (finger opens).

Each phase is a quintic move in joint space between waypoints (zero velocity and acceleration
at both ends, so the path is C² and the torques are finite): its duration is the shortest that
keeps every joint within its velocity and acceleration limits (peak speed ``15Δ/8T``, peak
acceleration ``10Δ/(√3·T²)``), and at least :data:`MIN_PHASE` seconds. The hand points straight
down; its finger travels radially (the tool's x axis at the azimuth of the cylinder, then of the
place), so the gripped cylinder stays upright. The wrist goes to where the grasp point is over
the cylinder's axis; shoulder and elbow turn as :func:`aaria_pin.apps.arm.ik.plan_planar_move` says,
so the forearm never swings through the pillar.

**Grasp.** The cylinder is held at half its height, its top just under the palm
(:mod:`aaria_pin.apps.arm.dims`: heights the fingers can hold without the palm or the floor in the
way),
pressed by the sliding finger against the two fixed ones (gap = its diameter); it is held (its mass
on the hand) from the end of ``grasp`` to the start of ``release``. It must stand clear of the
pillar's foot plate by its radius plus a finger's thickness. Clearances (chosen): the fingertips
pass 3 cm over the cylinder's top, the carried cylinder's bottom is at least 10 cm above its grasp
height, the open finger leaves 3 cm of gap.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from aaria_pin.apps.arm.dims import ArmDimensions, height_limits
from aaria_pin.apps.arm.hand import downward_grasp, hand_angles
from aaria_pin.apps.arm.ik import ANNULUS_TOLERANCE, plan_planar_move
from aaria_pin.apps.arm.preset import arm_joints
from aaria_pin.core.inertia import Inertia, cylinder_inertia
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import sample_times
from aaria_pin.errors import ParameterError

__all__ = [
    "MIN_PHASE",
    "PHASES",
    "Cylinder",
    "JointPath",
    "home_pose",
    "plan_pick_place",
]

PHASES = ("approach", "descend", "grasp", "lift", "move", "place", "release")
"""The task's phases, in order."""

MIN_PHASE = 0.5
"""Shortest phase [s]."""

_ACCELERATION = {  # chosen: joint acceleration limits [rad/s² or m/s²]
    "lift": 0.5,
    "shoulder": 2.0,
    "elbow": 2.0,
    "hand_yaw": 4.0,
    "hand_pitch": 4.0,
    "hand_roll": 4.0,
    "finger": 0.2,
}
_TIP_CLEARANCE = 0.03
_CARRY_CLEARANCE = 0.10
_OPEN_MARGIN = 0.03


@dataclass(frozen=True)
class Cylinder:
    """The cylinder to move, standing upright on the floor.

    Attributes:
        x: position of its axis [m]
        y: position of its axis [m]
        radius: radius [m]
        height: height [m]
        mass: mass [kg] (0: an empty, massless object)
    """

    x: float
    y: float
    radius: float = 0.03
    height: float = 0.12
    mass: float = 0.5

    def __post_init__(self) -> None:
        for name in ("x", "y", "radius", "height", "mass"):
            if not np.isfinite(getattr(self, name)):
                raise ParameterError(
                    f"cylinder {name} is {getattr(self, name)!r}; allowed: finite",
                    parameter=name,
                    value=getattr(self, name),
                )
        if self.radius <= 0 or self.height <= 0 or self.mass < 0:
            raise ParameterError(
                f"cylinder radius {self.radius} m, height {self.height} m, mass {self.mass} kg;"
                " allowed: radius > 0, height > 0, mass >= 0",
                parameter=next(
                    name
                    for name, good in (
                        ("radius", self.radius > 0),
                        ("height", self.height > 0),
                        ("mass", self.mass >= 0),
                    )
                    if not good
                ),
            )

    def inertia(self) -> Inertia:
        """Its mass properties about its centre, axis along z (solid, uniform)."""
        return Inertia(
            self.mass, np.zeros(3), cylinder_inertia(self.mass, self.radius, self.height)
        )


@dataclass(frozen=True)
class JointPath:
    """A sampled joint path with its phases.

    Attributes:
        time: sample times [s], (T,)
        q: joint values (T, 7), order of :data:`aaria_pin.apps.arm.preset.ARM_JOINTS` [m or rad]
        qd: joint velocities (T, 7)
        qdd: joint accelerations (T, 7)
        phase: index into :data:`PHASES` of each sample, -1 before the first and after the
            last (T,), integers
        held: True where the cylinder is in the hand (T,)
        boundaries: start and end time of each phase [s], (7, 2)
        waypoints: joint values at the phase boundaries, (8, 7)
    """

    time: Array
    q: Array
    qd: Array
    qdd: Array
    phase: NDArray[np.int_]
    held: NDArray[np.bool_]
    boundaries: Array
    waypoints: Array

    @property
    def held_interval(self) -> tuple[float, float]:
        """Start and end of the hold [s] (held: start <= t < end).

        The end of ``grasp`` and the start of ``release``.
        """
        return _held_interval(self.boundaries)


def _held_interval(boundaries: Array) -> tuple[float, float]:
    grasp, release = PHASES.index("grasp"), PHASES.index("release")
    return float(boundaries[grasp, 1]), float(boundaries[release, 0])


def home_pose(dims: ArmDimensions) -> Array:
    """The start pose: lift at 80 % of its range, α = 0, β = +90°, hand down, finger at 6 cm."""
    low, high = dims.lift_range
    return np.array([low + 0.8 * (high - low), 0.0, np.pi / 2, -np.pi / 2, 0.0, 0.0, 0.06])


def _check_cylinder(dims: ArmDimensions, cylinder: Cylinder, where: str) -> None:
    low, high = height_limits(dims)
    if not low - 1e-12 <= cylinder.height <= high + 1e-12:
        raise ParameterError(
            f"cylinder height {cylinder.height} m; allowed: {low:.3g} to {high:.3g} m (held with"
            f" its top {dims.palm_clearance} m below the palm: shorter, the fingertips would touch"
            " the floor; taller, the fingers would not reach its half height)",
            parameter="height",
            value=cylinder.height,
        )
    if 2 * cylinder.radius + _OPEN_MARGIN > dims.finger_travel:
        raise ParameterError(
            f"cylinder radius {cylinder.radius} m; allowed: <= "
            f"{(dims.finger_travel - _OPEN_MARGIN) / 2:.3g} m (the finger opens"
            f" {dims.finger_travel} m)",
            parameter="radius",
            value=cylinder.radius,
        )
    half = dims.foot_size / 2
    gap = float(np.hypot(max(abs(cylinder.x) - half, 0.0), max(abs(cylinder.y) - half, 0.0)))
    margin = cylinder.radius + dims.finger_thickness
    if gap < margin:
        raise ParameterError(
            f"{where} ({cylinder.x:g}, {cylinder.y:g}) m is {gap:.3g} m from the pillar's foot"
            f" plate ({dims.foot_size} m square about the origin); allowed: at least cylinder"
            f" radius + finger thickness = {margin:.3g} m from it (the cylinder and the fingers"
            " stand on the floor)",
            parameter=where,
            value=(cylinder.x, cylinder.y),
        )


def _lift_for(dims: ArmDimensions, grasp_height: float, height: float, what: str) -> float:
    below = dims.grasp_below_carriage(height)
    lift = grasp_height + below
    low, high = dims.lift_range
    if not low - 1e-12 <= lift <= high + 1e-12:
        raise ParameterError(
            f"{what} needs the lift at {lift:.4g} m; allowed: {low} to {high} m (grasp heights"
            f" {low - below:.4g} to {high - below:.4g} m above the floor)",
            parameter="height",
            value=height,
        )
    return lift


def _arm_over(
    dims: ArmDimensions, q: Array, x: float, y: float, radius: float, branch: str, what: str
) -> Array:
    """Joint values that put the grasp point over (x, y), hand down, finger radial."""
    yaw = float(np.arctan2(y, x))
    offset = dims.finger_face + radius  # grasp point along the tool's x axis
    wx, wy = x - offset * np.cos(yaw), y - offset * np.sin(yaw)
    inner, outer = dims.annulus
    distance, wrist = float(np.hypot(x, y)), float(np.hypot(wx, wy))
    if not inner - ANNULUS_TOLERANCE <= wrist <= outer + ANNULUS_TOLERANCE:
        raise ParameterError(
            f"{what} ({x:g}, {y:g}) m at {distance:.4g} m from the pillar's axis is out of reach:"
            f" the grasp point of a {radius:g} m radius cylinder is {offset:.4g} m out from the"
            f" wrist along the finger's travel, so the wrist would be at {wrist:.4g} m, outside"
            f" the reachable annulus {inner:.4g} m <= r <= {outer:.4g} m; allowed: {what} at"
            f" {inner + offset:.4g} to {outer + offset:.4g} m from the pillar's axis",
            parameter=what,
            value=(x, y),
        )
    planar = plan_planar_move(
        float(q[1]),
        float(q[2]),
        wx,
        wy,
        dims.upper_arm,
        dims.forearm,
        branch,  # type: ignore[arg-type]
    )
    heading = float(planar.alpha + planar.beta)
    hand = hand_angles(downward_grasp(yaw), heading, previous=q[3:6]).angles
    limit = 2 * np.pi
    hand = np.where(hand > limit, hand - 2 * np.pi, np.where(hand < -limit, hand + 2 * np.pi, hand))
    out = q.copy()
    out[1], out[2], out[3:6] = float(planar.alpha), float(planar.beta), hand
    return out


def _duration(delta: Array, velocity: Array, acceleration: Array) -> float:
    d = np.abs(delta)
    by_speed = 15.0 / 8.0 * d / velocity
    by_acceleration = np.sqrt(10.0 / np.sqrt(3.0) * d / acceleration)
    return float(max(MIN_PHASE, by_speed.max(), by_acceleration.max()))


def _quintic(s: Array) -> tuple[Array, Array, Array]:
    return (
        s**3 * (10 - 15 * s + 6 * s * s),
        30 * s * s * (1 - s) ** 2,
        60 * s * (1 - s) * (1 - 2 * s),
    )


def plan_pick_place(
    dims: ArmDimensions,
    cylinder: Cylinder,
    place: tuple[float, float],
    *,
    rate: float = 100.0,
    start: Array | None = None,
    branch: str = "nearest",
    settle: float = 0.5,
) -> JointPath:
    """The pick-and-place joint path.

    Args:
        dims: the arm
        cylinder: the cylinder and where it stands
        place: where to put it down (x, y) [m]
        rate: sample rate [Hz]
        start: the arm's start pose (7 joint values), default :func:`home_pose`
        branch: IK branch of every move: ``"nearest"``, ``"left"`` or ``"right"``
        settle: rest before the first and after the last phase [s]

    Returns:
        The path.

    Raises:
        ParameterError: a cylinder that the hand cannot hold, a pick or place point outside the
            reachable annulus (the message names it) or on the pillar, a height the lift cannot
            reach, a bad rate, start pose or branch.
    """
    if not (np.isfinite(settle) and settle >= 0):
        raise ParameterError(
            f"settle {settle!r} s; allowed: >= 0", parameter="settle", value=settle
        )
    target = Cylinder(float(place[0]), float(place[1]), cylinder.radius, cylinder.height, 0.0)
    _check_cylinder(dims, cylinder, "cylinder")
    _check_cylinder(dims, target, "place")
    q0 = home_pose(dims) if start is None else np.asarray(start, dtype=float).copy()
    if q0.shape != (7,) or not np.all(np.isfinite(q0)):
        raise ParameterError(
            f"start pose of shape {q0.shape}; allowed: 7 finite joint values", parameter="start"
        )
    h = cylinder.height
    grasp_lift = _lift_for(dims, h / 2, h, "grasping the cylinder at half height")
    carry = max(h + dims.fingertip_below_grasp(h) + _TIP_CLEARANCE, h / 2 + _CARRY_CLEARANCE)
    carry_lift = _lift_for(dims, carry, h, "carrying the cylinder clear of the floor")
    open_gap = 2 * cylinder.radius + _OPEN_MARGIN
    closed = 2 * cylinder.radius

    above_pick = _arm_over(dims, q0, cylinder.x, cylinder.y, cylinder.radius, branch, "cylinder")
    above_pick[0], above_pick[6] = carry_lift, open_gap
    down = above_pick.copy()
    down[0] = grasp_lift
    gripped = down.copy()
    gripped[6] = closed
    up = gripped.copy()
    up[0] = carry_lift
    above_place = _arm_over(dims, up, target.x, target.y, cylinder.radius, branch, "place")
    placed = above_place.copy()
    placed[0] = grasp_lift
    released = placed.copy()
    released[6] = open_gap
    waypoints = np.array([q0, above_pick, down, gripped, up, above_place, placed, released])

    joints = [j for j in arm_joints(dims) if j.kind != "fixed"]
    velocity = np.array([j.velocity for j in joints])
    acceleration = np.array([_ACCELERATION[j.name] for j in joints])
    durations = [_duration(b - a, velocity, acceleration) for a, b in itertools.pairwise(waypoints)]
    starts = settle + np.concatenate([[0.0], np.cumsum(durations)[:-1]])
    boundaries = np.column_stack([starts, starts + durations])
    time = sample_times(float(boundaries[-1, 1] + settle), rate)
    phase = np.searchsorted(boundaries[:, 0], time, side="right") - 1
    phase = np.where(time >= boundaries[-1, 1], len(PHASES), phase)  # after the end
    q = np.empty((time.size, 7))
    qd = np.zeros_like(q)
    qdd = np.zeros_like(q)
    q[phase < 0] = waypoints[0]
    q[phase >= len(PHASES)] = waypoints[-1]
    for k, (t0, t1) in enumerate(boundaries):
        mask = phase == k
        span = t1 - t0
        s, ds, dds = _quintic((time[mask] - t0) / span)
        delta = waypoints[k + 1] - waypoints[k]
        q[mask] = waypoints[k] + s[:, None] * delta
        qd[mask] = ds[:, None] * delta / span
        qdd[mask] = dds[:, None] * delta / span**2
    phase = np.where(phase >= len(PHASES), -1, phase)
    hold_start, hold_end = _held_interval(boundaries)
    held = (time >= hold_start) & (time < hold_end)
    return JointPath(time, q, qd, qdd, phase, held, boundaries, waypoints)
