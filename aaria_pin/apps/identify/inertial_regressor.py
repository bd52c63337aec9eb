"""The joint torque regressor: torques as a linear function of the standard inertial parameters.

The torques are linear in the standard inertial parameters, ten per body
``[m, m·cx, m·cy, m·cz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz]`` (inertia about the body's joint origin,
Pinocchio's ``Inertia.toDynamicParameters`` order): ``tau = Y(q, v, a)·pi``.
:func:`torque_regressor` computes ``Y`` for the whole trajectory in two compiled passes (the
frame kinematics, then Newton–Euler per body), the same matrix as Pinocchio's
``computeJointTorqueRegressor`` (the tests hold them equal to 1e-9 relative), which has no
batched form: 2.3 µs a sample against 6.9 µs for one Pinocchio call per sample, 2.3 times the
batched RNEA (ur5 and ``aaria-fig2`` on a moving base, 30 s at 200 Hz, one core;
``benchmarks/bench_identify_dynamics.py``; 7 against 20 µs on a loaded machine).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory

if TYPE_CHECKING:  # Pinocchio loads only where a model is used
    from aaria_pin.core.model import RobotModel

__all__ = ["INERTIAL_PARAMETERS", "body_frames", "standard_parameters", "torque_regressor"]

INERTIAL_PARAMETERS = ("m", "mx", "my", "mz", "Ixx", "Ixy", "Iyy", "Ixz", "Iyz", "Izz")
"""The ten standard parameters of a body, in regressor order: mass [kg], first moments
``m·c`` [kg·m] and the inertia about the body's joint origin [kg·m²]."""


def body_frames(robot: RobotModel) -> tuple[list[int], list[str]]:
    """The joints that carry a body, and each body's name.

    The bodies are the root joint's on a moving base and each actuated joint's; a body is named
    after its first link (body frame), else after its joint.
    """
    import pinocchio as pin

    model = robot.model
    joints = list(range(1, model.njoints))
    names = []
    for j in joints:
        links = [
            frame.name
            for frame in model.frames
            if frame.type == pin.FrameType.BODY and frame.parentJoint == j
        ]
        names.append(links[0] if links else str(model.names[j]))
    return joints, names


def standard_parameters(robot: RobotModel) -> tuple[tuple[str, ...], Array]:
    """The standard inertial parameters of a model, ten per body, and their names.

    Returns:
        Names ``<parameter>_<body>`` (``m_link2``, ``Izz_tool``; :data:`INERTIAL_PARAMETERS`)
        and the model's values, (10·B,) [kg, kg·m, kg·m²].
    """
    joints, bodies = body_frames(robot)
    names = tuple(f"{p}_{body}" for body in bodies for p in INERTIAL_PARAMETERS)
    values = np.concatenate(
        [np.asarray(robot.model.inertias[j].toDynamicParameters()) for j in joints]
    )
    return names, values


def torque_regressor(robot: RobotModel, base: BaseMotion, trajectory: JointTrajectory) -> Array:
    """The joint torque regressor over a whole trajectory, (T, nv, 10·B).

    ``Y[t] @ pi`` is the generalized force of sample t (Pinocchio's RNEA, gravity included) for
    standard parameters ``pi`` (:func:`standard_parameters`); on a moving base the first six
    rows are the base wrench ``[f, n]`` in base axes about the base origin. It equals
    Pinocchio's ``computeJointTorqueRegressor`` (the tests' per-sample oracle).

    The frame kinematics come from one compiled pass
    (:func:`~aaria_pin.core.kinematics.trajectory_signals`: each joint frame's angular velocity,
    proper acceleration and pose), the rest from a second one
    (:mod:`aaria_pin.apps.identify._regressor_kernel`): the angular accelerations by their
    recursion in world axes (``alpha_j = alpha_p + z·qdd + (omega_p × z)·qd`` for a revolute
    joint about z), then each body's wrench about its origin by Newton–Euler,
    ``f = m·a + alpha × h + omega × (omega × h)``, ``n = I·alpha + omega × (I·omega) + h × a``
    (``a`` the origin's acceleration less gravity, ``h = m·c``), linear in the parameters. A
    revolute joint about the world axis z through o takes ``z·(n_w + (p_i - o) × f_w)`` of each
    body i it carries, a prismatic one ``z·f_w``, the free flyer the force and the moment about
    its origin along each base axis.

    Args:
        robot: the model (revolute, prismatic and free-flyer joints)
        base: the base motion (ignored on a fixed base)
        trajectory: joint values over time, columns in model order

    Returns:
        The regressor [N·m or N per unit parameter].
    """
    from dataclasses import replace

    import pinocchio as pin

    from aaria_pin.apps.identify._regressor_kernel import regressor_kernel
    from aaria_pin.core._kinematics_kernel import FREEFLYER, PRISMATIC, REVOLUTE
    from aaria_pin.core.kinematics import joint_kind, trajectory_signals

    model = pin.Model(robot.model)  # a copy with one frame at each joint origin
    frames = []
    for j in range(1, model.njoints):
        frames.append(f"__regressor_origin_{j}")
        frame = pin.Frame(frames[-1], j, 0, pin.SE3.Identity(), pin.FrameType.OP_FRAME)
        model.addFrame(frame, False)
    probe = replace(robot, model=model, sensor_frames=())
    signals, poses = trajectory_signals(probe, base, trajectory, frames, frames)
    codes = {"revolute": REVOLUTE, "prismatic": PRISMATIC, "freeflyer": FREEFLYER}
    n_bodies = model.njoints - 1
    kinds = np.empty(n_bodies, dtype=np.int64)
    axes = np.zeros((n_bodies, 3))
    columns = np.zeros(n_bodies, dtype=np.int64)
    column = 0
    for j in range(1, model.njoints):
        kind, axis = joint_kind(model.joints[j])
        kinds[j - 1], axes[j - 1], columns[j - 1] = codes[kind], axis, column
        column += kind != "freeflyer"
    # every (row, body) pair: the body, the joint that carries it, the axis, moment or force
    pairs: list[tuple[int, int, tuple[float, ...], bool, int]] = []
    unit = np.eye(3)
    for i in range(1, model.njoints):
        k = i
        while k > 0:  # body i is carried by joint i and its ancestors
            first = model.joints[k].idx_v
            if kinds[k - 1] == FREEFLYER:  # force rows along each base axis, then moments
                pairs += [(i - 1, k - 1, tuple(unit[a % 3]), a >= 3, first + a) for a in range(6)]
            else:
                pairs.append((i - 1, k - 1, tuple(axes[k - 1]), kinds[k - 1] == REVOLUTE, first))
            k = model.parents[k]
    body, joint, pair_axis, moment, row = zip(*pairs, strict=True)
    Y = np.zeros((trajectory.q.shape[0], model.nv, 10 * n_bodies))
    regressor_kernel(
        kinds,
        np.array([model.parents[j] - 1 for j in range(1, model.njoints)], dtype=np.int64),
        columns,
        axes,
        *(np.ascontiguousarray(x, dtype=float) for x in (trajectory.qd, trajectory.qdd)),
        np.ascontiguousarray(base.omega_dot, dtype=float),
        np.ascontiguousarray(signals[..., :3]),
        np.ascontiguousarray(signals[..., 3:]),
        np.ascontiguousarray(poses[..., :3, :3]),
        np.ascontiguousarray(poses[..., :3, 3]),
        np.array(body, dtype=np.int64),
        np.array(joint, dtype=np.int64),
        np.array(pair_axis, dtype=float),
        np.array(moment, dtype=np.bool_),
        np.array(row, dtype=np.int64),
        Y,
    )
    return Y
