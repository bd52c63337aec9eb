"""One simulation run of any URDF robot: sine joint motions, a fixed or moving base, IMUs, torques.

The producers of a URDF robot's run by keyword arguments: they make its engine adapter
(:func:`~aaria_pin.core.run.urdf_kind.urdf_robot_run`) and run the engine every run shares
(:func:`~aaria_pin.core.run.simulate_pieces`): IMU kinematics over the whole time grid in one
compiled pass, torques and the base wrench by Pinocchio's batched RNEA, ADIS16485-like noise if
asked. The joints follow their joint table, or move under given torques by forward dynamics
(:func:`~aaria_pin.core.forward.forward_simulate`). The result is the one
:class:`~aaria_pin.core.record.RunRecord` (kind ``"urdf"``) that stores its URDF, its
``joint_table`` and ``base_table`` and its IMU layout, so the run can be re-made from its record
alone (:func:`simulate_urdf_from_record`; from a run file,
:func:`aaria_pin.apps.remake.remake_run`).
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.core.excitation import DEFAULT_HARMONICS, FourierExcitation, fourier_excitation
from aaria_pin.core.imu_noise import ADIS16485, ImuNoiseModel
from aaria_pin.core.record import ImuMount, RunRecord
from aaria_pin.core.run import (
    CHUNK_SAMPLES,
    Motion,
    RunKind,
    RunSettings,
    TorqueDrive,
    as_motion,
    join_chunks,
    motion_from_record,
    register_kind,
    simulate,
    simulate_pieces,
)
from aaria_pin.core.run.urdf_kind import UrdfRunSpec, urdf_robot_run
from aaria_pin.core.run_metadata import RunMetadata
from aaria_pin.core.trajectory import (
    DEFAULT_DURATION,
    DEFAULT_RATE,
    MAX_SAMPLES,
    JointTrajectory,
)
from aaria_pin.core.urdf_robot import (
    UrdfRobot,
    load_urdf_robot,
    mimic_followers,
    usable_range,
)

__all__ = [
    "FOURIER_SPEED",
    "simulate_loaded_robot",
    "simulate_urdf_from_record",
    "simulate_urdf_from_record_chunks",
    "simulate_urdf_run",
    "simulate_urdf_run_chunks",
    "urdf_fourier_excitation",
]

FOURIER_SPEED = (1.5, 5.0)
"""|velocity| [rad/s or m/s] and |acceleration| [rad/s² or m/s²] of a URDF robot's Fourier
excitation; the velocity is the URDF's limit where that is finite and lower."""

MotionInput = Motion | JointTrajectory | FourierExcitation | None
"""A run's joint motion: None (the joint table's sines), a motion, a given trajectory or a
Fourier excitation."""


