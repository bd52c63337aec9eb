"""One simulation run of any URDF robot: sine joint motions, a fixed or moving base, IMUs, torques.

:func:`urdf_request` (of a URDF text), :func:`loaded_robot_request` (of a loaded robot) and
:func:`urdf_request_from_record` turn a URDF robot's run into the engine's
:class:`~aaria_pin.core.run.RunRequest` once: its adapter
(:func:`~aaria_pin.core.run.urdf_kind.urdf_robot_run`), motion and settings. The engine every run
shares (:func:`~aaria_pin.core.run.simulate_pieces`) computes IMU kinematics over the whole time
grid in one compiled pass, torques and the base wrench by Pinocchio's batched RNEA, ADIS16485-like
noise if asked. The joints follow their joint table, or move under given torques by forward dynamics
(:func:`~aaria_pin.core.forward.forward_simulate`). The result is the one
:class:`~aaria_pin.core.record.RunRecord` (kind ``"urdf"``) that stores its URDF, its
``joint_table`` and ``base_table`` and its IMU layout, so the run can be re-made from its record
alone (:func:`urdf_request_from_record`; from a run file, :func:`aaria_pin.apps.remake.remake_run`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, TypedDict, Unpack

import numpy as np

from aaria_pin.core.arguments import checked
from aaria_pin.core.excitation import DEFAULT_HARMONICS, FourierExcitation, fourier_excitation
from aaria_pin.core.imu_noise import ImuNoiseModel
from aaria_pin.core.joint_sensors import (
    ActuatorModel,
    ControllerModel,
    CurrentSensorModel,
    EncoderModel,
    TorqueSensorModel,
)
from aaria_pin.core.record import ImuMount, RunRecord
from aaria_pin.core.run import (
    Motion,
    RunKind,
    RunRequest,
    RunRobot,
    RunSettings,
    RunTables,
    as_motion,
    check_options,
    motion_from_record,
    register_kind,
)
from aaria_pin.core.run.deprecation import deprecated_producer
from aaria_pin.core.run.drives import DriveOptions, driven, remade_drive
from aaria_pin.core.run.settings import stored_hardware
from aaria_pin.core.run.urdf_kind import UrdfRunSpec, urdf_robot_run
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
    "LoadedRobotOptions",
    "UrdfRunOptions",
    "loaded_robot_request",
    "simulate_loaded_robot",
    "simulate_urdf_from_record",
    "simulate_urdf_from_record_chunks",
    "simulate_urdf_run",
    "simulate_urdf_run_chunks",
    "urdf_fourier_excitation",
    "urdf_request",
    "urdf_request_from_record",
]

FOURIER_SPEED = (1.5, 5.0)
"""|velocity| [rad/s or m/s] and |acceleration| [rad/s² or m/s²] of a URDF robot's Fourier
excitation; the velocity is the URDF's limit where that is finite and lower."""

MotionInput = Motion | JointTrajectory | FourierExcitation | None
"""A run's joint motion: None (the joint table's sines), a motion, a given trajectory or a
Fourier excitation."""


@checked
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


class _UrdfSettings(DriveOptions, total=False):
    """The options of a loaded URDF robot's run but its tables (see :class:`UrdfRunOptions`)."""

    source: str | None
    moving_base: bool | None
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
    threads: int
    motion: MotionInput
    chunk: int | None


class LoadedRobotOptions(_UrdfSettings, RunTables, total=False):
    """The options of a run of a loaded URDF robot (every key optional).

    Attributes:
        joint_table: n × 5 joint oscillation table, one row per actuated joint in model order
            (default :func:`~aaria_pin.core.urdf_robot.default_urdf_joint_table`)
        base_table: 2 × 4 or 6 × 4 base oscillation table (default a gentle motion; ignored
            and not stored on a fixed base)
        source: where the URDF came from (a robot name or a file), stored as an attribute
        moving_base: False holds a free-flyer robot's base at rest at the origin (its base
            wrench is then the fixed mount's load); default: moving (for a loaded robot:
            moving if the model has a free-flyer)
        duration: run length [s]
        rate: sample rate [Hz]
        seed: seed of the IMU noise, 0 to 2⁶³ - 1, or a ``SeedSequence``
        noise: add IMU noise (``False`` gives the exact signals)
        noise_model: IMU noise parameters (a preset:
            :func:`~aaria_pin.core.imu_presets.imu_preset`)
        encoder: the joint encoders (the table ``q_measured``; None: none)
        torque_sensor: the joint torque sensors (``tau_measured``; None: none)
        actuator: the joints' motors and gearboxes (``tau_motor``; None: none)
        current_sensor: the motor current sensors (``current_measured``; None: none)
        threads: worker threads of the batched RNEA
        torques: (T, n) joint torques [N·m] or forces [N], model order: the joints then move
            under them by forward dynamics, starting from the joint table's values and
            velocities at t = 0, instead of following the joint table (stored as the table
            ``torque_table``; the run is then one piece)
        limits: with ``torques``, ``stop`` (default) or ``ignore``: what the run does when a
            joint leaves the model's limits (:mod:`~aaria_pin.core.joint_limits`)
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
        chunk: samples per piece of :meth:`~aaria_pin.core.run.RunRequest.pieces` (default
            :data:`~aaria_pin.core.run.CHUNK_SAMPLES`; None: one piece)
    """


