"""The pick-and-place run: path, torques with the payload, tool pose, and its run file.

:func:`simulate_pick_place` plans the task (:mod:`aaria_pin.apps.arm.task`), computes the joint
torques
by RNEA with the cylinder on the hand while it is held and without it
(:mod:`aaria_pin.apps.arm.payload`), the wrench of the pillar's mount, and the grasp point's pose.
:func:`pick_place_record` turns the run into the one run record
(:class:`aaria_pin.core.record.RunRecord`, kind ``"pick-place"``: ``q``, ``qd``, ``qdd``,
``tau``; a fixed base; ``base_wrench`` = the mount's; ``tool_pose`` = the grasp point; no IMU;
the URDF text, whose frame ``grasp`` is placed for the run's cylinder, so it equals
``tool_pose``), written by :func:`aaria_pin.files.runfile.write_run` as any run file (``.h5`` or
``.mat``). The task's settings (the cylinder, the place, the preset, the rate, the IK branch:
what re-makes it), phases and held interval are attributes.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin._version import __version__
from aaria_pin.apps.arm.dims import ArmDimensions, get_arm_preset
from aaria_pin.apps.arm.parts import MeshPart
from aaria_pin.apps.arm.payload import HAND_JOINT, payload_inertia, with_payload
from aaria_pin.apps.arm.preset import ARM_JOINTS, arm_joints, arm_parts, arm_urdf, build_arm_model
from aaria_pin.apps.arm.task import PHASES, Cylinder, JointPath, plan_pick_place
from aaria_pin.core.model import GRAVITY, RobotModel
from aaria_pin.core.record import ColumnView, ImuMount, RunRecord
from aaria_pin.core.run import (
    FixedMount,
    Payload,
    RunKind,
    RunSettings,
    SampledTrajectory,
    register_kind,
    simulate,
)
from aaria_pin.core.run.measured import HARDWARE_ATTRIBUTES
from aaria_pin.core.run.settings import stored_hardware
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory

__all__ = [
    "PickPlaceRobot",
    "PickPlaceRun",
    "cylinder_track",
    "effort_excess",
    "pick_place_record",
    "simulate_pick_place",
    "simulate_pick_place_from_record",
    "stored_cylinder",
    "stored_preset",
    "write_pick_place_run",
]

_UNITS = {
    "q": "m (lift, finger), rad (shoulder, elbow, hand)",
    "tau": "N (lift, finger), N*m (shoulder, elbow, hand)",
    "tool_pose": "m",
    "base_wrench": "N (fx, fy, fz), N*m (mx, my, mz)",
    "time": "s",
}


@dataclass(frozen=True)
class PickPlaceRun:
    """A pick-and-place run.

    Attributes:
        path: the joint path, its phases and held mask
        tau: joint torques [N·m] and forces [N] with the cylinder on the hand where held (T, 7)
        tau_free: the same without the cylinder (T, 7)
        base_wrench: the wrench the pillar's mount applies to the arm, cylinder included where
            held, ``[fx fy fz mx my mz]`` in world axes about the pillar's origin on the floor
            (T, 6) [N, N·m]
        tool_pose: the grasp point's pose in the world (T, 4, 4) [m]
        cylinder: the cylinder (where it stood)
        place: where it was put down (x, y) [m]
        dims: the arm
        preset: the arm preset's name
        branch: the IK branch rule used
        robot: the arm's model on a moving base resting at the world origin (its URDF text,
            ``robot.urdf``, places frame ``grasp`` for the cylinder)
        parts: the arm's part meshes (:func:`aaria_pin.apps.arm.preset.arm_parts`)
        rate: the sample rate asked for [Hz]
        measured: the hardware's tables (``q_measured``, ``tau_measured``, ``tau_motor`` ...;
            none without hardware)
        hardware: the attributes recording the hardware
            (:data:`~aaria_pin.core.run.measured.HARDWARE_ATTRIBUTES`; ``noise_parameters`` only
            when an IMU model was given: the arm has no IMU)
    """

    path: JointPath
    tau: Array
    tau_free: Array
    base_wrench: Array
    tool_pose: Array
    cylinder: Cylinder
    place: tuple[float, float]
    dims: ArmDimensions
    preset: str
    branch: str
    robot: RobotModel
    parts: Mapping[str, MeshPart]
    rate: float = 0.0
    measured: Mapping[str, Array] = field(default_factory=dict)
    hardware: Mapping[str, Any] = field(default_factory=dict)

    def link_poses(self, frames: list[str], samples: ArrayLike | None = None) -> Array:
        """World poses (S, F, 4, 4) [m] of model frames at samples (default: every one)."""
        from aaria_pin.core.kinematics import frame_poses

        p = self.path
        index = slice(None) if samples is None else np.asarray(samples, dtype=int)
        trajectory = JointTrajectory(
            *(np.ascontiguousarray(a[index]) for a in (p.time, p.q, p.qd, p.qdd))
        )
        n = trajectory.time.size
        return frame_poses(self.robot, BaseMotion.resting(n), trajectory, frames)


@dataclass(frozen=True)
class PickPlaceRobot(FixedMount):
    """The pick-and-place arm as the run engine's robot: a fixed mount, no IMU, a payload.

    Its model has a free-flyer held at rest, so the base wrench is the pillar mount's load; the
    cylinder is on the hand (:data:`~aaria_pin.apps.arm.payload.HAND_JOINT`) where held.

    Attributes:
        model: the bare arm on a moving base resting at the world origin
        payload: the arm with the cylinder on the hand, and where it is held
    """

    model: RobotModel
    payload: Payload
    kind: ClassVar[str] = "pick-place"
    columns: ClassVar[None] = None
    imu_frames: ClassVar[list[str]] = []
    imu_slots: ClassVar[None] = None
    n_slots: ClassVar[None] = None
    imu_mounts: ClassVar[tuple[ImuMount, ...]] = ()
    tables: ClassVar[dict[str, Array]] = {}
    views: ClassVar[dict[str, ColumnView]] = {}
    torque_name: ClassVar[str] = "torques"

    @property
    def joint_names(self) -> tuple[str, ...]:
        """The arm's joints."""
        return tuple(ARM_JOINTS)

    @property
    def limits(self) -> tuple[Array, Array]:
        """The model's position limits (the URDF's) [m or rad]."""
        return self.model.position_limits

    @property
    def urdf(self) -> str:
        """The arm's URDF text (frame ``grasp`` placed for the cylinder)."""
        return self.model.urdf or ""

    def attributes(self, peaks: Array) -> dict[str, Any]:
        """``robot``, ``moving_base`` (False), frames."""
        return {
            "robot": PICK_PLACE_ROBOT,
            "moving_base": False,
            "base_frame": "pillar",
            "tool_frame": self.model.tool_frame,
        }


