"""The wrist report's simulation: a point-to-point motion, joint torques by RNEA, a run file.

The arm is Table 1 of the report with the masses, centres of mass and inertias of its Appendix B
parts (:func:`report_wrist`): part 2 on link 1, part 3 on link 2, part 4 (the gripper) on link 3,
each part's CAD frame taken as its link's frame (the report gives no other placement), centres of
mass in mm and principal moments of inertia in kg·mm² as listed. Every joint waits ``start``
seconds, then moves to its target (the report's ramp at constant speed, or a trapezoid with an
acceleration limit, for torques), then holds.

The run is computed by the run engine every robot shares (:func:`~aaria_pin.core.run.simulate`: the
adapter :class:`WristRobotRun`, the motion :class:`PointToPoint`) on a fixed mount (a free-flyer
held at rest, so the base wrench is the mount's load), with the DH robot's IMUs (base, tool, two per
link; noise-free), and becomes the one :class:`~aaria_pin.core.record.RunRecord`
(:func:`wrist_record`, kind ``"wrist"``), written by :func:`write_wrist_run` as any run file.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar, Literal

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin._version import __version__
from aaria_pin.aaria.arm_run import DHImuSlots
from aaria_pin.aaria.dh_robot import DHRobot, build_dh_robot
from aaria_pin.aaria.presets import get_preset
from aaria_pin.core.excitation import check_joint_range
from aaria_pin.core.imu_noise import ADIS16485
from aaria_pin.core.model import RobotModel
from aaria_pin.core.profiles import ramp_profile, trapezoid_profile
from aaria_pin.core.record import ColumnView, ImuMount, RunRecord
from aaria_pin.core.run import (
    FixedMount,
    FollowedMotion,
    RunKind,
    RunRobot,
    RunSettings,
    register_kind,
    sampling_attributes,
    simulate,
)
from aaria_pin.core.run.measured import HARDWARE_ATTRIBUTES
from aaria_pin.core.run.settings import stored_hardware
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import MAX_DURATION, BaseMotion, JointTrajectory, piece_times
from aaria_pin.errors import ParameterError

__all__ = [
    "WRIST_ROBOT",
    "PointToPoint",
    "WristRobotRun",
    "WristRun",
    "report_wrist",
    "simulate_wrist",
    "simulate_wrist_from_record",
    "wrist_record",
    "wrist_robot",
    "write_wrist_run",
]

WRIST_ROBOT = "spherical-wrist"
"""The wrist's preset name (the ``robot`` attribute of its runs)."""

WRIST_JOINTS = ("joint1", "joint2", "joint3")
"""The wrist's joints (the record's columns)."""


def report_wrist() -> DHRobot:
    """The ``spherical-wrist`` preset: Table 1 with the report's Appendix B parts."""
    preset = get_preset(WRIST_ROBOT)
    return build_dh_robot(
        preset.table,
        preset.convention,
        name="spherical_wrist",
        mass_properties=preset.mass_properties,
    )


@dataclass(frozen=True)
class WristRobotRun(FixedMount, DHImuSlots):
    """The wrist as the run engine's robot: on a fixed mount, its DH robot's IMUs.

    The model has a free-flyer held at rest, so the base wrench is the mount's load.

    Attributes:
        arm: the wrist (:func:`report_wrist`)
        model: its model with a free-flyer
    """

    arm: DHRobot
    model: RobotModel
    kind: ClassVar[str] = "wrist"
    columns: ClassVar[None] = None
    torque_name: ClassVar[str] = "torques"
    tables: ClassVar[dict[str, Array]] = {}
    views: ClassVar[dict[str, ColumnView]] = {}

    @property
    def joint_names(self) -> tuple[str, ...]:
        """``joint1``, ``joint2``, ``joint3``."""
        return WRIST_JOINTS

    @property
    def limits(self) -> tuple[Array, Array]:
        """The model's position limits (±2π) [rad]."""
        return self.model.position_limits

    @property
    def urdf(self) -> str:
        """The wrist's URDF text."""
        return self.arm.urdf

    def attributes(self, peaks: Array) -> dict[str, Any]:
        """``robot``, ``moving_base`` (False), frames."""
        return {
            "robot": WRIST_ROBOT,
            "moving_base": False,
            "base_frame": "base",
            "tool_frame": self.model.tool_frame,
        }


