"""A run's motion set in MuJoCo: MuJoCo's own IMU readings and inverse-dynamics torques.

:func:`replay_motion` sets a run's joint positions, velocities and accelerations and its base
motion (on the chain :data:`~aaria_pin.core.export.mjcf_emit.BASE_JOINTS`, through
:func:`gimbal_xyz_coordinates`) in the model :func:`~aaria_pin.core.export.mjcf_emit.emit_mjcf`
wrote, and returns MuJoCo's sensor readings and torques, to compare with the run's. The base
motion is given (or a function giving it, called only on a moving base): which table of a
record holds it is the record's business (:func:`aaria_pin.apps.record_model.replay_in_mujoco`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from aaria_pin.core.export.mjcf_emit import BASE_JOINTS, load_mjcf, sensor_names
from aaria_pin.core.record import RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion
from aaria_pin.errors import ModelError, ParameterError

if TYPE_CHECKING:
    import mujoco

__all__ = ["gimbal_xyz_coordinates", "replay_motion"]


def gimbal_xyz_coordinates(
    rotation: Array, omega: Array, omega_dot: Array
) -> tuple[Array, Array, Array]:
    """The X-Y-Z gimbal angles, rates and accelerations of a rotation and its body motion.

    The inverse of the base kinematics' gimbal (:func:`~aaria_pin.core.oscillation.base_motion`):
    with
    ``R = Rx(a)·Ry(b)·Rz(c)`` the body angular velocity is ``ω = E(b, c)·[ȧ ḃ ċ]`` with
    ``E = [[cos b cos c, sin c, 0], [-cos b sin c, cos c, 0], [sin b, 0, 1]]``, and
    ``ω̇ = E·[ä b̈ c̈] + Ė·[ȧ ḃ ċ]``; both are solved for the gimbal's rates and accelerations
    (the coordinates of a chain of hinges about x, the new y and the newer z). The angles are
    :func:`~aaria_pin.core.rotations.angles_from_matrix` ``"XYZ"``: in ``(-π, π]``, the middle
    one in ``[-π/2, π/2]``; the rates are singular at ``cos b = 0``.

    Args:
        rotation: ``R_world_base``, T × 3 × 3
        omega: angular velocity in base axes, T × 3 [rad/s]
        omega_dot: its derivative in base axes, T × 3 [rad/s²]

    Returns:
        Angles (a, b, c) [rad], rates [rad/s] and accelerations [rad/s²], each T × 3.
    """
    from aaria_pin.core.rotations import angles_from_matrix

    angles = angles_from_matrix(rotation, "XYZ").angles
    b, c = angles[:, 1], angles[:, 2]
    cb, sb, cc, sc = np.cos(b), np.sin(b), np.cos(c), np.sin(c)

    def solve(w: Array) -> Array:  # E(b, c)⁻¹ · w, row by row
        first = (cc * w[:, 0] - sc * w[:, 1]) / cb
        return np.stack([first, sc * w[:, 0] + cc * w[:, 1], w[:, 2] - sb * first], axis=1)

    rates = solve(np.asarray(omega, dtype=float))
    da, db, dc = rates.T
    E_dot_rates = np.stack(
        [
            (-sb * cc * db - cb * sc * dc) * da + cc * dc * db,
            (sb * sc * db - cb * cc * dc) * da - sc * dc * db,
            cb * db * da,
        ],
        axis=1,
    )
    accelerations = solve(np.asarray(omega_dot, dtype=float) - E_dot_rates)
    return angles, rates, accelerations


def _named(model: mujoco.MjModel, sensor: bool, name: str) -> int:
    """The id of a joint or sensor by name.

    Raises:
        ModelError: the MJCF has none of that name.
    """
    import mujoco

    kind = mujoco.mjtObj.mjOBJ_SENSOR if sensor else mujoco.mjtObj.mjOBJ_JOINT
    found = int(mujoco.mj_name2id(model, kind, name))
    if found < 0:
        what, allowed = ("sensor", "with the run's IMUs") if sensor else ("joint", "of its robot")
        raise ModelError(
            f"{what} {name!r} is not in the MJCF; allowed: a model {allowed}",
            parameter="xml",
            element=name,
        )
    return found


def _joint_address(model: mujoco.MjModel, name: str) -> tuple[int, int]:
    """(qpos address, dof address) of a 1-DOF joint by name."""
    joint_id = _named(model, False, name)
    return int(model.jnt_qposadr[joint_id]), int(model.jnt_dofadr[joint_id])


def replay_motion(
    record: RunRecord,
    xml: str,
    base: BaseMotion | Callable[[], BaseMotion] | None = None,
    frictionloss: bool = False,
) -> tuple[Array, Array]:
    """MuJoCo's IMU readings and joint torques along a run's motion.

    For each sample the run's joint values, velocities and accelerations and its base motion
    (on the chain :data:`BASE_JOINTS`: positions and world-axis velocities and accelerations on
    the slides, :func:`gimbal_xyz_coordinates` of the body angular motion on the hinges) are
    set; ``mj_inverse`` gives the generalised forces ``qfrc_inverse`` (the joints' are the
    torques); with those applied (``qfrc_applied``) ``mj_forward`` reproduces the accelerations
    and its ``sensordata`` are MuJoCo's gyro (angular velocity) and accelerometer (specific
    force: acceleration less gravity) readings in each site's axes. Constraints are disabled
    (no contacts or limits act; with ``frictionloss`` the joints' friction loss does). One
    call into MuJoCo per sample (MuJoCo has no batched inverse dynamics): a check of a run,
    not a data path.

    The torques are the motor's where the MJCF carries actuators
    (:mod:`~aaria_pin.core.export.mjcf_actuators`): ``armature`` is in MuJoCo's mass matrix and
    ``damping`` a passive force, so they hold ``tau + armature·qdd + damping·qd``; the friction
    loss is a constraint, left out unless ``frictionloss``: then ``+frictionloss·sign(qd)``
    once MuJoCo's soft constraint saturates (at a speed well away from rest).

    Args:
        record: the run (its joints must be joints of the MJCF, its IMUs sites with sensors)
        xml: the MJCF of the run's robot (:func:`~aaria_pin.core.export.mjcf_emit.emit_mjcf`)
        base: the base motion on a moving base, or a function giving it (called only when
            the MJCF has the base chain)
        frictionloss: let the joints' friction loss act (MuJoCo's frictionloss constraint;
            contacts, limits and equalities stay disabled)

    Returns:
        IMU signals ``[wx wy wz fx fy fz]``, T × S × 6 in the record's IMU order (zeros in
        empty slots) [rad/s, m/s²], and joint torques, T × n in the record's joint order
        [N·m or N] (zeros in the all-zero column of an empty DH module, which has no joint).

    Raises:
        ModelError: the MJCF lacks a joint or a sensor of the run.
        ParameterError: a moving base without a base motion.
    """
    import mujoco

    model = load_mjcf(xml)
    disabled = mujoco.mjtDisableBit
    off = (disabled.mjDSBL_CONTACT, disabled.mjDSBL_LIMIT, disabled.mjDSBL_EQUALITY)
    for flag in off if frictionloss else (disabled.mjDSBL_CONSTRAINT,):
        model.opt.disableflags |= int(flag)
    data = mujoco.MjData(model)
    samples = record.n_samples
    qpos = np.zeros((samples, model.nq))
    qvel, qacc = np.zeros((samples, model.nv)), np.zeros((samples, model.nv))
    columns, dofs = [], []
    for j, name in enumerate(record.joint_names):
        empty = not any(np.any(a[:, j]) for a in (record.q, record.qd, record.qdd, record.tau))
        if empty and mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name) < 0:
            continue  # an empty module of a DH arm: a zero column, no joint
        position, dof = _joint_address(model, name)
        qpos[:, position], qvel[:, dof], qacc[:, dof] = (
            record.q[:, j],
            record.qd[:, j],
            record.qdd[:, j],
        )
        columns.append(j)
        dofs.append(dof)
    if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, BASE_JOINTS[0]) >= 0:
        if base is None:
            raise ParameterError(
                "the MJCF has a moving base and no base motion is given; allowed: the run's "
                "base motion",
                parameter="base",
                value=None,
            )
        motion = base() if callable(base) else base
        angles, rates, accelerations = gimbal_xyz_coordinates(
            motion.rotation, motion.omega, motion.omega_dot
        )
        base_values = (
            (motion.position, motion.velocity, motion.acceleration),
            (angles, rates, accelerations),
        )
        for k, name in enumerate(BASE_JOINTS):
            position, dof = _joint_address(model, name)
            values = base_values[k // 3]
            qpos[:, position], qvel[:, dof], qacc[:, dof] = (v[:, k % 3] for v in values)
    sensors: list[tuple[int, int, int]] = []
    for s, mount in enumerate(record.imu_mounts):
        if not mount.parent:
            continue
        gyro, accelerometer = (
            int(model.sensor_adr[_named(model, True, sensor)])
            for sensor in sensor_names(mount.name)
        )
        sensors.append((s, gyro, accelerometer))
    imu = np.zeros((samples, len(record.imu_mounts), 6))
    tau = np.zeros((samples, len(record.joint_names)))
    for t in range(samples):
        data.qpos[:], data.qvel[:], data.qacc[:] = qpos[t], qvel[t], qacc[t]
        data.qfrc_applied[:] = 0.0
        mujoco.mj_inverse(model, data)
        tau[t, columns] = data.qfrc_inverse[dofs]
        data.qfrc_applied[:] = data.qfrc_inverse
        mujoco.mj_forward(model, data)
        for s, gyro, accelerometer in sensors:
            imu[t, s, :3] = data.sensordata[gyro : gyro + 3]
            imu[t, s, 3:] = data.sensordata[accelerometer : accelerometer + 3]
    return imu, tau
