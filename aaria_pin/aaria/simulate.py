"""One Aaria simulation run: a DH arm, sine joint and base motions, 14 IMUs, torques.

:func:`dh_request` turns a DH table and keyword options (:class:`DhRunOptions`) into the
engine's :class:`~aaria_pin.core.run.RunRequest` once: the arm's adapter
(:func:`~aaria_pin.aaria.arm_run.dh_arm`), the motion and the
:class:`~aaria_pin.core.run.RunSettings`; :func:`dh_request_from_record` does the same from a
DH run's record. The engine (:func:`~aaria_pin.core.run.simulate_pieces`: IMU kinematics as
arrays over the whole time grid, ADIS16485-like noise if asked, torques by Pinocchio's batched
RNEA) then makes the one
:class:`~aaria_pin.core.record.RunRecord` in the paper's module order: joints ``joint1`` …
``joint6`` (zero columns for an empty module), the 14 IMU slots in ``senSen`` order (an empty
module's slots have parent ``""``), the tables ``senSenDH``, ``senSenJ``, ``senSenB`` and the view
``senSen`` (:func:`~aaria_pin.aaria.sensen.sensen_view`).
"""

from __future__ import annotations

import os
from typing import Any, Unpack

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.aaria.arm_run import DH_ROBOT, DHArmSpec, dh_arm
from aaria_pin.aaria.dh_robot import BodyDimensions
from aaria_pin.aaria.sensen import N_MODULES
from aaria_pin.core.arguments import checked
from aaria_pin.core.excitation import FourierExcitation, fourier_excitation
from aaria_pin.core.imu_noise import ImuNoiseModel
from aaria_pin.core.joint_sensors import (
    ActuatorModel,
    ControllerModel,
    CurrentSensorModel,
    EncoderModel,
    TorqueSensorModel,
)
from aaria_pin.core.record import RunRecord
from aaria_pin.core.run import (
    UNITS,
    Motion,
    RunRequest,
    RunSettings,
    RunTables,
    as_motion,
    check_options,
    motion_from_record,
    sampling_attributes,
)
from aaria_pin.core.run.deprecation import deprecated_producer, warn_deprecated
from aaria_pin.core.run.drives import DriveOptions, driven, remade_drive
from aaria_pin.core.run.robot import RunKind, register_kind
from aaria_pin.core.run.settings import stored_hardware
from aaria_pin.core.trajectory import (
    DEFAULT_DURATION,
    DEFAULT_RATE,
    MAX_SAMPLES,
    JointTrajectory,
)
from aaria_pin.errors import InputFileError, ParameterError

__all__ = [
    "DEFAULT_DURATION",
    "DEFAULT_RATE",
    "FOURIER_LIMITS",
    "UNITS",
    "DhRunOptions",
    "dh_fourier_excitation",
    "dh_request",
    "dh_request_from_record",
    "sampling_attributes",
    "simulate_from_record",
    "simulate_from_record_chunks",
    "simulate_from_run_file",
    "simulate_run",
    "simulate_run_chunks",
]


class _DhSettings(DriveOptions, total=False):
    """:class:`DhRunOptions` but the joint and base tables."""

    duration: float
    rate: float
    seed: int | np.random.SeedSequence
    noise: bool
    noise_model: ImuNoiseModel
    encoder: EncoderModel | None
    torque_sensor: TorqueSensorModel | None
    actuator: ActuatorModel | None
    controller: ControllerModel | None
    current_sensor: CurrentSensorModel | None
    dims: BodyDimensions | None
    imu_mount: ArrayLike | None
    motion: Motion | JointTrajectory | FourierExcitation | None
    threads: int
    robot_name: str
    keep_urdf: bool
    chunk: int | None