def wrist_robot() -> WristRobotRun:
    """The ``spherical-wrist`` preset as the run engine's robot."""
    wrist = report_wrist()
    return WristRobotRun(wrist, wrist.model(moving_base=True))


@dataclass(frozen=True)
class PointToPoint(FollowedMotion):
    """Every joint waits ``start``, moves to its target at ``speed``, then holds (a motion).

    Stored as the table ``targets`` [rad] and the attributes ``speed_rad_s``,
    ``acceleration_rad_s2``, ``profile`` and ``start_s``.

    Attributes:
        targets: the joint targets [rad]
        speed: joint speed [rad/s]
        acceleration: acceleration limit of the trapezoid [rad/s²]
        profile: ``"trapezoid"`` (:func:`~aaria_pin.core.profiles.trapezoid_profile`) or
            ``"ramp"`` (:func:`~aaria_pin.core.profiles.ramp_profile`)
        start: when the joints start moving [s]
    """

    targets: Array
    speed: float
    acceleration: float
    profile: str
    start: float
    name: ClassVar[str] = "point-to-point"

    def checked(self, robot: RunRobot, samples: int, rate: float) -> PointToPoint:
        """Itself, when every joint stays within the robot's limits over the run.

        Raises:
            ParameterError: (``targets``) a joint beyond its limit, naming the joint, the time,
                the value and the limit (:func:`~aaria_pin.core.excitation.check_joint_range`).
        """
        times = piece_times(0, samples, rate)
        q = self.trajectory(robot, (0, samples), times, robot.base(times)).q
        check_joint_range(times, q, robot.limits, robot.joint_names, "targets")
        return self

    def trajectory(
        self, robot: RunRobot, span: tuple[int, int], times: Array, base: BaseMotion
    ) -> JointTrajectory:
        """Each joint's profile at ``times``."""
        columns = [
            trapezoid_profile(g, self.speed, self.acceleration, times, self.start)
            if self.profile == "trapezoid"
            else ramp_profile(g, self.speed, times, self.start)
            for g in self.targets
        ]
        q, qd, qdd = (np.column_stack([c[n] for c in columns]) for n in range(3))
        return JointTrajectory(times, q, qd, qdd)

    def record(self, robot: RunRobot) -> tuple[dict[str, Array], dict[str, Any]]:
        """``targets``, and the settings as attributes."""
        attributes = {
            "speed_rad_s": self.speed,
            "acceleration_rad_s2": self.acceleration,
            "profile": self.profile,
            "start_s": self.start,
        }
        return {"targets": np.asarray(self.targets, dtype=float).copy()}, attributes


@dataclass(frozen=True)
class WristRun:
    """A wrist run and its settings.

    Attributes:
        time: sample times, T [s]
        q: joint values, T × 3 [rad]
        qd: joint velocities, T × 3 [rad/s]
        qdd: joint accelerations, T × 3 [rad/s²]
        tau: joint torques, T × 3 [N·m]
        tool_pose: the tool's pose, T × 4 × 4 (base frame = world) [m]
        targets: the joint targets, 3 [rad]
        speed: joint speed [rad/s]
        acceleration: acceleration limit of the trapezoid [rad/s²]
        profile: the profile's name, ``"trapezoid"`` or ``"ramp"``
        start: when the joints start moving [s]
        rate: sample rate [Hz]
        duration: run length [s]
        base_wrench: the wrench the fixed mount applies, T × 6 ``[fx fy fz mx my mz]`` in world
            axes about the base origin [N, N·m]
        imu: noise-free IMU signals ``[wx wy wz fx fy fz]``, T × S × 6 [rad/s, m/s²]
        imu_mounts: the IMUs (the DH robot's slots: base, tool, two per link)
        urdf: the URDF text of the wrist
        tool_frame: the tool frame's name
        measured: the hardware's tables (``q_measured``, ``tau_measured``, ``tau_motor`` ...;
            none without hardware)
        hardware: the attributes recording the hardware
            (:data:`~aaria_pin.core.run.measured.HARDWARE_ATTRIBUTES`; none: the ADIS16485 IMU
            model and no joint hardware)
    """

    time: Array
    q: Array
    qd: Array
    qdd: Array
    tau: Array
    tool_pose: Array
    targets: Array
    speed: float
    acceleration: float
    profile: str
    start: float
    rate: float
    duration: float
    base_wrench: Array
    imu: Array
    imu_mounts: tuple[ImuMount, ...]
    urdf: str
    tool_frame: str
    measured: Mapping[str, Array] = field(default_factory=dict)
    hardware: Mapping[str, Any] = field(default_factory=dict)