class _UrdfLoad(TypedDict, total=False):
    """How a URDF text is loaded (see :class:`UrdfRunOptions`)."""

    urdf_dir: Path | None
    tool_frame: str | None
    imu_layout: tuple[ImuMount, ...] | None


class UrdfRunOptions(LoadedRobotOptions, _UrdfLoad, total=False):
    """The options of a URDF robot's run: :class:`LoadedRobotOptions` and how it is loaded.

    Attributes:
        urdf_dir: the URDF's folder, for relative mesh paths (stored as ``urdf_dir``)
        tool_frame: the tool frame (default: chosen as in
            :func:`~aaria_pin.core.urdf_robot.load_urdf_robot`)
        imu_layout: the IMUs (default: two per moving link plus base and tool)
    """


def _run_motion(options: LoadedRobotOptions) -> Motion:
    """The engine's motion of the options' ``motion``, ``torques``, ``limits``, ``dynamics``."""
    return driven(as_motion(options.get("motion")), options)


def _request(robot: RunRobot, options: LoadedRobotOptions) -> RunRequest:
    """The engine's inputs of an adapted robot and the run's options."""
    settings = RunSettings.from_options(options)
    motion = _run_motion(options)
    return RunRequest(robot, motion, settings, options.get("seed", 0))


@checked
def urdf_request(urdf: str, **options: Unpack[UrdfRunOptions]) -> RunRequest:
    """A run of a URDF robot, as the engine's inputs (checked once here).

    ``urdf_request(text, **options).record()`` is the run held whole, ``.pieces()`` the run
    in time pieces (bit for bit the whole run's, noise included; each piece's attributes cover
    the run up to its end, so the last piece's ``effort_exceeded`` is the whole run's).

    Args:
        urdf: the URDF text
        **options: :class:`UrdfRunOptions`

    Returns:
        The robot, motion, settings and seed; the record it makes is of kind ``"urdf"``.

    Raises:
        UrdfError, ModelError: a URDF that is no robot. TableError, ParameterError: a bad
            table or setting.
    """
    check_options("urdf_request", options, UrdfRunOptions)
    urdf_dir = options.get("urdf_dir")
    loaded = load_urdf_robot(
        urdf,
        urdf_dir=urdf_dir,
        moving_base=True,
        tool_frame=options.get("tool_frame"),
        imu_layout=options.get("imu_layout"),
    )
    spec = UrdfRunSpec(
        options.get("joint_table"),
        options.get("base_table"),
        options.get("moving_base", True),
        options.get("source"),
        "" if urdf_dir is None else str(urdf_dir),
    )
    return _request(urdf_robot_run(loaded, spec), options)


def loaded_robot_request(loaded: UrdfRobot, **options: Unpack[LoadedRobotOptions]) -> RunRequest:
    """A run of a URDF robot already loaded (a data set's runs), as the engine's inputs.

    Args:
        loaded: the robot (:func:`~aaria_pin.core.urdf_robot.load_urdf_robot`)
        **options: :class:`LoadedRobotOptions` (``moving_base`` default: moving if the model
            has a free-flyer; a model without one gives a zero base wrench)

    Returns:
        The robot, motion, settings and seed (kind ``"urdf"``).
    """
    check_options("loaded_robot_request", options, LoadedRobotOptions)
    spec = UrdfRunSpec(
        options.get("joint_table"),
        options.get("base_table"),
        options.get("moving_base"),
        options.get("source"),
    )
    return _request(urdf_robot_run(loaded, spec), options)


def urdf_request_from_record(stored: RunRecord, **overrides: Unpack[UrdfRunOptions]) -> RunRequest:
    """The URDF robot's run a record holds the inputs of, as the engine's inputs.

    The URDF, joint and base tables, IMU layout, tool frame, base mode, rate, duration, seed
    noise setting and hardware (IMU model, joint
    models) come from the record (and the URDF's folder, for its meshes, if it is
    still there); ``overrides`` replace them.

    Args:
        stored: a URDF robot's run record (e.g. read from its run file)
        **overrides: :class:`UrdfRunOptions`

    Returns:
        The run's inputs; with no overrides their record equals the stored one.
    """
    meta = stored.metadata
    options: UrdfRunOptions = {
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
        "motion": motion_from_record(stored.tables, stored.attributes, drive=False),
        **stored_hardware(stored.attributes),  # type: ignore[typeddict-item]
    }
    options.update(remade_drive(stored.tables, stored.attributes, overrides))  # type: ignore[typeddict-item]
    options.update(overrides)
    return urdf_request(stored.urdf, **options)


def _remake(stored: RunRecord, **overrides: Any) -> RunRecord:
    """The registered re-make of a URDF run (:func:`urdf_request_from_record`, held whole)."""
    return urdf_request_from_record(stored, **overrides).record()


simulate_urdf_run = deprecated_producer("simulate_urdf_run", urdf_request, "record")
simulate_urdf_run_chunks = deprecated_producer("simulate_urdf_run_chunks", urdf_request, "pieces")
simulate_loaded_robot = deprecated_producer("simulate_loaded_robot", loaded_robot_request, "record")
simulate_urdf_from_record = deprecated_producer(
    "simulate_urdf_from_record", urdf_request_from_record, "record"
)
simulate_urdf_from_record_chunks = deprecated_producer(
    "simulate_urdf_from_record_chunks", urdf_request_from_record, "pieces"
)


register_kind(RunKind("urdf", _remake, lambda record: "joint_table" in record.tables))