def urdf_fourier_excitation(
    loaded: UrdfRobot,
    duration: float = DEFAULT_DURATION,
    rate: float = DEFAULT_RATE,
    *,
    base_frequency: float | None = None,
    harmonics: int | None = None,
    seed: int | np.random.SeedSequence | None = 0,
    max_samples: int | None = MAX_SAMPLES,
) -> FourierExcitation:
    """A random Fourier excitation of a URDF robot's joints within their limits.

    Each joint moves within the part of its range that default motions use
    (:func:`~aaria_pin.core.urdf_robot.usable_range`: the URDF limits, a continuous joint
    ±π, a prismatic one at most 0.5 m), at most at its URDF velocity limit (or
    :data:`FOURIER_SPEED`), by :func:`~aaria_pin.core.excitation.fourier_excitation`. A mimic
    joint's row is its leader's scaled by the multiplier, plus the offset: the series of
    ``multiplier·q_leader + offset``.

    Args:
        loaded: the robot (:func:`~aaria_pin.core.urdf_robot.load_urdf_robot`)
        duration: run length [s]
        rate: sample rate [Hz]
        base_frequency: the base frequency [Hz] (default: as
            :func:`~aaria_pin.core.excitation.fourier_excitation`)
        harmonics: harmonics per joint (default
            :data:`~aaria_pin.core.excitation.DEFAULT_HARMONICS`)
        seed: seed of the coefficients
        max_samples: most samples of the run (as :func:`~aaria_pin.core.trajectory.sample_count`)

    Returns:
        The excitation, one row per actuated joint in model order.

    Raises:
        ParameterError: as :func:`~aaria_pin.core.excitation.fourier_excitation`.
        ModelError: a mimic joint whose leader is not actuated.
    """
    joints = loaded.joints
    ranges = [usable_range(joint) for joint in joints]
    q_limits = [(middle - span / 2, middle + span / 2) for middle, span in ranges]
    speed, acceleration = FOURIER_SPEED
    qd_limits = [
        min(speed, joint.velocity) if np.isfinite(joint.velocity) and joint.velocity > 0 else speed
        for joint in joints
    ]
    excitation = fourier_excitation(
        len(joints),
        duration,
        rate,
        base_frequency=base_frequency,
        harmonics=DEFAULT_HARMONICS if harmonics is None else harmonics,
        q_limits=q_limits,
        qd_limits=qd_limits,
        qdd_limits=acceleration,
        seed=seed,
        max_samples=max_samples,
    )
    for row, (source, multiplier, offset) in mimic_followers(joints).items():
        excitation.a[row] = multiplier * excitation.a[source]
        excitation.b[row] = multiplier * excitation.b[source]
        excitation.offset[row] = multiplier * excitation.offset[source] + offset
    return excitation


def _run_motion(torques: ArrayLike | None, motion: MotionInput) -> Motion:
    """The engine's motion of the producers' ``motion`` and ``torques``."""
    run_motion = as_motion(motion)
    return run_motion if torques is None else TorqueDrive(torques, run_motion)


def simulate_urdf_run(
    urdf: str,
    joint_table: ArrayLike | None = None,
    base_table: ArrayLike | None = None,
    *,
    urdf_dir: Path | None = None,
    source: str | None = None,
    moving_base: bool = True,
    tool_frame: str | None = None,
    imu_layout: tuple[ImuMount, ...] | None = None,
    duration: float = DEFAULT_DURATION,
    rate: float = DEFAULT_RATE,
    seed: int | np.random.SeedSequence = 0,
    noise: bool = True,
    noise_model: ImuNoiseModel = ADIS16485,
    threads: int = 1,
    torques: ArrayLike | None = None,
    motion: MotionInput = None,
) -> RunRecord:
    """Simulate one run of a URDF robot.

    Args:
        urdf: the URDF text
        joint_table: n × 5 joint oscillation table, one row per actuated joint in model order
            (default :func:`~aaria_pin.core.urdf_robot.default_urdf_joint_table`)
        base_table: 2 × 4 or 6 × 4 base oscillation table (default a gentle motion; ignored
            and not stored on a fixed base)
        urdf_dir: the URDF's folder, for relative mesh paths
        source: where the URDF came from (a robot name or a file), stored as an attribute
        moving_base: carry the root link on the base motion (False: fixed at the origin; the
            base wrench is then the load on the fixed mount)
        tool_frame: the tool frame (default: chosen as in :func:`load_urdf_robot`)
        imu_layout: the IMUs (default: two per moving link plus base and tool)
        duration: run length [s]
        rate: sample rate [Hz]
        seed: seed of the IMU noise, 0 to 2⁶³ - 1, or a ``SeedSequence``
        noise: add IMU noise (``False`` gives the exact signals)
        noise_model: IMU noise parameters
        threads: worker threads of the batched RNEA
        torques: (T, n) joint torques [N·m] or forces [N], model order: the joints then move
            under them by forward dynamics, starting from the joint table's values and
            velocities at t = 0, instead of following the joint table (stored as the table
            ``torque_table``)
        motion: the joint motion instead of the joint table's sines, one column (or row) per
            actuated joint in model order: a
            :class:`~aaria_pin.core.trajectory.JointTrajectory` of the run's samples (e.g.
            :func:`~aaria_pin.core.sampled_motion.trajectory_from_samples`; stored as the table
            ``joint_trajectory``: time, q, qd, qdd; checked against the URDF position limits;
            mimic columns used as given) or a
            :class:`~aaria_pin.core.excitation.FourierExcitation`
            (:func:`urdf_fourier_excitation`; stored as the table ``fourier_coefficients`` and
            the attribute ``fourier``). The attribute ``motion`` says which: ``sine``,
            ``trajectory`` or ``fourier``

    Returns:
        The run record (kind ``"urdf"``).
    """
    return join_chunks(
        simulate_urdf_run_chunks(
            urdf,
            joint_table,
            base_table,
            urdf_dir=urdf_dir,
            source=source,
            moving_base=moving_base,
            tool_frame=tool_frame,
            imu_layout=imu_layout,
            duration=duration,
            rate=rate,
            seed=seed,
            noise=noise,
            noise_model=noise_model,
            threads=threads,
            torques=torques,
            motion=motion,
            chunk=None,
        )
    )


