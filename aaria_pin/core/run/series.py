"""The series every robot's run shares: IMUs, tool pose, torques and base wrench over a run.

The engine (:mod:`aaria_pin.core.run.engine`) gives :func:`simulate_series` a robot's model, its
joint trajectory and its base motion over a piece of the run: IMU kinematics over the whole time
grid in one compiled pass (:func:`~aaria_pin.core.kinematics.trajectory_signals`),
the IMU errors and noise if asked (:mod:`~aaria_pin.core.imu_errors`,
:func:`~aaria_pin.core.imu_noise.add_imu_noise`), torques and the
base wrench by Pinocchio's batched RNEA (:func:`~aaria_pin.core.dynamics.inverse_dynamics`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from aaria_pin.core.imu_errors import ImuErrors, draw_imu_errors
from aaria_pin.core.imu_noise import ImuNoiseModel, ImuNoiseStream
from aaria_pin.core.model import RobotModel
from aaria_pin.core.run.settings import RunSettings
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory

__all__ = [
    "ImuSlots",
    "Payload",
    "RunSeries",
    "carry_payload",
    "imu_errors",
    "noise_stream",
    "simulate_series",
]


def noise_stream(
    samples: int,
    n_imu: int,
    rate: float,
    seed: int | np.random.SeedSequence,
    noise: bool,
    noise_model: ImuNoiseModel,
    pieces: int,
) -> ImuNoiseStream | None:
    """The noise of a run computed in ``pieces`` (None if one piece, no noise or no IMU)."""
    if pieces <= 1 or not noise or n_imu < 1:
        return None
    return ImuNoiseStream(samples, n_imu, rate, np.random.default_rng(seed), noise_model)


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


@dataclass(frozen=True)
class ImuSlots:
    """The IMUs of a run's record.

    Attributes:
        frames: the model frames of the IMUs that exist
        slots: the record slot each of ``frames`` fills (None: 0, 1, …); the other slots stay
            zero (empty slots)
        n_slots: S, the record's IMU slots (None: ``len(frames)``)
        errors: the run's IMU errors drawn once (:func:`imu_errors`; None: every term off)
    """

    frames: Sequence[str]
    slots: Sequence[int] | None = None
    n_slots: int | None = None
    errors: ImuErrors | None = None

    @property
    def record_slots(self) -> list[int]:
        """The record slot of each frame (``slots``, or 0, 1, … by default)."""
        return list(range(len(self.frames))) if self.slots is None else list(self.slots)

    @property
    def slot_count(self) -> int:
        """S, the record's IMU slots (``n_slots``, or one per frame by default)."""
        return len(self.frames) if self.n_slots is None else self.n_slots


def imu_errors(
    settings: RunSettings, seed: int | np.random.SeedSequence, samples: int, imus: ImuSlots
) -> ImuErrors | None:
    """The run's IMU errors drawn once (:func:`~aaria_pin.core.imu_errors.draw_imu_errors`).

    None without noise, without an IMU, or with every term of 0.4 off (nothing is drawn).

    Args:
        settings: the run's settings (``noise``, ``noise_model``, ``rate``)
        seed: the run's noise seed (its IMU sensor-error stream is derived from it)
        samples: T, the run's samples
        imus: the run's IMUs and their record slots
    """
    from aaria_pin.core.seeds import sensor_sequence

    slots = tuple(imus.record_slots)
    if not settings.noise or not slots or not settings.noise_model.new_terms:
        return None
    sequence = sensor_sequence(seed, "imu")
    model = settings.noise_model
    return draw_imu_errors(model, sequence, samples, settings.rate, slots, imus.slot_count)


@dataclass(frozen=True)
class Payload:
    """A load the robot carries over part of its run (e.g. a gripped object).

    A robot adapter that has one exposes it as its ``payload`` attribute; the engine then
    takes the torques and base wrench of the held samples from the loaded model.

    Attributes:
        model: the robot's model with the load added to the body that carries it
        held: (T,) True at the run's samples where it is carried
    """

    model: RobotModel
    held: NDArray[np.bool_]


