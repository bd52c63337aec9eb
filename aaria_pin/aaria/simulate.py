"""One Aaria simulation run: a DH arm, sine joint and base motions, 14 IMUs, torques.

:func:`simulate_run` and its chunked form are the keyword-argument producers of a DH run: they
make the arm's engine adapter (:func:`~aaria_pin.aaria.arm_run.dh_arm`), the motion and the
:class:`~aaria_pin.core.run.RunSettings`, and run the engine
(:func:`~aaria_pin.core.run.simulate_pieces`: IMU kinematics as arrays over the whole time grid,
ADIS16485-like noise if asked, torques by Pinocchio's batched RNEA). It returns the one
:class:`~aaria_pin.core.record.RunRecord` in the paper's module order: joints ``joint1`` …
``joint6`` (zero columns for an empty module), the 14 IMU slots in ``senSen`` order (an empty
module's slots have parent ``""``), the tables ``senSenDH``, ``senSenJ``, ``senSenB`` and the view
``senSen`` (:func:`~aaria_pin.aaria.sensen.sensen_view`).
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.aaria.arm_run import DH_ROBOT, DHArmSpec, dh_arm
from aaria_pin.aaria.dh_robot import BodyDimensions
from aaria_pin.aaria.sensen import N_MODULES
from aaria_pin.core.excitation import FourierExcitation, fourier_excitation
from aaria_pin.core.imu_noise import ADIS16485, ImuNoiseModel
from aaria_pin.core.record import RunRecord
from aaria_pin.core.run import (
    CHUNK_SAMPLES,
    UNITS,
    Motion,
    RunSettings,
    TorqueDrive,
    as_motion,
    join_chunks,
    motion_from_record,
    sampling_attributes,
    simulate_pieces,
)
from aaria_pin.core.run_metadata import RunMetadata
from aaria_pin.core.run.robot import RunKind, register_kind
from aaria_pin.core.trajectory import (
    DEFAULT_DURATION,
    DEFAULT_RATE,
    MAX_SAMPLES,
    JointTrajectory,
)
from aaria_pin.errors import InputFileError

__all__ = [
    "DEFAULT_DURATION",
    "DEFAULT_RATE",
    "FOURIER_LIMITS",
    "UNITS",
    "dh_fourier_excitation",
    "sampling_attributes",
    "simulate_from_record",
    "simulate_from_record_chunks",
    "simulate_from_run_file",
    "simulate_run",
    "simulate_run_chunks",
]

FOURIER_LIMITS = {"revolute": (1.0, 1.5, 5.0), "prismatic": (None, 0.5, 2.0)}
"""Limits of a DH arm's Fourier excitation by joint kind: position [rad] (None: the rail,
``±d/2``), |velocity| [rad/s or m/s] and |acceleration| [rad/s² or m/s²]. A revolute module
swings within ±1 rad (the sine default's 0.6 rad amplitude, a little wider), a prismatic one
along its whole rail."""


def dh_fourier_excitation(
    dh_table: ArrayLike,
    duration: float = DEFAULT_DURATION,
    rate: float = DEFAULT_RATE,
    *,
    base_frequency: float | None = None,
    harmonics: int | None = None,
    seed: int | np.random.SeedSequence | None = 0,
    max_samples: int | None = MAX_SAMPLES,
) -> FourierExcitation:
    """A random Fourier excitation of an Aaria arm's modules (:data:`FOURIER_LIMITS`).

    Coefficients are drawn for all six modules (so a module's motion does not depend on which
    other modules are empty) by :func:`~aaria_pin.core.excitation.fourier_excitation`; the
    rows of empty modules are then zero.

    Args:
        dh_table: 8 × 5 extended DH table
        duration: run length [s]
        rate: sample rate [Hz]
        base_frequency: the base frequency [Hz] (default: as
            :func:`~aaria_pin.core.excitation.fourier_excitation`)
        harmonics: harmonics per joint (default
            :data:`~aaria_pin.core.excitation.DEFAULT_HARMONICS`)
        seed: seed of the coefficients
        max_samples: most samples of the run (as :func:`~aaria_pin.core.trajectory.sample_count`)

    Returns:
        The excitation, one row per module (six).

    Raises:
        TableError: a bad DH table. ParameterError: as
            :func:`~aaria_pin.core.excitation.fourier_excitation`.
    """
    from aaria_pin.aaria.dh import chain_from_aaria
    from aaria_pin.core.excitation import DEFAULT_HARMONICS

    chain = chain_from_aaria(dh_table)
    q_limits = np.tile([-1.0, 1.0], (N_MODULES, 1))
    qd_limits = np.full(N_MODULES, FOURIER_LIMITS["revolute"][1])
    qdd_limits = np.full(N_MODULES, FOURIER_LIMITS["revolute"][2])
    for joint in chain.joints:
        row = joint.module - 1
        position, speed, acceleration = FOURIER_LIMITS[joint.kind]
        q_limits[row] = (joint.lower, joint.upper) if position is None else (-position, position)
        qd_limits[row], qdd_limits[row] = speed, acceleration
    excitation = fourier_excitation(
        N_MODULES,
        duration,
        rate,
        base_frequency=base_frequency,
        harmonics=DEFAULT_HARMONICS if harmonics is None else harmonics,
        q_limits=q_limits,
        qd_limits=qd_limits,
        qdd_limits=qdd_limits,
        seed=seed,
        max_samples=max_samples,
    )
    empty = np.ones(N_MODULES, dtype=bool)
    empty[[joint.module - 1 for joint in chain.joints]] = False
    for array in (excitation.a, excitation.b):
        array[empty] = 0.0
    excitation.offset[empty] = 0.0
    return excitation


def simulate_run(
    dh_table: ArrayLike,
    joint_table: ArrayLike | None = None,
    base_table: ArrayLike | None = None,
    *,
    duration: float = DEFAULT_DURATION,
    rate: float = DEFAULT_RATE,
    seed: int | np.random.SeedSequence = 0,
    noise: bool = True,
    noise_model: ImuNoiseModel = ADIS16485,
    dims: BodyDimensions | None = None,
    imu_mount: ArrayLike | None = None,
    torques: ArrayLike | None = None,
    motion: Motion | JointTrajectory | FourierExcitation | None = None,
    threads: int = 1,
    robot_name: str = DH_ROBOT,
    keep_urdf: bool = True,
) -> RunRecord:
    """Simulate one run of an Aaria arm on a moving base.

    Args:
        dh_table: 8 × 5 extended DH table (``senSenDH``)
        joint_table: 8 × 5 joint oscillation table (``senSenJ``); default moves every module
        base_table: 2 × 4 or 6 × 4 base oscillation table (``senSenB``); default a gentle motion
        duration: run length [s]
        rate: sample rate [Hz]
        seed: seed of the IMU noise, 0 to 2⁶³ - 1 (or a ``SeedSequence``, as data sets use)
        noise: add IMU noise (``False`` gives the exact signals)
        noise_model: IMU noise parameters
        dims: body dimensions and densities
        imu_mount: 14 × 4 × 4 pose of each IMU slot in its parent frame, slot order as in
            ``senSen`` (default: :func:`~aaria_pin.aaria.dh_robot.default_imu_slots`); entries of
            empty modules are ignored
        torques: (T, 6) joint torques [N·m] or forces [N] by module (columns of empty modules
            are ignored): the joints then move under them by forward dynamics
            (:func:`~aaria_pin.core.forward.forward_simulate`), starting from the joint table's
            values and velocities at t = 0, instead of following the joint table (stored as the
            table ``torque_table``)
        motion: the joint motion instead of the joint table's sines, by module (six columns
            or rows; those of empty modules are ignored): a
            :class:`~aaria_pin.core.trajectory.JointTrajectory` of the run's samples (T × 6,
            e.g. :func:`~aaria_pin.core.sampled_motion.trajectory_from_samples`; stored as the
            table ``joint_trajectory``, T × 19: time, q, qd, qdd) or a
            :class:`~aaria_pin.core.excitation.FourierExcitation`
            (:func:`dh_fourier_excitation`; stored as the table ``fourier_coefficients`` and
            the attribute ``fourier``). The attribute ``motion`` says which: ``sine``,
            ``trajectory`` or ``fourier``
        threads: worker threads of the batched RNEA
        robot_name: the ``robot`` attribute (a preset's name, or the table's)
        keep_urdf: keep the arm's URDF text in the record. It is written once per arm
            (:func:`cached_arm`: 1.5 ms for ``aaria-fig2``); the data-set engine, whose random
            tables each make a new arm and whose file stores the URDF once or not at all,
            passes False so it is never written

    Returns:
        The run record (kind ``"dh"``).
    """
    return join_chunks(
        simulate_run_chunks(
            dh_table,
            joint_table,
            base_table,
            duration=duration,
            rate=rate,
            seed=seed,
            noise=noise,
            noise_model=noise_model,
            dims=dims,
            imu_mount=imu_mount,
            torques=torques,
            motion=motion,
            threads=threads,
            robot_name=robot_name,
            keep_urdf=keep_urdf,
            chunk=None,
        )
    )


def simulate_run_chunks(
    dh_table: ArrayLike,
    joint_table: ArrayLike | None = None,
    base_table: ArrayLike | None = None,
    *,
    duration: float = DEFAULT_DURATION,
    rate: float = DEFAULT_RATE,
    seed: int | np.random.SeedSequence = 0,
    noise: bool = True,
    noise_model: ImuNoiseModel = ADIS16485,
    dims: BodyDimensions | None = None,
    imu_mount: ArrayLike | None = None,
    torques: ArrayLike | None = None,
    motion: Motion | JointTrajectory | FourierExcitation | None = None,
    threads: int = 1,
    robot_name: str = DH_ROBOT,
    keep_urdf: bool = True,
    chunk: int | None = CHUNK_SAMPLES,
) -> Iterator[RunRecord]:
    """:func:`simulate_run` computed in time chunks: one record per piece of the run, in order.

    The joint and base motions are functions of time, so each piece is computed on its own
    sample times; the IMU noise of the pieces is that of the whole run
    (:class:`~aaria_pin.core.imu_noise.ImuNoiseStream`), so the pieces put together
    (:func:`~aaria_pin.core.run.join_chunks`) are bit for bit :func:`simulate_run`'s record
    and memory does not grow with the run's length (each piece makes its own sample times).
    Each piece carries the run's tables, views and attributes. A run driven by torques is one
    piece (forward dynamics integrates the whole run). A run in pieces may have up to
    :data:`~aaria_pin.core.trajectory.MAX_STREAMED_SAMPLES` samples, one held whole (``chunk``
    None, or driven by torques) up to :data:`~aaria_pin.core.trajectory.MAX_SAMPLES`.

    Args:
        dh_table: as in :func:`simulate_run`
        joint_table: as in :func:`simulate_run`
        base_table: as in :func:`simulate_run`
        duration: run length [s]
        rate: sample rate [Hz]
        seed: seed of the IMU noise (as in :func:`simulate_run`)
        noise: add IMU noise
        noise_model: IMU noise parameters
        dims: body dimensions and densities
        imu_mount: as in :func:`simulate_run`
        torques: as in :func:`simulate_run` (the run is then one piece)
        motion: as in :func:`simulate_run`; a given trajectory is sliced piece by piece, a
            Fourier excitation evaluated on each piece's times (bit for bit the whole run's)
        threads: worker threads of the batched RNEA
        robot_name: the ``robot`` attribute
        keep_urdf: keep the arm's URDF text in the records
        chunk: samples per piece (default :data:`~aaria_pin.core.run.CHUNK_SAMPLES`); None:
            one piece

    Yields:
        The run record of each piece (kind ``"dh"``), ``time`` the piece's sample times.
    """
    settings = RunSettings(duration, rate, chunk, noise, noise_model, threads)
    robot = dh_arm(
        dh_table, DHArmSpec(joint_table, base_table, dims, imu_mount, robot_name, keep_urdf)
    )
    run_motion = as_motion(motion)
    if torques is not None:
        run_motion = TorqueDrive(torques, run_motion)
    return simulate_pieces(robot, run_motion, settings, seed)


def simulate_from_record(stored: RunRecord, **overrides: Any) -> RunRecord:
    """Re-make a DH run from the inputs its record holds.

    The tables (``senSenDH``, ``senSenJ``, ``senSenB``, ``torque_table`` for a run driven by
    torques, ``joint_trajectory`` or ``fourier_coefficients`` for a run that follows a given
    motion), the IMU mounts, the body dimensions,
    the robot's name and the rate, duration, seed and noise setting come from the record;
    keyword arguments of :func:`simulate_run` given here replace them.

    Args:
        stored: a DH run's record (e.g. read from its run file)
        **overrides: keyword arguments of :func:`simulate_run`

    Returns:
        The run record; with no overrides it equals the stored one.

    Raises:
        InputFileError: the record lacks a table, or its body dimensions cannot be used.
    """
    settings = _stored_settings(stored, overrides)
    return simulate_run(stored.tables["senSenDH"], **settings)


def simulate_from_record_chunks(
    stored: RunRecord, chunk: int | None = CHUNK_SAMPLES, **overrides: Any
) -> Iterator[RunRecord]:
    """:func:`simulate_from_record` in time chunks (:func:`simulate_run_chunks`).

    Args:
        stored: a DH run's record
        chunk: samples per piece; None: one piece
        **overrides: keyword arguments of :func:`simulate_run`

    Yields:
        The run record of each piece.

    Raises:
        InputFileError: as :func:`simulate_from_record`.
    """
    settings = _stored_settings(stored, overrides)
    return simulate_run_chunks(stored.tables["senSenDH"], **settings, chunk=chunk)


def _stored_settings(stored: RunRecord, overrides: dict[str, Any]) -> dict[str, Any]:
    """Keyword arguments of :func:`simulate_run` from a DH record, ``overrides`` applied."""
    attributes = stored.attributes
    missing = [name for name in ("senSenDH", "senSenJ", "senSenB") if name not in stored.tables]
    if missing:
        raise InputFileError(
            f"run has no {missing[0]} table; allowed: a DH run (senSenDH, senSenJ, senSenB)",
            parameter="stored",
            allowed="a DH run",
        )
    meta = RunMetadata.from_attributes(attributes)
    settings: dict[str, Any] = {
        "joint_table": stored.tables["senSenJ"],
        "base_table": stored.tables["senSenB"],
        "duration": meta.duration,
        "rate": meta.rate,
        "seed": meta.seed,
        "noise": meta.noise,
        "imu_mount": stored.imu_mount,
        "robot_name": meta.robot or DH_ROBOT,
    }
    if "torque_table" in stored.tables:
        settings["torques"] = stored.tables["torque_table"]
    settings["motion"] = motion_from_record(stored.tables, attributes, drive=False)
    if "body_dimensions" in meta.extra:
        try:
            settings["dims"] = BodyDimensions(**meta.extra["body_dimensions"])
        except TypeError as exc:
            raise InputFileError(
                f"body_dimensions cannot be used ({exc})", parameter="body_dimensions"
            ) from None
    settings.update(overrides)
    return settings


def simulate_from_run_file(path: str | os.PathLike[str], **overrides: Any) -> RunRecord:
    """Re-make the run stored in a run file from its inputs alone.

    The tables (``senSenDH``, ``senSenJ``, ``senSenB``), the IMU mounts and the rate, duration,
    seed and noise setting come from the file (its series are not read:
    :func:`~aaria_pin.files.runfile.read_run_inputs`); keyword arguments of
    :func:`simulate_run` given here replace them.

    Args:
        path: an ``.h5`` or ``.mat`` run file
        **overrides: keyword arguments of :func:`simulate_run`

    Returns:
        The run record; with no overrides it equals the stored one.

    Raises:
        InputFileError: not a DH run file, or its body dimensions cannot be used.
    """
    from aaria_pin.files.runfile import read_run_inputs

    try:
        return simulate_from_record(read_run_inputs(path), **overrides)
    except InputFileError as exc:
        raise InputFileError(f"{path}: {exc}", element=str(path), parameter="path") from None


register_kind(RunKind("dh", simulate_from_record, lambda record: "senSenDH" in record.tables))