def simulate_urdf_run_chunks(
    urdf: str,
    joint_table: ArrayLike | None = None,
    base_table: ArrayLike | None = None,
    *,
    urdf_dir: Path | None = None,
    source: str | None = None,
    moving_base: bool = True,
    tool_frame: str | None = None,
    imu_layout: tuple[ImuMount, ...] | None = None,
    duration: float = DEFAULT_DURATION,
    rate: float = DEFAULT_RATE,
    seed: int | np.random.SeedSequence = 0,
    noise: bool = True,
    noise_model: ImuNoiseModel = ADIS16485,
    threads: int = 1,
    torques: ArrayLike | None = None,
    motion: MotionInput = None,
    chunk: int | None = CHUNK_SAMPLES,
) -> Iterator[RunRecord]:
    """:func:`simulate_urdf_run` computed in time chunks: one record per piece, in order.

    As :func:`aaria_pin.aaria.simulate.simulate_run_chunks`: the pieces put together
    (:func:`~aaria_pin.core.run.join_chunks`) are bit for bit :func:`simulate_urdf_run`'s
    record, noise included; each piece's attributes cover the run up to its end (the last
    piece's ``effort_exceeded`` is the whole run's). A run driven by torques is one piece.
    The limits on the run's length are those of the DH run's pieces.

    Args:
        urdf: the URDF text
        joint_table: as in :func:`simulate_urdf_run`
        base_table: as in :func:`simulate_urdf_run`
        urdf_dir: the URDF's folder, for relative mesh paths
        source: where the URDF came from, stored as an attribute
        moving_base: carry the root link on the base motion
        tool_frame: the tool frame
        imu_layout: the IMUs
        duration: run length [s]
        rate: sample rate [Hz]
        seed: seed of the IMU noise
        noise: add IMU noise
        noise_model: IMU noise parameters
        threads: worker threads of the batched RNEA
        torques: as in :func:`simulate_urdf_run` (the run is then one piece)
        motion: as in :func:`simulate_urdf_run` (sliced or evaluated piece by piece)
        chunk: samples per piece (default :data:`~aaria_pin.core.run.CHUNK_SAMPLES`); None:
            one piece

    Yields:
        The run record of each piece (kind ``"urdf"``).
    """
    loaded = load_urdf_robot(
        urdf,
        urdf_dir=urdf_dir,
        moving_base=True,
        tool_frame=tool_frame,
        imu_layout=imu_layout,
    )
    robot = urdf_robot_run(
        loaded,
        UrdfRunSpec(
            joint_table,
            base_table,
            moving_base,
            source,
            "" if urdf_dir is None else str(urdf_dir),
        ),
    )
    settings = RunSettings(duration, rate, chunk, noise, noise_model, threads)
    return simulate_pieces(robot, _run_motion(torques, motion), settings, seed)


