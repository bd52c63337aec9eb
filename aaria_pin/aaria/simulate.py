"""One Aaria simulation run: a DH arm, sine joint and base motions, 14 IMUs, torques.

:func:`simulate_run` validates the inputs, builds the arm on a moving base, computes every
signal over the whole time grid at once (IMU kinematics as arrays, torques by Pinocchio's
batched RNEA), adds ADIS16485-like noise if asked, and returns the :class:`RunRecord`.
"""

from __future__ import annotations

import os
from dataclasses import asdict
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin import __version__
from aaria_pin.aaria.dh_robot import (
    BodyDimensions,
    build_dh_robot,
)
from aaria_pin.aaria.oscillation import (
    base_motion,
    default_base_table,
    default_joint_table,
    joint_trajectory,
    validate_base_table,
)
from aaria_pin.aaria.sensen import N_MODULES, RunRecord, new_sensen
from aaria_pin.core.dynamics import inverse_dynamics
from aaria_pin.core.imu_noise import ADIS16485, ImuNoiseModel, add_imu_noise, noise_attributes
from aaria_pin.core.kinematics import trajectory_signals
from aaria_pin.core.model import GRAVITY
from aaria_pin.core.se3 import Array
from aaria_pin.core.seeds import check_seed, seed_attributes, stored_seed
from aaria_pin.core.trajectory import DEFAULT_DURATION, DEFAULT_RATE, sample_times
from aaria_pin.errors import InputFileError

__all__ = [
    "DEFAULT_DURATION",
    "DEFAULT_RATE",
    "sampling_attributes",
    "simulate_from_run_file",
    "simulate_run",
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


def _module_columns(columns: list[int], values: Array) -> Array:
    """Scatter per-joint columns into the six module columns (zeros for empty modules)."""
    out = np.zeros((values.shape[0], N_MODULES))
    out[:, columns] = values
    return out


def sampling_attributes(
    rate: float,
    duration: float,
    seed: int | np.random.SeedSequence,
    noise: bool,
    noise_model: ImuNoiseModel,
) -> dict[str, Any]:
    """The attributes every run file records: rate, duration, seed, noise, gravity, units."""
    return {
        "rate": float(rate),
        "duration": float(duration),
        **seed_attributes(seed),
        "noise": bool(noise),
        "noise_parameters": noise_attributes(noise_model),
        "gravity": GRAVITY.tolist(),
        "units": UNITS,
    }


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
    threads: int = 1,
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
            values
            and velocities at t = 0, instead of following the joint table
        threads: worker threads of the batched RNEA

    Returns:
        The run record.
    """
    check_seed(seed)
    robot = build_dh_robot(dh_table, "aaria", dims, imu_mount=imu_mount)
    time = sample_times(duration, rate)
    senSenJ = (
        default_joint_table(robot.chain) if joint_table is None else np.array(joint_table, float)
    )
    senSenB = default_base_table() if base_table is None else validate_base_table(base_table)
    trajectory = joint_trajectory(senSenJ, robot.chain, time)
    base = base_motion(senSenB, time)
    model = robot.model(moving_base=True)
    columns = [module - 1 for module in robot.chain.modules]  # module order → senSen columns
    if torques is not None:
        from aaria_pin.core.forward import check_torques, forward_simulate

        by_module = check_torques(torques, time.size, N_MODULES, "torque table")
        trajectory = forward_simulate(
            model, base, by_module[:, columns], time, trajectory.q[0], trajectory.qd[0]
        )

    senSen, q, imu = new_sensen(time)
    q[:, columns] = trajectory.q
    present = [k for k, slot in enumerate(robot.imu_slots) if slot.parent is not None]
    exact, tool_pose = trajectory_signals(
        model,
        base,
        trajectory,
        [robot.imu_slots[k].name for k in present],
        [model.tool_frame],
        imu_out=None if noise else imu,  # noise-free: straight into senSen
        imu_slots=None if noise else present,
    )
    if noise:
        imu[:, present] = add_imu_noise(exact, rate, np.random.default_rng(seed), noise_model)
    tau, base_wrench = inverse_dynamics(model, base, trajectory, threads)

    attributes: dict[str, Any] = {
        **sampling_attributes(rate, duration, seed, noise, noise_model),
        "body_dimensions": {
            **asdict(robot.dims),
            "density_overrides": dict(robot.dims.density_overrides),
        },
        "drive": "motion" if torques is None else "torque",
        "version": __version__,
    }
    return RunRecord(
        senSen=senSen,
        senSenDH=robot.chain.table.copy(),
        senSenJ=senSenJ,
        senSenB=senSenB,
        q=np.ascontiguousarray(q),
        qd=_module_columns(columns, trajectory.qd),
        qdd=_module_columns(columns, trajectory.qdd),
        tau=_module_columns(columns, tau),
        base_wrench=base_wrench,
        tool_pose=tool_pose[:, 0],
        imu_mount=np.array(
            [slot.T_parent_imu if slot.parent else np.zeros((4, 4)) for slot in robot.imu_slots]
        ),
        attributes=attributes,
    )


def simulate_from_run_file(path: str | os.PathLike[str], **overrides: Any) -> RunRecord:
    """Re-make the run stored in a run file from its inputs alone.

    The tables (``senSenDH``, ``senSenJ``, ``senSenB``), the IMU mounts and the rate, duration,
    seed and noise setting come from the file; keyword arguments of :func:`simulate_run` given
    here replace them.

    Args:
        path: an ``.h5`` or ``.mat`` run file
        **overrides: keyword arguments of :func:`simulate_run`

    Returns:
        The run record; with no overrides it equals the stored one.
    """
    from aaria_pin.files.runfile import read_run

    stored = read_run(path)
    attributes = stored.attributes
    seed = stored_seed(attributes)
    settings: dict[str, Any] = {
        "joint_table": stored.senSenJ,
        "base_table": stored.senSenB,
        "duration": float(attributes.get("duration", DEFAULT_DURATION)),
        "rate": float(attributes.get("rate", DEFAULT_RATE)),
        "seed": seed,
        "noise": bool(attributes.get("noise", True)),
        "imu_mount": stored.imu_mount,
    }
    if "body_dimensions" in attributes:
        try:
            settings["dims"] = BodyDimensions(**attributes["body_dimensions"])
        except TypeError as exc:
            raise InputFileError(f"{path}: body_dimensions cannot be used ({exc})") from None
    settings.update(overrides)
    return simulate_run(stored.senSenDH, **settings)