def simulate_pick_place(
    cylinder: Cylinder,
    place: tuple[float, float],
    *,
    preset: str = "pick-place-arm",
    rate: float = 100.0,
    branch: str = "nearest",
    threads: int = 1,
    hardware: Mapping[str, Any] | None = None,
) -> PickPlaceRun:
    """Plan the task and run it on the run engine (:class:`PickPlaceRobot`, its planned path).

    Args:
        cylinder: the cylinder and where it stands
        place: where to put it (x, y) [m]
        preset: the arm preset
        rate: sample rate [Hz]
        branch: IK branch: ``"nearest"``, ``"left"`` or ``"right"``
        threads: RNEA worker threads
        hardware: the run's hardware as :class:`~aaria_pin.core.run.RunSettings` fields
            (``encoder``, ``torque_sensor``, ``actuator``; ``noise_model`` is recorded only:
            the arm has no IMU; :func:`~aaria_pin.aaria.hardware.hardware_run_options`)

    Returns:
        The run.

    Raises:
        ParameterError: as :func:`aaria_pin.apps.arm.task.plan_pick_place`, an unknown preset,
            a path beyond the arm's joint limits, or hardware its models refuse.
    """
    from aaria_pin.core.dynamics import inverse_dynamics

    dims = get_arm_preset(preset)
    path = plan_pick_place(dims, cylinder, place, rate=rate, branch=branch)
    parts = arm_parts(dims)
    grasp = (cylinder.radius, cylinder.height)
    urdf = arm_urdf(dims, grasp=grasp, parts=parts)
    robot = build_arm_model(dims, grasp, free_flyer=True, urdf=urdf)
    loaded = replace(robot, model=with_payload(robot.model, payload_inertia(dims, cylinder)))
    arm = PickPlaceRobot(robot, Payload(loaded, path.held))
    trajectory = JointTrajectory(path.time, path.q, path.qd, path.qdd)
    given: dict[str, Any] = dict(hardware or {})
    settings = RunSettings(float(path.time[-1]), float(rate), threads=threads, **given)
    record = simulate(arm, SampledTrajectory(trajectory), settings)
    recorded = [k for k in HARDWARE_ATTRIBUTES if k != "noise_parameters" or "noise_model" in given]
    tau_free, _ = inverse_dynamics(robot, BaseMotion.resting(path.time.size), trajectory, threads)
    return PickPlaceRun(
        path,
        record.tau,
        tau_free,
        record.base_wrench,
        record.tool_pose,
        cylinder,
        (float(place[0]), float(place[1])),
        dims,
        preset,
        branch,
        robot,
        parts,
        float(rate),
        {k: v for k, v in record.tables.items() if k != "joint_trajectory"},
        {k: record.attributes[k] for k in recorded if k in record.attributes},
    )