def simulate_wrist(
    targets: ArrayLike,
    *,
    speed: float = np.radians(40.0),
    acceleration: float = np.radians(80.0),
    profile: Literal["trapezoid", "ramp"] = "trapezoid",
    start: float = 2.0,
    duration: float | None = None,
    rate: float = 100.0,
    hardware: Mapping[str, Any] | None = None,
) -> WristRun:
    """Move the wrist to joint targets and compute the torques along the way.

    Args:
        targets: joint targets θ1, θ2, θ3 [rad]
        speed: joint speed [rad/s] (the report's default 40°/s)
        acceleration: acceleration limit of the trapezoid [rad/s²]
        profile: ``"trapezoid"`` (smooth, for torques) or ``"ramp"`` (the report's; its
            corners' infinite accelerations are left out of the torques)
        start: when the joints start moving [s] (the report waits 2 s)
        duration: run length [s] (default: 1 s after the slowest joint arrives)
        rate: sample rate [Hz]
        hardware: the run's hardware as :class:`~aaria_pin.core.run.RunSettings` fields
            (``noise_model``, ``encoder``, ``torque_sensor``, ``actuator``;
            :func:`~aaria_pin.aaria.hardware.hardware_run_options`); the IMUs are noise-free,
            so the IMU model is recorded and changes no signal

    Returns:
        The run.

    Raises:
        ParameterError: targets that are not three finite angles or that take a joint beyond
            its limits (±2π), a speed or acceleration that is not positive, an unknown
            profile, or hardware its models refuse.
    """
    goal = np.asarray(targets, dtype=float)
    if goal.shape != (3,):
        raise ParameterError(
            f"targets have shape {goal.shape}; allowed: three angles (3,)",
            parameter="targets",
            value=goal.shape,
            allowed="three angles, shape (3,)",
        )
    if not np.all(np.isfinite(goal)):
        raise ParameterError(
            f"targets are {', '.join(f'{v:g}' for v in goal)} rad; allowed: finite angles",
            parameter="targets",
            value=goal.tolist(),
            allowed="three finite angles",
        )
    for name, value in (("speed", speed), ("acceleration", acceleration)):
        if not (np.isfinite(value) and value > 0):
            unit = "rad/s" if name == "speed" else "rad/s^2"
            raise ParameterError(
                f"{name} is {float(value):g} {unit}; allowed: finite and > 0",
                parameter=name,
                value=float(value),
                allowed="finite and > 0",
            )
    if profile not in ("trapezoid", "ramp"):
        raise ParameterError(parameter="profile", value=profile, allowed="trapezoid, ramp")
    if duration is None:
        duration = start + float(np.max(np.abs(goal))) / speed + speed / acceleration + 1.0
        if not duration <= MAX_DURATION:  # say which inputs made it, not a duration not given
            raise ParameterError(
                f"speed {float(speed):g} rad/s ({np.degrees(speed):g} deg/s) and acceleration"
                f" {float(acceleration):g} rad/s^2 ({np.degrees(acceleration):g} deg/s^2) need a"
                f" run of {duration:.3g} s to reach the targets; allowed: a run of at most"
                f" {MAX_DURATION:g} s (a higher speed or acceleration, or a shorter duration)",
                parameter="speed",
            )
    motion = PointToPoint(goal, float(speed), float(acceleration), profile, float(start))
    settings = RunSettings(float(duration), float(rate), noise=False, **(hardware or {}))
    robot = wrist_robot()
    record = simulate(robot, motion, settings)
    motion_tables, _ = motion.record(robot)
    return WristRun(
        record.time,
        record.q,
        record.qd,
        record.qdd,
        record.tau,
        record.tool_pose,
        goal,
        float(speed),
        float(acceleration),
        profile,
        float(start),
        float(rate),
        float(duration),
        record.base_wrench,
        record.imu,
        record.imu_mounts,
        record.urdf,
        record.metadata.tool_frame,
        {k: v for k, v in record.tables.items() if k not in motion_tables},
        {k: record.attributes[k] for k in HARDWARE_ATTRIBUTES if k in record.attributes},
    )


