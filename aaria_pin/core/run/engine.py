"""The run engine: one robot, one motion, one set of settings → the run record.

:func:`simulate_pieces` owns every step a run of any robot kind takes, in this order: the
run's samples (held whole or in pieces), the motion checked once against the robot, the
pieces (:func:`~aaria_pin.core.run.chunks.chunk_bounds`), the run's IMU noise stream (so the
pieces' noise is the whole run's), and per piece the base motion, the joint motion (the torque
drive integrates the whole run in one piece), the series
(:func:`~aaria_pin.core.run.series.simulate_series`), the peak torques so far, the joint
channels (encoders, torque sensors, actuators: :func:`~aaria_pin.core.run.measured.run_sensors`)
and the record.
:func:`simulate` is the same run held whole.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from typing import Any, TypedDict

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin._version import __version__
from aaria_pin.core.arguments import checked
from aaria_pin.core.joint_sensors import JointColumns
from aaria_pin.core.model import RobotModel
from aaria_pin.core.record import SERIES, TIMED_HARDWARE, RunRecord
from aaria_pin.core.run.chunks import chunk_bounds, join_chunks
from aaria_pin.core.run.drives import equipped
from aaria_pin.core.run.measured import run_sensors
from aaria_pin.core.run.motion import Motion, SineTable
from aaria_pin.core.run.robot import RunRobot
from aaria_pin.core.run.sensor import (
    Sensor,
    SensorState,
    measure,
    measure_channels,
    sensor_attributes,
)
from aaria_pin.core.run.series import (
    ImuSlots,
    Payload,
    carry_payload,
    imu_errors,
    noise_stream,
    simulate_series,
)
from aaria_pin.core.run.settings import RunSettings
from aaria_pin.core.seeds import RunSeeds, check_seed
from aaria_pin.core.trajectory import piece_times

__all__ = [
    "RunRequest",
    "RunTables",
    "Seeds",
    "check_options",
    "noise_seed",
    "simulate",
    "simulate_pieces",
]

Seeds = RunSeeds | int | np.random.SeedSequence
"""A run's seeds: its :class:`~aaria_pin.core.seeds.RunSeeds`, or the seed of its IMU noise
(an integer from 0 to 2⁶³ - 1, or a data set run's ``SeedSequence``)."""


def noise_seed(seeds: Seeds) -> int | np.random.SeedSequence:
    """The seed of a run's IMU noise, checked.

    Raises:
        ParameterError: a seed out of range (parameter ``seed``).
    """
    if isinstance(seeds, RunSeeds):
        return seeds.noise
    check_seed(seeds)
    return seeds


@checked
def simulate(
    robot: RunRobot,
    motion: Motion | None = None,
    settings: RunSettings | None = None,
    seeds: Seeds = 0,
    sensors: Sequence[Sensor] = (),
) -> RunRecord:
    """Simulate one run of a robot, held whole.

    Args:
        robot: the robot (an adapter of its kind, e.g.
            :func:`aaria_pin.aaria.simulate.dh_arm` or
            :func:`aaria_pin.core.urdf_run.urdf_robot_run`)
        motion: the joint motion (default: the robot's joint table,
            :class:`~aaria_pin.core.run.motion.SineTable`)
        settings: duration, rate, noise, threads (default :class:`RunSettings`); its
            ``chunk`` is not used
        seeds: the run's seeds (:data:`Seeds`)
        sensors: sensors beside the IMUs (:mod:`~aaria_pin.core.run.sensor`), each recorded
            as the table ``sensor_<name>`` and described in the attribute ``sensors``

    Returns:
        The run record.

    Raises:
        ParameterError: a seed out of range, more samples than a run held whole may have, or
            a motion the robot cannot follow.
    """
    settings = RunSettings() if settings is None else settings
    whole = replace(settings, chunk=None)
    return join_chunks(simulate_pieces(robot, motion, whole, seeds, sensors))


@checked
def simulate_pieces(
    robot: RunRobot,
    motion: Motion | None = None,
    settings: RunSettings | None = None,
    seeds: Seeds = 0,
    sensors: Sequence[Sensor] = (),
) -> Iterator[RunRecord]:
    """:func:`simulate` in time pieces of ``settings.chunk`` samples: one record per piece.

    The joint and base motions are functions of time, so each piece is computed on its own
    sample times; the IMU noise of the pieces is that of the whole run
    (:class:`~aaria_pin.core.imu_noise.ImuNoiseStream`), so the pieces put together
    (:func:`~aaria_pin.core.run.chunks.join_chunks`) are bit for bit :func:`simulate`'s record
    and memory does not grow with the run's length. Each piece carries the run's tables, views
    and attributes; its attributes cover the run up to its end (peaks so far), so the last
    piece's are the whole run's. A motion computed whole (the torque drive) is one piece. A run
    in pieces may have up to :data:`~aaria_pin.core.trajectory.MAX_STREAMED_SAMPLES` samples,
    one held whole up to :data:`~aaria_pin.core.trajectory.MAX_SAMPLES`.

    Args:
        robot: as in :func:`simulate`
        motion: as in :func:`simulate`
        settings: as in :func:`simulate`; ``chunk`` the samples per piece (None: one piece)
        seeds: as in :func:`simulate`
        sensors: as in :func:`simulate` (each piece's table holds the piece's signals)

    Yields:
        The run record of each piece, ``time`` the piece's sample times [s].

    Raises:
        ParameterError: as :func:`simulate` (before any piece is computed).
    """
    settings = RunSettings() if settings is None else settings
    seed = noise_seed(seeds)
    run_motion: Motion = SineTable() if motion is None else motion
    whole = run_motion.whole or settings.needs_whole_run
    samples = settings.samples(whole=whole)
    settings = settings.for_drive(run_motion.drive)
    run_motion = equipped(run_motion.checked(robot, samples, settings.rate), settings, seed)
    motion_tables, motion_attributes = run_motion.record(robot)
    tables = {**robot.tables, **motion_tables}
    pieces = chunk_bounds(samples, None if whole else settings.chunk)
    channels = run_sensors(robot, settings, seed)
    run_tables = {k: v for c in channels for k, v in c.run_tables().items()}
    imus = ImuSlots(robot.imu_frames, robot.imu_slots, robot.n_slots)
    errors = imu_errors(settings, seed, samples, imus)
    imus = replace(imus, errors=errors)
    if errors is not None:
        tables = {**tables, **errors.tables}
    stream = noise_stream(
        samples,
        len(robot.imu_frames),
        settings.rate,
        seed,
        settings.noise,
        settings.noise_model if errors is None else errors.noise_model,
        len(pieces),
    )
    sampling = {
        **settings.attributes(seed),
        **sensor_attributes(tuple(sensors)),
    }
    model = robot.model
    peaks = np.zeros(model.n_joints)
    payload: Payload | None = getattr(robot, "payload", None)  # a load it carries, if any
    for start, stop in pieces:
        times = piece_times(start, stop, settings.rate)
        with _world_gravity(model, settings.gravity):
            base = robot.base(times)
            trajectory = run_motion.trajectory(robot, (start, stop), times, base)
            series = simulate_series(model, base, trajectory, imus, settings, seed, stream, start)
            if payload is not None:
                series = carry_payload(series, payload, base, trajectory, start, settings.threads)
        if len(series.tau):
            np.maximum(peaks, np.abs(series.tau).max(axis=0), out=peaks)
        joints = JointColumns(
            times,
            robot.record_columns(trajectory.q),
            robot.record_columns(trajectory.qd),
            robot.record_columns(trajectory.qdd),
            robot.record_columns(series.tau),
        )
        piece_tables = tables
        if sensors:
            state = SensorState(times, trajectory, base, series)
            piece_tables = {**tables, **measure(robot, state, tuple(sensors))}
        channel_attributes: dict[str, Any] = {}
        if channels:
            piece_tables = {**piece_tables, **run_tables, **measure_channels(channels, joints)}
            channel_attributes = {k: v for c in channels for k, v in c.attributes().items()}
        if trajectory.tables:  # a closed-loop drive's reference, commands and gains
            made = {k: robot.record_columns(v) for k, v in trajectory.tables.items()}
            piece_tables = {**piece_tables, **made}
        record = RunRecord(
            time=times,
            joint_names=robot.joint_names,
            q=joints.q,
            qd=joints.qd,
            qdd=joints.qdd,
            tau=joints.tau,
            base_pose=series.base_pose,
            base_wrench=series.base_wrench,
            tool_pose=series.tool_pose,
            imu=series.imu,
            imu_mounts=robot.imu_mounts,
            urdf=robot.urdf,
            tables=piece_tables,
            views=robot.views,
            attributes={
                "kind": robot.kind,
                **robot.attributes(peaks),
                **sampling,
                **channel_attributes,
                "drive": run_motion.drive,
                **motion_attributes,
                "version": __version__,
            },
        )
        yield _rounded(record, settings.dtype)


@contextmanager
def _world_gravity(model: RobotModel, gravity: tuple[float, float, float]) -> Iterator[None]:
    """The run's gravity in the robot's Pinocchio model while a piece is computed, then restored.

    Every gravity-dependent series (RNEA torques, the base wrench, forward dynamics, the
    accelerometers' specific force) reads the model's ``gravity``; a robot adapter may be shared
    between runs, so the model is left as it was found.
    """
    kept = np.array(model.model.gravity.linear, dtype=float)
    model.model.gravity.linear = np.asarray(gravity, dtype=float)
    try:
        yield
    finally:
        model.model.gravity.linear = kept


def _rounded(record: RunRecord, dtype: str) -> RunRecord:
    """The record's series (and time-axis tables) rounded to ``dtype`` and held as float64.

    That is what a data set of that dtype stores and
    :func:`~aaria_pin.files.source.open_record` reads back.
    """
    if dtype == "float64":
        return record
    rounded: dict[str, Any] = {
        name: getattr(record, name).astype(dtype).astype(np.float64) for name in SERIES
    }
    rounded["tables"] = {
        name: np.asarray(t).astype(dtype).astype(np.float64) if name in TIMED_HARDWARE else t
        for name, t in record.tables.items()
    }
    return replace(record, **rounded)


@checked
@dataclass(frozen=True)
class RunRequest:
    """One run's inputs as the engine takes them: what a producer of a robot kind builds.

    A kind's library function (e.g. :func:`aaria_pin.aaria.simulate.dh_request`,
    :func:`aaria_pin.core.urdf_run.urdf_request`) turns its tables or file into this once,
    checking each input there; :meth:`pieces` and :meth:`record` then run the engine.

    Attributes:
        robot: the robot (an adapter of its kind)
        motion: the joint motion (None: the robot's joint table)
        settings: duration, rate, pieces, noise, threads
        seeds: the run's seeds (:data:`Seeds`)
        sensors: sensors beside the IMUs
    """

    robot: RunRobot
    motion: Motion | None = None
    settings: RunSettings = field(default_factory=RunSettings)
    seeds: Seeds = 0
    sensors: Sequence[Sensor] = ()

    def pieces(self) -> Iterator[RunRecord]:
        """The run in pieces of ``settings.chunk`` samples (:func:`simulate_pieces`)."""
        return simulate_pieces(self.robot, self.motion, self.settings, self.seeds, self.sensors)

    def record(self) -> RunRecord:
        """The run held whole (:func:`simulate`)."""
        return simulate(self.robot, self.motion, self.settings, self.seeds, self.sensors)


class RunTables(TypedDict, total=False):
    """The joint and base oscillation tables of a run's options (DH arm or URDF robot).

    Attributes:
        joint_table: the joint table (None: the robot's default)
        base_table: 2 × 4 or 6 × 4 base oscillation table (None: a gentle motion)
    """

    joint_table: ArrayLike | None
    base_table: ArrayLike | None


def check_options(function: str, options: Mapping[str, Any], allowed: Any) -> None:
    """Refuse keyword options a request does not take, as Python refuses an unknown keyword.

    The requests take their options as ``**options: Unpack[TypedDict]``, which type checkers
    check but Python does not: without this a misspelt option (``durration=5``) would be dropped.

    Args:
        function: the request's name, for the message
        options: the keyword options given
        allowed: the options' ``TypedDict``

    Raises:
        TypeError: an option the request does not take.
    """
    known = set(allowed.__required_keys__) | set(allowed.__optional_keys__)
    unknown = sorted(set(options) - known)
    if unknown:
        raise TypeError(f"{function}() got an unexpected keyword argument {unknown[0]!r}")