PICK_PLACE_ROBOT = "pick-place-arm"
"""The ``robot`` attribute of a pick-and-place run."""


def pick_place_record(run: PickPlaceRun) -> RunRecord:
    """The run as the one run record (module docstring), kind ``"pick-place"``."""
    path = run.path
    n = path.time.size
    c = run.cylinder
    attributes: dict[str, Any] = {
        "kind": "pick-place",
        "robot": PICK_PLACE_ROBOT,
        "source": run.preset,
        "preset": run.preset,
        "task": "pick-place",
        "moving_base": False,
        "base_frame": "pillar",
        "tool_frame": "grasp",
        "base_wrench_frame": "world axes, about the pillar's origin on the floor",
        "payload_joint": HAND_JOINT,
        "rate": run.rate or (float(1.0 / (path.time[1] - path.time[0])) if n > 1 else 0.0),
        "duration": float(path.time[-1]),
        "cylinder": {"x": c.x, "y": c.y, "radius": c.radius, "height": c.height, "mass": c.mass},
        "place": list(run.place),
        "branch": run.branch,
        "phases": list(PHASES),
        "phase_start": path.boundaries[:, 0].tolist(),
        "phase_end": path.boundaries[:, 1].tolist(),
        "held_interval": list(path.held_interval),
        "waypoints": path.waypoints.tolist(),
        "peak_payload_share": np.abs(run.tau - run.tau_free).max(axis=0).tolist(),
        "gravity": GRAVITY.tolist(),
        "units": _UNITS,
        **run.hardware,
        "version": __version__,
    }
    return RunRecord(
        time=path.time,
        joint_names=ARM_JOINTS,
        q=np.ascontiguousarray(path.q),
        qd=np.ascontiguousarray(path.qd),
        qdd=np.ascontiguousarray(path.qdd),
        tau=np.ascontiguousarray(run.tau),
        base_pose=np.broadcast_to(np.eye(4), (n, 4, 4)).copy(),
        base_wrench=np.ascontiguousarray(run.base_wrench),
        tool_pose=run.tool_pose,
        imu=np.zeros((n, 0, 6)),
        imu_mounts=(),
        urdf=run.robot.urdf or "",
        tables=dict(run.measured),
        attributes=attributes,
    )


def stored_cylinder(attributes: Mapping[str, Any]) -> Cylinder:
    """The cylinder a pick-and-place record's ``cylinder`` attribute describes.

    Raises:
        KeyError: no ``cylinder`` attribute.
        InputFileError: one that is not an object of the numbers ``x``, ``y``, ``radius``,
            ``height``, ``mass`` (``parameter="file"``).
        ParameterError: a cylinder that is not physical (as :class:`Cylinder`).
    """
    from aaria_pin.errors import InputFileError

    c = attributes["cylinder"]
    try:
        if not isinstance(c, Mapping):
            raise TypeError
        x, y, radius, height, mass = (
            float(c[key]) for key in ("x", "y", "radius", "height", "mass")
        )
    except (KeyError, TypeError, ValueError):
        raise InputFileError(
            f"attribute 'cylinder' is {c!r}; allowed: an object of the numbers x, y, radius,"
            " height, mass",
            parameter="file",
        ) from None
    return Cylinder(x, y, radius=radius, height=height, mass=mass)


def stored_preset(attributes: Mapping[str, Any]) -> str:
    """The arm preset a pick-and-place record names.

    Its ``preset`` attribute, else its ``source``, else ``"pick-place-arm"`` (a 0.1.0 file may
    name none).

    Raises:
        InputFileError: a ``preset`` or ``source`` that is not text (``parameter="file"``).
    """
    from aaria_pin.errors import InputFileError

    for name in ("preset", "source"):
        value = attributes.get(name)
        if value is not None and not isinstance(value, str):
            raise InputFileError(
                f"attribute {name!r} is {value!r}; allowed: an arm preset's name (text)",
                parameter="file",
            )
    return str(attributes.get("preset") or attributes.get("source") or PICK_PLACE_ROBOT)