def carry_payload(
    series: RunSeries,
    payload: Payload,
    base: BaseMotion,
    trajectory: JointTrajectory,
    start: int,
    threads: int = 1,
) -> RunSeries:
    """The series with the torques and base wrench of the held samples from the loaded model.

    RNEA is per sample, so the loaded model's RNEA over the whole piece, taken at the held
    samples, is that of the held samples alone.

    Args:
        series: the piece's series on the bare model
        payload: the load and where it is carried over the whole run
        base: the piece's base motion
        trajectory: the piece's joint motion
        start: the index of the piece's first sample in the run
        threads: RNEA worker threads

    Returns:
        The series, its ``tau`` and ``base_wrench`` loaded where held (the same series if the
        piece holds nothing).
    """
    from dataclasses import replace

    from aaria_pin.core.dynamics import inverse_dynamics

    held = np.asarray(payload.held, dtype=bool)[start : start + trajectory.q.shape[0]]
    if not np.any(held):
        return series
    tau_loaded, wrench_loaded = inverse_dynamics(payload.model, base, trajectory, threads)
    tau, wrench = series.tau.copy(), series.base_wrench.copy()
    tau[held], wrench[held] = tau_loaded[held], wrench_loaded[held]
    return replace(series, tau=tau, base_wrench=wrench)


def simulate_series(
    robot: RobotModel,
    base: BaseMotion,
    trajectory: JointTrajectory,
    imus: ImuSlots,
    settings: RunSettings,
    seed: int | np.random.SeedSequence = 0,
    noise_stream: ImuNoiseStream | None = None,
    start: int = 0,
) -> RunSeries:
    """IMU signals, tool pose, torques, base wrench and base pose over a whole trajectory.

    Args:
        robot: the model (with ``moving_base`` the base follows ``base``; a free-flyer held at
            rest gives the fixed mount's load as the base wrench)
        base: the base motion at the sample times
        trajectory: the joint motion, columns in model order
        imus: the IMUs that exist and the record slots they fill
        settings: the run's ``rate`` [Hz] (for the noise), ``noise``, ``noise_model`` and
            ``threads`` (of the batched RNEA)
        seed: seed of the IMU noise
        noise_stream: for a piece of a longer run (:func:`chunk_bounds`), the run's noise
            (:class:`~aaria_pin.core.imu_noise.ImuNoiseStream`, over the existing IMUs); the
            piece's measurements are then those of the whole run (``seed`` is not used)
        start: the index of the piece's first sample in the run (with ``noise_stream``)

    Returns:
        The series.
    """
    from aaria_pin.core.dynamics import inverse_dynamics
    from aaria_pin.core.imu_noise import add_imu_noise
    from aaria_pin.core.kinematics import trajectory_signals

    samples = trajectory.q.shape[0]
    imu_frames, noise = list(imus.frames), settings.noise
    slots, n_imu_slots = imus.record_slots, imus.slot_count
    # No empty slot: the noisy measurements are the record's array as they come (no zeros, no
    # scatter: a 6.7 MB copy and its page faults, 1–1.5 ms of a 10,000-sample run of 14 IMUs),
    # and no array is made for them beforehand.
    every_slot = slots == list(range(n_imu_slots))
    measured_is_record = noise and every_slot and bool(slots)
    shape = (samples, n_imu_slots, 6)
    record_imu: Array | None = None
    if not measured_is_record:
        record_imu = np.empty(shape) if every_slot and not noise else np.zeros(shape)
    exact, tool_pose = trajectory_signals(
        robot,
        base,
        trajectory,
        imu_frames,
        [robot.tool_frame],
        imu_out=None if noise else record_imu,  # noise-free: straight into the record's array
        imu_slots=None if noise else slots,
    )
    imu = exact if record_imu is None else record_imu
    if noise and slots:
        model = settings.noise_model
        if imus.errors is not None:  # the terms drawn once per run, before the noise
            exact, model = imus.errors.sensed(exact, start), imus.errors.noise_model
        if noise_stream is not None:
            measured = noise_stream.measure(exact, start)
        else:
            measured = add_imu_noise(exact, settings.rate, np.random.default_rng(seed), model)
        if record_imu is None:
            imu = measured  # a new (T, S, 6) array: the record's, without a copy
        else:
            record_imu[:, slots] = measured
    tau, base_wrench = inverse_dynamics(robot, base, trajectory, settings.threads)
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