class DhRunOptions(_DhSettings, RunTables, total=False):
    """The options of a DH run beside its DH table (every key optional).

    Attributes:
        joint_table: 8 × 5 joint oscillation table (``senSenJ``); default moves every module
        base_table: 2 × 4 or 6 × 4 base oscillation table (``senSenB``); default a gentle motion
        duration: run length [s]
        rate: sample rate [Hz]
        seed: seed of the IMU noise, 0 to 2⁶³ - 1 (or a ``SeedSequence``, as data sets use)
        noise: add IMU noise (``False`` gives the exact signals)
        noise_model: IMU noise parameters (a preset:
            :func:`~aaria_pin.core.imu_presets.imu_preset`)
        encoder: the joint encoders (the table ``q_measured``; None: none)
        torque_sensor: the joint torque sensors (``tau_measured``; None: none)
        actuator: the joints' motors and gearboxes (``tau_motor``; None: none)
        current_sensor: the motor current sensors (``current_measured``; None: none)
        dims: body dimensions and densities
        imu_mount: 14 × 4 × 4 pose of each IMU slot in its parent frame, slot order as in
            ``senSen`` (default: :func:`~aaria_pin.aaria.dh_robot.default_imu_slots`); entries of
            empty modules are ignored
        torques: (T, 6) joint torques [N·m] or forces [N] by module (columns of empty modules
            are ignored): the joints then move under them by forward dynamics
            (:func:`~aaria_pin.core.forward.forward_simulate`), starting from the joint table's
            values and velocities at t = 0, instead of following the joint table (stored as the
            table ``torque_table``)
        limits: with ``torques``, ``stop`` (default) or ``ignore``: what the run does when a
            joint leaves the model's limits (:mod:`~aaria_pin.core.joint_limits`)
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
            (:func:`~aaria_pin.aaria.arm_run.cached_arm`: 1.5 ms for ``aaria-fig2``); the
            data-set engine, whose random tables each make a new arm and whose file stores the
            URDF once or not at all, passes False so it is never written
        chunk: samples per piece of :meth:`~aaria_pin.core.run.RunRequest.pieces` (default
            :data:`~aaria_pin.core.run.CHUNK_SAMPLES`; None: one piece); a run driven by
            torques is one piece
    """


FOURIER_LIMITS = {"revolute": (1.0, 1.5, 5.0), "prismatic": (None, 0.5, 2.0)}
"""Limits of a DH arm's Fourier excitation by joint kind: position [rad] (None: the rail,
``±d/2``), |velocity| [rad/s or m/s] and |acceleration| [rad/s² or m/s²]. A revolute module
swings within ±1 rad (the sine default's 0.6 rad amplitude, a little wider), a prismatic one
along its whole rail."""


@checked
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


@checked
def dh_request(dh_table: ArrayLike, **options: Unpack[DhRunOptions]) -> RunRequest:
    """A DH run of an Aaria arm on a moving base, as the engine's inputs (checked once here).

    ``dh_request(table, **options).record()`` is the run held whole, ``.pieces()`` the run in
    time pieces (each piece's IMU noise is the whole run's, so the pieces put together,
    :func:`~aaria_pin.core.run.join_chunks`, are bit for bit the whole record).

    Args:
        dh_table: 8 × 5 extended DH table (``senSenDH``)
        **options: :class:`DhRunOptions`

    Returns:
        The robot (:func:`~aaria_pin.aaria.arm_run.dh_arm`), motion, settings and seed; the
        record it makes is of kind ``"dh"``.

    Raises:
        TableError, ParameterError: a bad table or setting.
        TypeError: an option it does not take.
    """
    check_options("dh_request", options, DhRunOptions)
    settings = RunSettings.from_options(options)
    spec = DHArmSpec(
        options.get("joint_table"),
        options.get("base_table"),
        options.get("dims"),
        options.get("imu_mount"),
        options.get("robot_name", DH_ROBOT),
        options.get("keep_urdf", True),
    )
    run_motion = driven(as_motion(options.get("motion")), options)
    return RunRequest(dh_arm(dh_table, spec), run_motion, settings, options.get("seed", 0))