def simulate_loaded_robot(
    loaded: UrdfRobot,
    joint_table: ArrayLike | None = None,
    base_table: ArrayLike | None = None,
    *,
    moving_base: bool | None = None,
    source: str | None = None,
    duration: float = DEFAULT_DURATION,
    rate: float = DEFAULT_RATE,
    seed: int | np.random.SeedSequence = 0,
    noise: bool = True,
    noise_model: ImuNoiseModel = ADIS16485,
    threads: int = 1,
    torques: ArrayLike | None = None,
    motion: MotionInput = None,
) -> RunRecord:
    """The same as :func:`simulate_urdf_run` for a robot already loaded (a data set's runs).

    Args:
        loaded: the robot (:func:`~aaria_pin.core.urdf_robot.load_urdf_robot`)
        joint_table: as in :func:`simulate_urdf_run`
        base_table: as in :func:`simulate_urdf_run`
        moving_base: False holds a free-flyer robot's base at rest at the origin (its base
            wrench is then the fixed mount's load); default: moving if the model has a
            free-flyer (a model without one gives a zero base wrench)
        source: as in :func:`simulate_urdf_run`
        duration: run length [s]
        rate: sample rate [Hz]
        seed: seed of the IMU noise
        noise: add IMU noise
        noise_model: IMU noise parameters
        threads: worker threads of the batched RNEA
        torques: as in :func:`simulate_urdf_run`
        motion: as in :func:`simulate_urdf_run`

    Returns:
        The run record (kind ``"urdf"``).
    """
    robot = urdf_robot_run(loaded, UrdfRunSpec(joint_table, base_table, moving_base, source))
    settings = RunSettings(duration, rate, None, noise, noise_model, threads)
    return simulate(robot, _run_motion(torques, motion), settings, seed)


def simulate_urdf_from_record(stored: RunRecord, **overrides: Any) -> RunRecord:
    """Re-make a URDF robot's run from the inputs its record holds.

    The URDF, joint and base tables, IMU layout, tool frame, base mode, rate, duration, seed
    and noise setting come from the record (and the URDF's folder, for its meshes, if it is
    still there); keyword arguments of :func:`simulate_urdf_run` given here replace them.

    Args:
        stored: a URDF robot's run record (e.g. read from its run file)
        **overrides: keyword arguments of :func:`simulate_urdf_run`

    Returns:
        The run record; with no overrides it equals the stored one.
    """
    return simulate_urdf_run(stored.urdf, **_stored_settings(stored, overrides))


def simulate_urdf_from_record_chunks(
    stored: RunRecord, chunk: int | None = CHUNK_SAMPLES, **overrides: Any
) -> Iterator[RunRecord]:
    """:func:`simulate_urdf_from_record` in time chunks (:func:`simulate_urdf_run_chunks`).

    Args:
        stored: a URDF robot's run record
        chunk: samples per piece; None: one piece
        **overrides: keyword arguments of :func:`simulate_urdf_run`

    Yields:
        The run record of each piece.
    """
    return simulate_urdf_run_chunks(stored.urdf, **_stored_settings(stored, overrides), chunk=chunk)


def _stored_settings(stored: RunRecord, overrides: dict[str, Any]) -> dict[str, Any]:
    """Keyword arguments of :func:`simulate_urdf_run` from a record, ``overrides`` applied."""
    meta = RunMetadata.from_attributes(stored.attributes)
    settings: dict[str, Any] = {
        "joint_table": stored.tables.get("joint_table"),
        "base_table": stored.tables.get("base_table"),
        "source": meta.source or None,
        "urdf_dir": Path(meta.urdf_dir) if meta.urdf_dir else None,
        "moving_base": meta.moving_base is not False,
        "tool_frame": meta.tool_frame or None,
        "imu_layout": stored.imu_mounts,
        "duration": meta.duration,
        "rate": meta.rate,
        "seed": meta.seed,
        "noise": meta.noise,
    }
    if "torque_table" in stored.tables:
        settings["torques"] = stored.tables["torque_table"]
    settings["motion"] = motion_from_record(stored.tables, stored.attributes, drive=False)
    settings.update(overrides)
    return settings


register_kind(
    RunKind("urdf", simulate_urdf_from_record, lambda record: "joint_table" in record.tables)
)
