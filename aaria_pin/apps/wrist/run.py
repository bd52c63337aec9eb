"""The wrist report's simulation: a point-to-point motion, joint torques by RNEA, a run file.

The arm is Table 1 of the report with the masses, centres of mass and inertias of its Appendix B
parts (:func:`report_wrist`): part 2 on link 1, part 3 on link 2, part 4 (the gripper) on link 3,
each part's CAD frame taken as its link's frame (the report gives no other placement), centres of
mass in mm and principal moments of inertia in kg·mm² as listed. Every joint waits ``start``
seconds, then moves to its target (the report's ramp at constant speed, or a trapezoid with an
acceleration limit, for torques), then holds.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.aaria.dh_robot import DHRobot, build_dh_robot
from aaria_pin.aaria.presets import get_preset
from aaria_pin.core.profiles import ramp_profile, trapezoid_profile
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory, sample_times
from aaria_pin.errors import OutputFileError, ParameterError
from aaria_pin.files.io import atomic_output

__all__ = ["WristRun", "report_wrist", "simulate_wrist", "write_wrist_run"]


def report_wrist() -> DHRobot:
    """The ``spherical-wrist`` preset: Table 1 with the report's Appendix B parts."""
    preset = get_preset("spherical-wrist")
    return build_dh_robot(
        preset.table,
        preset.convention,
        name="spherical_wrist",
        mass_properties=preset.mass_properties,
    )


@dataclass(frozen=True)
class WristRun:
    """A wrist run and its settings.

    Attributes are the time [s], q, qd, qdd [rad, rad/s, rad/s²] and tau [N·m] (T × 3), the tool
    pose (T × 4 × 4, base frame), the targets [rad], speed [rad/s], acceleration [rad/s²] and the
    profile's name.
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


def simulate_wrist(
    targets: ArrayLike,
    *,
    speed: float = np.radians(40.0),
    acceleration: float = np.radians(80.0),
    profile: Literal["trapezoid", "ramp"] = "trapezoid",
    start: float = 2.0,
    duration: float | None = None,
    rate: float = 100.0,
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

    Returns:
        The run.
    """
    from aaria_pin.core.dynamics import inverse_dynamics
    from aaria_pin.core.kinematics import frame_poses

    goal = np.asarray(targets, dtype=float)
    if goal.shape != (3,) or not np.all(np.isfinite(goal)):
        raise ParameterError(f"targets of shape {goal.shape}; allowed: three finite angles")
    if not (np.isfinite(speed) and speed > 0 and np.isfinite(acceleration) and acceleration > 0):
        raise ParameterError(
            f"speed {speed!r} rad/s, acceleration {acceleration!r} rad/s^2; allowed: both > 0"
        )
    if duration is None:
        duration = start + float(np.max(np.abs(goal))) / speed + speed / acceleration + 1.0
    time = sample_times(duration, rate)
    columns = [
        trapezoid_profile(g, speed, acceleration, time, start)
        if profile == "trapezoid"
        else ramp_profile(g, speed, time, start)
        for g in goal
    ]
    q, qd, qdd = (np.column_stack([c[n] for c in columns]) for n in range(3))
    robot = report_wrist().model()
    trajectory = JointTrajectory(time, q, qd, qdd)
    base = BaseMotion.resting(time.size)
    tau, _ = inverse_dynamics(robot, base, trajectory)
    pose = frame_poses(robot, base, trajectory, [robot.tool_frame])[:, 0]
    return WristRun(time, q, qd, qdd, tau, pose, goal, float(speed), float(acceleration), profile)


def write_wrist_run(path: str | os.PathLike[str], run: WristRun) -> Path:
    """Write a wrist run to ``.h5`` (h5py) or ``.mat`` (scipy), atomically."""
    final = Path(path)
    arrays = {name: getattr(run, name) for name in ("time", "q", "qd", "qdd", "tau", "tool_pose")}
    attributes = {
        "targets_rad": run.targets,
        "speed_rad_s": run.speed,
        "acceleration_rad_s2": run.acceleration,
        "profile": run.profile,
    }
    suffix = final.suffix.lower()
    if suffix not in (".h5", ".hdf5", ".mat"):
        raise OutputFileError(f"{final}: unknown type {suffix!r}; allowed: .h5, .hdf5, .mat")
    with atomic_output(final) as temporary:
        if suffix == ".mat":
            from scipy.io import savemat

            savemat(temporary, {**arrays, **attributes}, do_compression=True)
        else:
            import h5py

            with h5py.File(temporary, "w") as handle:
                for name, array in arrays.items():
                    handle.create_dataset(name, data=array)
                for key, value in attributes.items():
                    handle.attrs[key] = value
    return final