def simulate_pick_place_from_record(stored: RunRecord, **overrides: Any) -> PickPlaceRun:
    """Re-make a pick-and-place run from the settings its record holds.

    The cylinder, the place, the arm preset, the rate, the IK branch and the hardware
    (:func:`~aaria_pin.core.run.settings.stored_hardware`; the IMU model only where recorded)
    come from the record's attributes; keyword arguments of :func:`simulate_pick_place` given
    here replace them (``cylinder`` and ``place`` too).

    Args:
        stored: a pick-and-place run's record (e.g. read from its run file)
        **overrides: arguments of :func:`simulate_pick_place`

    Returns:
        The run; with no overrides it equals the stored one.
    """
    meta = stored.metadata
    own = {**meta.extra, "source": meta.source}  # the kind's own attributes
    settings: dict[str, Any] = {
        "cylinder": stored_cylinder(own),
        "place": tuple(float(v) for v in own["place"]),
        "preset": stored_preset(own),
        "rate": meta.rate,
        "branch": str(own.get("branch", "nearest")),
        "hardware": {
            k: v
            for k, v in stored_hardware(stored.attributes).items()
            if k != "noise_model" or "noise_parameters" in stored.attributes
        },
    }
    settings.update(overrides)
    cylinder, place = settings.pop("cylinder"), settings.pop("place")
    return simulate_pick_place(cylinder, place, **settings)


def cylinder_track(
    held: ArrayLike,
    pick: tuple[float, float],
    place: tuple[float, float],
    height: float,
    tool_pose: Array,
) -> Array:
    """The cylinder's centre pose in the world at every sample (T, 4, 4) [m].

    Args:
        held: (T,) True where it is in the hand (one interval)
        pick: where it stands before the hold (x, y) [m]
        place: where it is put down, and stands after the hold (x, y) [m]
        height: its height [m]
        tool_pose: the grasp point's pose (T, 4, 4) [m]: the cylinder's centre while held
    """
    held = np.asarray(held, dtype=bool)
    poses = np.broadcast_to(np.eye(4), (held.size, 4, 4)).copy()
    poses[:, :3, 3] = (pick[0], pick[1], height / 2)
    if np.any(held):
        after = np.arange(held.size) > np.flatnonzero(held)[-1]
        poses[after, :3, 3] = (place[0], place[1], height / 2)
    poses[held] = np.asarray(tool_pose)[held]  # its mid-plane is symmetric: z up or down alike
    return poses


def effort_excess(run: PickPlaceRun) -> list[tuple[str, float, float]]:
    """Joints whose peak torque exceeds the URDF's effort limit.

    Returns:
        ``(joint, peak |tau|, limit)`` for each such joint, in model order [N·m or N].
    """
    limits = {j.name: j.effort for j in arm_joints(run.dims) if j.kind != "fixed"}
    peaks = np.abs(run.tau).max(axis=0)
    return [
        (name, float(peak), float(limits[name]))
        for name, peak in zip(ARM_JOINTS, peaks, strict=True)
        if peak > limits[name]
    ]


def write_pick_place_run(path: str | os.PathLike[str], run: PickPlaceRun) -> Path:
    """Write the run as a run file (``.h5``, ``.hdf5`` or ``.mat``), atomically.

    Raises:
        OutputFileError: as :func:`aaria_pin.files.runfile.write_run`.
    """
    from aaria_pin.files.runfile import write_run

    return write_run(path, pick_place_record(run))


def _remake_pick_place(stored: RunRecord, **overrides: Any) -> RunRecord:
    """The pick-and-place kind's re-make: :func:`simulate_pick_place_from_record` as a record.

    Raises:
        InputFileError: a stored attribute is missing.
    """
    from aaria_pin.errors import InputFileError

    try:
        return pick_place_record(simulate_pick_place_from_record(stored, **overrides))
    except KeyError as exc:
        raise InputFileError(
            f"pick-place run has no attribute {exc}; allowed: a run written by this toolkit",
            parameter=str(exc.args[0]) if exc.args else "attributes",
            element="run",
        ) from None


register_kind(
    RunKind("pick-place", _remake_pick_place, lambda record: "cylinder" in record.attributes)
)
