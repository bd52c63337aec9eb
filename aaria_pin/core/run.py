"""The run pipeline every robot shares: IMUs, tool pose, torques and base wrench over a run.

A producer (an Aaria DH arm, a URDF robot, the wrist) builds its model, its joint trajectory
and its base motion, then calls :func:`simulate_series`: IMU kinematics over the whole time grid
in one compiled pass (:func:`~aaria_pin.core.kinematics.trajectory_signals`), ADIS16485-like
noise if asked (:func:`~aaria_pin.core.imu_noise.add_imu_noise`), torques and the base wrench
by Pinocchio's batched RNEA (:func:`~aaria_pin.core.dynamics.inverse_dynamics`). The result goes
into the one :class:`~aaria_pin.core.record.RunRecord` with :func:`sampling_attributes`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from aaria_pin.core.imu_noise import ADIS16485, ImuNoiseModel, noise_attributes
from aaria_pin.core.model import GRAVITY, RobotModel
from aaria_pin.core.se3 import Array
from aaria_pin.core.seeds import seed_attributes, stored_seed
from aaria_pin.core.trajectory import DEFAULT_DURATION, DEFAULT_RATE, BaseMotion, JointTrajectory

__all__ = [
    "DEFAULT_DURATION",
    "DEFAULT_RATE",
    "UNITS",
    "RunSeries",
    "sampling_attributes",
    "simulate_series",
    "stored_sampling",
]

UNITS = {
    "time": "s",
    "q": "rad (revolute) or m (prismatic)",
    "angular_velocity": "rad/s",
    "specific_force": "m/s^2",
    "tau": "N*m (revolute) or N (prismatic)",
    "base_wrench": "N (force), N*m (moment about the base origin), world-aligned axes",
    "length": "m",
}
"""The ``units`` attribute of a run (the units of each quantity)."""


def sampling_attributes(
    rate: float,
    duration: float,
    seed: int | np.random.SeedSequence,
    noise: bool,
    noise_model: ImuNoiseModel,
) -> dict[str, Any]:
    """The attributes every run records: rate, duration, seed, noise, gravity, units.

    Args:
        rate: sample rate [Hz]
        duration: run length [s]
        seed: seed of the IMU noise (or a data set run's ``SeedSequence``)
        noise: whether the IMU signals carry noise
        noise_model: the IMU noise parameters
    """
    return {
        "rate": float(rate),
        "duration": float(duration),
        **seed_attributes(seed),
        "noise": bool(noise),
        "noise_parameters": noise_attributes(noise_model),
        "gravity": GRAVITY.tolist(),
        "units": UNITS,
    }


def stored_sampling(attributes: dict[str, Any]) -> dict[str, Any]:
    """The ``duration`` [s], ``rate`` [Hz], ``seed`` and ``noise`` a record's attributes hold.

    The inverse of :func:`sampling_attributes`, as keyword arguments of a producer, for
    re-making a run from its record (defaults where an attribute is missing).
    """
    return {
        "duration": float(attributes.get("duration", DEFAULT_DURATION)),
        "rate": float(attributes.get("rate", DEFAULT_RATE)),
        "seed": stored_seed(attributes),
        "noise": bool(attributes.get("noise", True)),
    }


@dataclass(frozen=True)
class RunSeries:
    """The computed series of a run (the record's arrays beyond the joint motion).

    Attributes:
        imu: IMU signals ``[wx wy wz fx fy fz]``, T × S × 6 [rad/s, m/s²] (zeros in empty slots)
        tool_pose: ``T_world_tool``, T × 4 × 4 [m]
        tau: joint torques [N·m] or forces [N], T × n, model order
        base_wrench: wrench the base mount applies, T × 6 ``[fx fy fz mx my mz]``, world-aligned
            axes, about the base origin [N, N·m]
        base_pose: ``T_world_base``, T × 4 × 4 [m]
    """

    imu: Array
    tool_pose: Array
    tau: Array
    base_wrench: Array
    base_pose: Array


def simulate_series(
    robot: RobotModel,
    base: BaseMotion,
    trajectory: JointTrajectory,
    *,
    imu_frames: Sequence[str],
    imu_slots: Sequence[int] | None = None,
    n_slots: int | None = None,
    rate: float,
    seed: int | np.random.SeedSequence = 0,
    noise: bool = True,
    noise_model: ImuNoiseModel = ADIS16485,
    threads: int = 1,
) -> RunSeries:
    """IMU signals, tool pose, torques, base wrench and base pose over a whole trajectory.

    Args:
        robot: the model (with ``moving_base`` the base follows ``base``; a free-flyer held at
            rest gives the fixed mount's load as the base wrench)
        base: the base motion at the sample times
        trajectory: the joint motion, columns in model order
        imu_frames: the model frames of the IMUs that exist
        imu_slots: the slot of ``imu`` each of ``imu_frames`` fills (default 0, 1, …); the
            other slots stay zero (empty slots)
        n_slots: S, the number of IMU slots (default ``len(imu_frames)``)
        rate: sample rate [Hz] (for the noise)
        seed: seed of the IMU noise
        noise: add IMU noise (``False`` gives the exact signals)
        noise_model: IMU noise parameters
        threads: worker threads of the batched RNEA

    Returns:
        The series.
    """
    from aaria_pin.core.dynamics import inverse_dynamics
    from aaria_pin.core.imu_noise import add_imu_noise
    from aaria_pin.core.kinematics import trajectory_signals

    samples = trajectory.q.shape[0]
    slots = list(range(len(imu_frames))) if imu_slots is None else list(imu_slots)
    imu = np.zeros((samples, len(imu_frames) if n_slots is None else n_slots, 6))
    exact, tool_pose = trajectory_signals(
        robot,
        base,
        trajectory,
        imu_frames,
        [robot.tool_frame],
        imu_out=None if noise else imu,  # noise-free: straight into the record's array
        imu_slots=None if noise else slots,
    )
    if noise and slots:
        imu[:, slots] = add_imu_noise(exact, rate, np.random.default_rng(seed), noise_model)
    tau, base_wrench = inverse_dynamics(robot, base, trajectory, threads)
    if robot.moving_base:
        base_pose = base.T_world_base()
    else:
        base_pose = np.broadcast_to(np.eye(4), (samples, 4, 4)).copy()
    return RunSeries(
        imu,
        tool_pose[:, 0],
        np.ascontiguousarray(tau),
        base_wrench,
        np.ascontiguousarray(base_pose),
    )
