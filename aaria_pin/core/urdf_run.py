"""One simulation run of any URDF robot: sine joint motions, a fixed or moving base, IMUs, torques.

The same pipeline as the Aaria run (:mod:`aaria_pin.aaria.simulate`): IMU kinematics over the whole
time grid in one compiled pass, torques and the base wrench by Pinocchio's batched RNEA,
ADIS16485-like noise if asked. The result is a :class:`~aaria_pin.core.record.GenericRunRecord`
that stores its URDF, joint and base tables and IMU layout, so the run can be re-made from its
file alone (:func:`simulate_urdf_from_run_file`).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin import __version__
from aaria_pin.aaria.simulate import DEFAULT_DURATION, DEFAULT_RATE, sampling_attributes
from aaria_pin.core.dynamics import inverse_dynamics
from aaria_pin.core.imu_noise import ADIS16485, ImuNoiseModel, add_imu_noise
from aaria_pin.core.kinematics import trajectory_signals
from aaria_pin.core.oscillation import base_motion, default_base_table, validate_base_table
from aaria_pin.core.record import GenericRunRecord, ImuMount
from aaria_pin.core.seeds import check_seed, stored_seed
from aaria_pin.core.trajectory import BaseMotion, sample_times
from aaria_pin.core.urdf_robot import (
    UrdfRobot,
    default_urdf_joint_table,
    effort_excess,
    load_urdf_robot,
    urdf_joint_trajectory,
)

__all__ = ["simulate_loaded_robot", "simulate_urdf_from_run_file", "simulate_urdf_run"]


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
) -> GenericRunRecord:
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

    Returns:
        The run record.
    """
    check_seed(seed)
    loaded = load_urdf_robot(
        urdf,
        urdf_dir=urdf_dir,
        moving_base=True,  # a fixed base is a free-flyer held at rest: RNEA gives the mount's load
        tool_frame=tool_frame,
        imu_layout=imu_layout,
    )
    record = simulate_loaded_robot(
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
    )
    record.attributes["urdf_dir"] = "" if urdf_dir is None else str(urdf_dir)
    return record


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
) -> GenericRunRecord:
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

    Returns:
        The run record.
    """
    check_seed(seed)
    robot = loaded.robot
    moving_base = robot.moving_base if moving_base is None else moving_base and robot.moving_base
    time = sample_times(duration, rate)
    table = (
        default_urdf_joint_table(loaded) if joint_table is None else np.array(joint_table, float)
    )
    trajectory = urdf_joint_trajectory(table, loaded, time)
    base_arr = None
    if moving_base:
        base_arr = default_base_table() if base_table is None else validate_base_table(base_table)
        base = base_motion(base_arr, time)
    else:
        base = BaseMotion.resting(time.size)

    n, n_joints, n_imus = time.size, robot.n_joints, len(loaded.imu_mounts)
    signals = np.empty((n, 1 + n_joints + 6 * n_imus))
    signals[:, 0] = time
    signals[:, 1 : 1 + n_joints] = trajectory.q
    imu_block = signals[:, 1 + n_joints :].reshape(n, n_imus, 6)
    exact, tool_pose = trajectory_signals(
        robot,
        base,
        trajectory,
        robot.sensor_frames,
        [robot.tool_frame],
        imu_out=None if noise else imu_block,
    )
    if noise:
        imu_block[:] = add_imu_noise(exact, rate, np.random.default_rng(seed), noise_model)
    tau, base_wrench = inverse_dynamics(robot, base, trajectory, threads)
    base_pose = np.broadcast_to(np.eye(4), (n, 4, 4)).copy()
    if moving_base:
        base_pose[:, :3, :3] = base.rotation
        base_pose[:, :3, 3] = base.position

    attributes: dict[str, Any] = {
        "robot": loaded.summary.name,
        "source": source if source is not None else "",
        "moving_base": bool(moving_base),
        "base_frame": robot.base_frame,
        "tool_frame": robot.tool_frame,
        "effort_exceeded": {
            name: list(values) for name, values in effort_excess(loaded, tau).items()
        },
        **sampling_attributes(rate, duration, seed, noise, noise_model),
        "version": __version__,
    }
    return GenericRunRecord(
        signals=signals,
        joint_names=robot.joint_names,
        q=np.ascontiguousarray(trajectory.q),
        qd=np.ascontiguousarray(trajectory.qd),
        qdd=np.ascontiguousarray(trajectory.qdd),
        tau=np.ascontiguousarray(tau),
        base_pose=base_pose,
        base_wrench=base_wrench,
        tool_pose=tool_pose[:, 0],
        imu_mounts=loaded.imu_mounts,
        urdf=loaded.urdf,
        joint_table=table,
        base_table=base_arr,
        attributes=attributes,
    )


def simulate_urdf_from_run_file(path: str | os.PathLike[str], **overrides: Any) -> GenericRunRecord:
    """Re-make the run stored in a generic run file from its inputs alone.

    The URDF, joint and base tables, IMU layout, tool frame, base mode, rate, duration, seed
    and noise setting come from the file (and the URDF's folder, for its meshes, if it is still
    there); keyword arguments of :func:`simulate_urdf_run` given
    here replace them.

    Args:
        path: an HDF5 generic run file
        **overrides: keyword arguments of :func:`simulate_urdf_run`

    Returns:
        The run record; with no overrides it equals the stored one.
    """
    from aaria_pin.files.runfile import read_generic_run

    stored = read_generic_run(path)
    attributes = stored.attributes
    settings: dict[str, Any] = {
        "joint_table": stored.joint_table,
        "base_table": stored.base_table,
        "source": attributes.get("source") or None,
        "urdf_dir": Path(attributes["urdf_dir"]) if attributes.get("urdf_dir") else None,
        "moving_base": bool(attributes.get("moving_base", True)),
        "tool_frame": attributes.get("tool_frame"),
        "imu_layout": stored.imu_mounts,
        "duration": float(attributes.get("duration", DEFAULT_DURATION)),
        "rate": float(attributes.get("rate", DEFAULT_RATE)),
        "seed": stored_seed(attributes),
        "noise": bool(attributes.get("noise", True)),
    }
    settings.update(overrides)
    return simulate_urdf_run(stored.urdf, **settings)