def wrist_record(run: WristRun) -> RunRecord:
    """The wrist run as the one run record (kind ``"wrist"``, fixed base, the targets a table).

    The settings that re-make it (:func:`simulate_wrist_from_record`) are the table ``targets``
    [rad] and the attributes ``speed_rad_s``, ``acceleration_rad_s2``, ``profile``, ``start_s``,
    ``rate`` and ``duration``.
    """
    samples = run.time.size
    attributes: dict[str, Any] = {
        "kind": "wrist",
        "robot": WRIST_ROBOT,
        **sampling_attributes(run.rate, run.duration, 0, False, ADIS16485),
        **run.hardware,
        "moving_base": False,
        "base_frame": "base",
        "tool_frame": run.tool_frame,
        "speed_rad_s": run.speed,
        "acceleration_rad_s2": run.acceleration,
        "profile": run.profile,
        "start_s": run.start,
        "version": __version__,
    }
    return RunRecord(
        time=run.time,
        joint_names=WRIST_JOINTS,
        q=run.q,
        qd=run.qd,
        qdd=run.qdd,
        tau=run.tau,
        base_pose=np.broadcast_to(np.eye(4), (samples, 4, 4)).copy(),
        base_wrench=run.base_wrench,
        tool_pose=run.tool_pose,
        imu=run.imu,
        imu_mounts=run.imu_mounts,
        urdf=run.urdf,
        tables={"targets": np.asarray(run.targets, dtype=float).copy(), **run.measured},
        attributes=attributes,
    )


def simulate_wrist_from_record(stored: RunRecord, **overrides: Any) -> WristRun:
    """Re-make a wrist run from the settings its record holds (see :func:`wrist_record`).

    Args:
        stored: a wrist run's record (e.g. read from its run file)
        **overrides: keyword arguments of :func:`simulate_wrist` that replace the stored ones
            (``hardware`` as stored unless given: :func:`stored_hardware`)

    Returns:
        The run; with no overrides it equals the stored one.
    """
    attributes = stored.attributes
    targets = stored.tables.get("targets", attributes.get("targets_rad"))
    names = {
        "speed_rad_s": "speed",
        "acceleration_rad_s2": "acceleration",
        "start_s": "start",
        "duration": "duration",
        "rate": "rate",
    }
    settings: dict[str, Any] = {
        parameter: float(attributes[name])
        for name, parameter in names.items()
        if name in attributes
    }
    settings["hardware"] = stored_hardware(attributes)
    if "profile" in attributes:
        settings["profile"] = str(attributes["profile"])
    if "duration" not in settings:  # a 0.1.0 wrist file: its samples give the grid
        settings["duration"] = float(stored.time[-1])
    if "rate" not in settings:
        settings["rate"] = float(1.0 / (stored.time[1] - stored.time[0]))
    settings.update(overrides)
    return simulate_wrist(np.asarray(targets, dtype=float).reshape(-1), **settings)


def write_wrist_run(path: str | os.PathLike[str], run: WristRun) -> Path:
    """Write a wrist run as a run file (``.h5``, ``.hdf5`` or ``.mat``), atomically.

    Raises:
        OutputFileError: as :func:`aaria_pin.files.runfile.write_run`.
    """
    from aaria_pin.files.runfile import write_run

    return write_run(path, wrist_record(run))


def _remake_wrist(stored: RunRecord, **overrides: Any) -> RunRecord:
    """The wrist kind's re-make: :func:`simulate_wrist_from_record` as a record."""
    return wrist_record(simulate_wrist_from_record(stored, **overrides))


register_kind(
    RunKind(
        "wrist",
        _remake_wrist,
        lambda record: "targets" in record.tables or "targets_rad" in record.attributes,
    )
)