def dh_request_from_record(
    stored: RunRecord, *, source: str | None = None, **overrides: Unpack[DhRunOptions]
) -> RunRequest:
    """The DH run a record holds the inputs of, as the engine's inputs.

    The tables (``senSenDH``, ``senSenJ``, ``senSenB``, ``torque_table`` for a run driven by
    torques, ``joint_trajectory`` or ``fourier_coefficients`` for a run that follows a given
    motion), the IMU mounts, the body dimensions, the robot's name and the rate, duration,
    seed, noise setting and hardware (IMU model, joint models) come from the record;
    ``overrides`` replace them.

    Args:
        stored: a DH run's record (e.g. read from its run file)
        source: the file it was read from, to name in a message about its own IMU mounts
        **overrides: :class:`DhRunOptions`

    Returns:
        The run's inputs; with no overrides their record equals the stored one.

    Raises:
        InputFileError: the record lacks a table, or its body dimensions or its IMU mounts
            (not replaced by ``imu_mount``) cannot be used (then ``parameter="file"``).
    """
    missing = [name for name in ("senSenDH", "senSenJ", "senSenB") if name not in stored.tables]
    if missing:
        raise InputFileError(
            f"run has no {missing[0]} table; allowed: a DH run (senSenDH, senSenJ, senSenB)",
            parameter="stored",
            allowed="a DH run",
        )
    meta = stored.metadata
    options: DhRunOptions = {
        "joint_table": stored.tables["senSenJ"],
        "base_table": stored.tables["senSenB"],
        "duration": meta.duration,
        "rate": meta.rate,
        "seed": meta.seed,
        "noise": meta.noise,
        "imu_mount": stored.imu_mount,
        "robot_name": meta.robot or DH_ROBOT,
        "motion": motion_from_record(stored.tables, stored.attributes, drive=False),
        **stored_hardware(stored.attributes),  # type: ignore[typeddict-item]
    }
    options.update(remade_drive(stored.tables, stored.attributes, overrides))  # type: ignore[typeddict-item]
    if "body_dimensions" in meta.extra:
        try:
            options["dims"] = BodyDimensions(**meta.extra["body_dimensions"])
        except TypeError as exc:
            raise InputFileError(
                f"body_dimensions cannot be used ({exc})", parameter="body_dimensions"
            ) from None
    options.update(overrides)
    try:
        return dh_request(stored.tables["senSenDH"], **options)
    except ParameterError as exc:
        if exc.parameter != "imu_mount" or "imu_mount" in overrides:
            raise
        prefix = "" if source is None else f"{source}: "
        raise InputFileError(f"{prefix}{exc}", parameter="file") from None


def _remake(stored: RunRecord, **overrides: Any) -> RunRecord:
    """The registered re-make of a DH run (:func:`dh_request_from_record`, held whole)."""
    return dh_request_from_record(stored, **overrides).record()


simulate_run = deprecated_producer("simulate_run", dh_request, "record")
simulate_run_chunks = deprecated_producer("simulate_run_chunks", dh_request, "pieces")
simulate_from_record = deprecated_producer("simulate_from_record", dh_request_from_record, "record")
simulate_from_record_chunks = deprecated_producer(
    "simulate_from_record_chunks", dh_request_from_record, "pieces"
)


def simulate_from_run_file(
    path: str | os.PathLike[str], **overrides: Unpack[DhRunOptions]
) -> RunRecord:
    """Deprecated: :func:`aaria_pin.apps.remake.remake_run` (any kind of run file).

    Returns:
        The run record; with no overrides it equals the stored one.

    Raises:
        InputFileError: not a DH run file, or its body dimensions cannot be used.
    """
    from aaria_pin.files.runfile import read_run_inputs

    warn_deprecated("simulate_from_run_file", "aaria_pin.apps.remake.remake_run(path, **overrides)")
    try:
        return dh_request_from_record(read_run_inputs(path), **overrides).record()
    except InputFileError as exc:
        raise InputFileError(f"{path}: {exc}", element=str(path), parameter="file") from None


register_kind(RunKind("dh", _remake, lambda record: "senSenDH" in record.tables))
