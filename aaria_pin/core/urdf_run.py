"""One simulation run of any URDF robot: sine joint motions, a fixed or moving base, IMUs, torques.

The same pipeline as every run (:func:`~aaria_pin.core.run.simulate_series`): IMU kinematics over
the whole time grid in one compiled pass, torques and the base wrench by Pinocchio's batched
RNEA, ADIS16485-like noise if asked. The joints follow their joint table, or move under given
torques by forward dynamics (:func:`~aaria_pin.core.forward.forward_simulate`). The result is the
one :class:`~aaria_pin.core.record.RunRecord` (kind ``"urdf"``) that stores its URDF, its
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

from aaria_pin._version import __version__
from aaria_pin.core.excitation import (
    DEFAULT_HARMONICS,
    FourierExcitation,
    check_trajectory,
    fourier_excitation,
    motion_attributes,
    motion_slice,
    stored_motion,
)
from aaria_pin.core.imu_noise import ADIS16485, ImuNoiseModel
from aaria_pin.core.oscillation import base_motion, default_base_table, validate_base_table
from aaria_pin.core.record import ImuMount, RunRecord
from aaria_pin.core.run import (
    CHUNK_SAMPLES,
    chunk_bounds,
    join_chunks,
    noise_stream,
    sampling_attributes,
    simulate_series,
    stored_sampling,
)
from aaria_pin.core.seeds import check_seed
from aaria_pin.core.trajectory import (
    DEFAULT_DURATION,
    DEFAULT_RATE,
    MAX_SAMPLES,
    MAX_STREAMED_SAMPLES,
    BaseMotion,
    JointTrajectory,
    piece_times,
    sample_count,
)
from aaria_pin.core.urdf_robot import (
    UrdfRobot,
    default_urdf_joint_table,
    effort_excess,
    load_urdf_robot,
    mimic_followers,
    urdf_joint_trajectory,
    usable_range,
    validate_urdf_joint_table,
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

Motion = JointTrajectory | FourierExcitation | None
"""A run's joint motion beside its joint table: a given trajectory or a Fourier excitation."""


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
    motion: Motion = None,
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
            :func:`~aaria_pin.core.excitation.trajectory_from_samples`; stored as the table
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
    motion: Motion = None,
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
    yield from _loaded_pieces(
        loaded,
        joint_table,
        base_table,
        moving_base=moving_base,
        source=source,
        duration=duration,
        rate=rate,
        seed=seed,
        noise=noise,
        noise_model=noise_model,
        threads=threads,
        torques=torques,
        motion=motion,
        chunk=chunk,
        extra={"urdf_dir": "" if urdf_dir is None else str(urdf_dir)},
    )


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
    motion: Motion = None,
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
    return join_chunks(
        _loaded_pieces(
            loaded,
            joint_table,
            base_table,
            moving_base=moving_base,
            source=source,
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


def _loaded_pieces(
    loaded: UrdfRobot,
    joint_table: ArrayLike | None,
    base_table: ArrayLike | None,
    *,
    moving_base: bool | None,
    source: str | None,
    duration: float,
    rate: float,
    seed: int | np.random.SeedSequence,
    noise: bool,
    noise_model: ImuNoiseModel,
    threads: int,
    torques: ArrayLike | None,
    motion: Motion,
    chunk: int | None,
    extra: dict[str, Any] | None = None,
) -> Iterator[RunRecord]:
    """The pieces of a loaded robot's run (:func:`simulate_urdf_run_chunks`).

    Each piece's attributes cover the run up to its end (``effort_exceeded`` from the peaks
    so far), so the last piece's are the whole run's; ``extra`` attributes are added last.
    """
    check_seed(seed)
    robot = loaded.robot
    moving_base = robot.moving_base if moving_base is None else moving_base and robot.moving_base
    streamed = chunk is not None and torques is None
    samples = sample_count(duration, rate, MAX_STREAMED_SAMPLES if streamed else MAX_SAMPLES)
    table = (
        default_urdf_joint_table(loaded) if joint_table is None else np.array(joint_table, float)
    )
    validate_urdf_joint_table(table, loaded)  # errors before any work
    base_arr = None
    if moving_base:
        base_arr = default_base_table() if base_table is None else validate_base_table(base_table)
    tau_in = None
    if torques is not None:
        from aaria_pin.core.forward import check_torques

        tau_in = check_torques(torques, samples, robot.n_joints)
        chunk = None
    tables = {"joint_table": table}
    if isinstance(motion, JointTrajectory):
        lower = [-np.inf if j.mimic is not None else j.lower for j in loaded.joints]
        upper = [np.inf if j.mimic is not None else j.upper for j in loaded.joints]
        motion = check_trajectory(motion, samples, rate, lower, upper, robot.joint_names)
    motion_tables, motion_attrs = motion_attributes(motion, robot.n_joints)
    if base_arr is not None:
        tables["base_table"] = base_arr
    if tau_in is not None:
        tables["torque_table"] = tau_in
    tables.update(motion_tables)
    pieces = chunk_bounds(samples, chunk)
    stream = noise_stream(
        samples, len(robot.sensor_frames), rate, seed, noise, noise_model, len(pieces)
    )
    peaks = np.zeros(robot.n_joints)
    for start, stop in pieces:
        times = piece_times(start, stop, rate)
        if motion is None:
            trajectory = urdf_joint_trajectory(table, loaded, times)
        else:
            trajectory = motion_slice(motion, start, stop, times)
        base = (
            base_motion(base_arr, times) if base_arr is not None else BaseMotion.resting(times.size)
        )
        if tau_in is not None:  # one piece: the whole run
            from aaria_pin.core.forward import forward_simulate

            trajectory = forward_simulate(
                robot, base, tau_in, times, trajectory.q[0], trajectory.qd[0]
            )
        series = simulate_series(
            robot,
            base,
            trajectory,
            imu_frames=robot.sensor_frames,
            rate=rate,
            seed=seed,
            noise=noise,
            noise_model=noise_model,
            threads=threads,
            noise_stream=stream,
            start=start,
        )
        tau = series.tau
        if len(tau):
            np.maximum(peaks, np.abs(tau).max(axis=0), out=peaks)
        attributes: dict[str, Any] = {
            "kind": "urdf",
            "robot": loaded.summary.name,
            "source": source if source is not None else "",
            "moving_base": bool(moving_base),
            "base_frame": robot.base_frame,
            "tool_frame": robot.tool_frame,
            "effort_exceeded": {
                name: list(values) for name, values in effort_excess(loaded, peaks[None]).items()
            },
            **sampling_attributes(rate, duration, seed, noise, noise_model),
            "drive": "motion" if torques is None else "torque",
            **motion_attrs,
            "version": __version__,
            **(extra or {}),
        }
        yield RunRecord(
            time=times,
            joint_names=robot.joint_names,
            q=np.ascontiguousarray(trajectory.q),
            qd=np.ascontiguousarray(trajectory.qd),
            qdd=np.ascontiguousarray(trajectory.qdd),
            tau=tau,
            base_pose=series.base_pose,
            base_wrench=series.base_wrench,
            tool_pose=series.tool_pose,
            imu=series.imu,
            imu_mounts=loaded.imu_mounts,
            urdf=loaded.urdf,
            tables=tables,
            attributes=attributes,
        )


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
    attributes = stored.attributes
    settings: dict[str, Any] = {
        "joint_table": stored.tables.get("joint_table"),
        "base_table": stored.tables.get("base_table"),
        "source": attributes.get("source") or None,
        "urdf_dir": Path(attributes["urdf_dir"]) if attributes.get("urdf_dir") else None,
        "moving_base": bool(attributes.get("moving_base", True)),
        "tool_frame": attributes.get("tool_frame"),
        "imu_layout": stored.imu_mounts,
        **stored_sampling(attributes),
    }
    if "torque_table" in stored.tables:
        settings["torques"] = stored.tables["torque_table"]
    motion = stored_motion(stored.tables, attributes)
    if motion is not None:
        settings["motion"] = motion
    settings.update(overrides)
    return settings
