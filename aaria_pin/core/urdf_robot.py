"""Any URDF robot as a simulation model: checked, with its IMUs, tool and joint ranges.

:func:`load_urdf_robot` checks the URDF (:mod:`aaria_pin.core.urdf_check`), builds its Pinocchio
model on a fixed base or on a free-flyer that carries the base (the root link), adds one frame
per IMU, and picks the tool frame. The joint motions come from a joint oscillation table with
one row per actuated joint in model order and the Aaria columns ``[amplitude (rad), prismatic
amplitude (m), bias, frequency (rad/s), phase (rad)]``: joint i follows
``q_i(t) = A·sin(w·t + phase) + bias`` (A from the column of its type), and must stay within the
URDF's position limits (``bias ± |A|``) and velocity limits (``|A|·w``). A mimic joint follows
its leader, ``q = multiplier·q_leader + offset``; its row is ignored and its own limits are not
checked (some URDFs, PR2's grippers among them, give mimic limits their leader breaks).
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.core.arguments import checked
from aaria_pin.core.model import RobotModel, build_model
from aaria_pin.core.oscillation import JOINT_COLUMNS, row_span
from aaria_pin.core.record import ImuMount
from aaria_pin.core.se3 import Array
from aaria_pin.core.tables import finite_table
from aaria_pin.core.trajectory import JointTrajectory, sine_motion
from aaria_pin.core.urdf_check import UrdfSummary, check_urdf
from aaria_pin.core.urdf_tree import UrdfJoint
from aaria_pin.errors import InputFileError, MeshWarning, ModelError, TableError, UrdfError

__all__ = [
    "PRISMATIC_SPAN",
    "REVOLUTE_SPAN",
    "TOOL_FRAME_NAMES",
    "UrdfRobot",
    "default_urdf_joint_table",
    "effort_excess",
    "load_urdf_robot",
    "mimic_followers",
    "missing_meshes_message",
    "read_urdf_file",
    "urdf_joint_trajectory",
    "usable_range",
    "validate_urdf_joint_table",
]

TOOL_FRAME_NAMES = ("tool0", "tool_tip", "tool", "tcp", "ee_link", "end_effector")
"""Link names taken as the tool, in this order of preference (then any name ending ``_tcp``,
then the deepest leaf link); ``tool_tip`` before ``tool``: a DH arm's URDF has both, and its
tool frame is the tip."""

PRISMATIC_SPAN = 0.5
"""Longest stretch of a prismatic joint's range that default and random motions use [m]: the
middle of a longer range (URDFs write ``±1e9`` for "unbounded")."""
REVOLUTE_SPAN = 2 * np.pi
"""The same for a revolute joint's range [rad] (and a continuous joint's)."""


@dataclass(frozen=True)
class UrdfRobot:
    """A URDF robot ready to simulate.

    Attributes:
        robot: the model, its base and tool frames, the IMU frames in record order
        summary: what the URDF check found (joints, limits, mimic relations, meshes)
        imu_mounts: the IMU layout, in record order
        joints: the URDF joint of each actuated model joint, in model order
    """

    robot: RobotModel
    summary: UrdfSummary
    imu_mounts: tuple[ImuMount, ...]
    joints: tuple[UrdfJoint, ...]

    @property
    def urdf(self) -> str:
        """The URDF text."""
        assert self.robot.urdf is not None
        return self.robot.urdf


def read_urdf_file(path: str | os.PathLike[str]) -> str:
    """The text of a URDF file.

    Raises:
        InputFileError: missing or unreadable.
    """
    file = Path(path)
    try:
        return file.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InputFileError(f"{file}: no such file", parameter="urdf_file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputFileError(f"{file}: cannot be read ({exc})", parameter="urdf_file") from None


def missing_meshes_message(summary: UrdfSummary) -> str:
    """The one-line warning for a URDF whose meshes are missing (first three named)."""
    shown = ", ".join(summary.missing_meshes[:3])
    more = len(summary.missing_meshes) - 3
    return (
        f"{len(summary.missing_meshes)} mesh file(s) of {summary.name!r} not found "
        f"({shown}{f', and {more} more' if more > 0 else ''}); simulating with the URDF's "
        "inertias"
    )


def _default_tool(summary: UrdfSummary) -> str:
    for name in TOOL_FRAME_NAMES:
        if name in summary.links:
            return name
    for link in summary.links:
        if link.endswith("_tcp"):
            return link
    parent_joint = {joint.child: joint for joint in summary.joints}
    depth: dict[str, int] = {}

    def actuated_depth(link: str) -> int:
        if link not in depth:
            joint = parent_joint.get(link)
            depth[link] = (
                0 if joint is None else actuated_depth(joint.parent) + (joint.kind != "fixed")
            )
        return depth[link]

    parents = {joint.parent for joint in summary.joints}
    leaves = [link for link in summary.links if link not in parents]
    return max(leaves, key=actuated_depth)  # the first of the deepest


@checked
def load_urdf_robot(
    urdf: str,
    *,
    urdf_dir: Path | None = None,
    moving_base: bool = True,
    tool_frame: str | None = None,
    imu_layout: tuple[ImuMount, ...] | None = None,
) -> UrdfRobot:
    """Check a URDF and build its simulation model.

    Args:
        urdf: the URDF text
        urdf_dir: its folder, for relative mesh paths (None: text only)
        moving_base: put the root link on a free-flyer that carries the base motion
        tool_frame: the tool frame (default: see :data:`TOOL_FRAME_NAMES`)
        imu_layout: the IMUs (default :func:`~aaria_pin.core.imu_layout.default_imu_layout`,
            each IMU the URDF carries as a link in place of its default mount:
            :func:`~aaria_pin.core.imu_layout.carried_imu_mounts`)

    Returns:
        The robot.

    Raises:
        UrdfError: the URDF check fails (the message names the element).
        ModelError: Pinocchio cannot build it, or an unknown tool or IMU parent frame.

    Warns:
        MeshWarning: meshes the URDF refers to that cannot be found (the robot still simulates:
            inertias come from the URDF).
    """
    from aaria_pin.core.imu_layout import (
        add_imu_frames,
        carried_imu_mounts,
        default_imu_layout,
    )

    summary = check_urdf(urdf, urdf_dir)
    if summary.missing_meshes:
        warnings.warn(missing_meshes_message(summary), MeshWarning, stacklevel=2)
    tool = tool_frame if tool_frame is not None else _default_tool(summary)
    frames = (*summary.links, *(joint.name for joint in summary.joints))
    if tool not in frames:
        raise ModelError(  # no allowed field: the message keeps naming the model
            f"tool frame {tool!r} is not in model {summary.name!r}; allowed: a link, "
            f"{', '.join(summary.links)}",
            parameter="tool_frame",
            value=tool,
        )
    bare = build_model(
        urdf,
        moving_base=moving_base,
        base_frame=summary.root_link,
        tool_frame=tool,
        sensor_frames=(),
    )
    model = bare.model
    carried = carried_imu_mounts(summary.frame_links)
    mounts = imu_layout
    if mounts is None:
        default = default_imu_layout(model, summary.root_link, tool)
        mounts = tuple(carried.get(mount.name, mount) for mount in default)
    add_imu_frames(model, mounts, carried)
    robot = RobotModel(
        model, urdf, moving_base, summary.root_link, tool, tuple(m.name for m in mounts)
    )
    if robot.n_joints == 0:
        raise UrdfError(
            f"robot {summary.name!r} has no actuated joint (all its joints are fixed); allowed: "
            "at least one revolute, continuous or prismatic joint",
            parameter="urdf",
        )
    joints = tuple(summary.joint(name) for name in robot.joint_names)
    for joint in joints:
        if joint.kind == "fixed":  # pragma: no cover - Pinocchio never makes a fixed joint
            raise ModelError(
                f"joint {joint.name!r} is fixed but has a model joint", parameter="urdf"
            )
    return UrdfRobot(robot, summary, tuple(mounts), joints)


def effort_excess(robot: UrdfRobot, tau: Array) -> dict[str, tuple[float, float]]:
    """Joints whose torque or force exceeds the URDF's effort limit somewhere in a run.

    Args:
        robot: the robot
        tau: joint torques [N·m] or forces [N], (T, n), model order

    Returns:
        Joint name → (peak |tau|, effort limit), for the joints over their limit.
    """
    peaks = np.abs(np.asarray(tau)).max(axis=0) if len(tau) else np.zeros(len(robot.joints))
    return {
        joint.name: (float(peak), joint.effort)
        for joint, peak in zip(robot.joints, peaks, strict=True)
        if peak > joint.effort
    }


def usable_range(joint: UrdfJoint) -> tuple[float, float]:
    """Middle and span of the part of a joint's range that default and random motions use.

    The URDF range, cut about its middle to :data:`PRISMATIC_SPAN` (prismatic) or
    :data:`REVOLUTE_SPAN` (revolute); a continuous joint's is centred on 0.

    Returns:
        ``(middle, span)`` [rad or m].
    """
    cap = PRISMATIC_SPAN if joint.kind == "prismatic" else REVOLUTE_SPAN
    span = joint.upper - joint.lower
    if not np.isfinite(span):
        return 0.0, cap
    return 0.5 * (joint.lower + joint.upper), min(span, cap)


def default_urdf_joint_table(robot: UrdfRobot) -> Array:
    """A joint oscillation table that moves every joint well within its limits.

    Joint i (from 1, model order) swings about the middle of its range (0 for a continuous
    joint): a revolute joint by 0.6 rad or 40 % of its range if less, a prismatic joint by
    40 % of its range or of :data:`PRISMATIC_SPAN` if the range is longer; at ``0.8 + 0.3·i``
    rad/s, slowed if needed to half its velocity limit;
    phase ``0.5·i`` rad. Mimic joints get zeros (they follow their leader).
    """
    table = np.zeros((len(robot.joints), 5))
    for i, joint in enumerate(robot.joints, start=1):
        if joint.mimic is not None:
            continue
        middle, span = usable_range(joint)
        bias = middle
        amplitude = 0.4 * span
        if joint.kind != "prismatic":
            amplitude = min(0.6, amplitude)
        frequency = 0.8 + 0.3 * i
        if amplitude > 0 and np.isfinite(joint.velocity):
            frequency = min(frequency, 0.5 * joint.velocity / amplitude)
        column = 1 if joint.kind == "prismatic" else 0
        table[i - 1, column] = amplitude
        table[i - 1, 2:] = [bias, frequency, 0.5 * i]
    return table


def validate_urdf_joint_table(table: ArrayLike, robot: UrdfRobot) -> Array:
    """Check a URDF robot's joint oscillation table against its joints' limits.

    Returns:
        The table as a float array (a copy).

    Raises:
        TableError: wrong shape, a non-finite value, a negative frequency, or a joint that
            leaves its position or velocity limits.
    """
    what = "joint oscillation table"
    arr = finite_table(table, JOINT_COLUMNS, what, rows=(len(robot.joints),))
    for row, joint in enumerate(robot.joints):
        if joint.mimic is not None:
            continue
        where = f"{what}: row {row + 1} ({joint.kind} joint {joint.name!r})"
        if arr[row, 3] < 0:
            raise TableError(
                f"{where}, column 4 (frequency) is {arr[row, 3]:g}; allowed: >= 0",
                parameter="joint_table",
            )
        span = row_span(arr[row], joint.kind)
        unit = span.unit
        if span.leaves(joint.lower, joint.upper):
            raise TableError(
                f"{where} moves over [{span.low:.4g}, {span.high:.4g}] {unit}; allowed: within "
                f"its URDF limits [{joint.lower:.4g}, {joint.upper:.4g}] {unit}",
                parameter="joint_table",
            )
        speed = span.amplitude * arr[row, 3]
        if speed > joint.velocity * (1 + 1e-12):
            raise TableError(
                f"{where} reaches {speed:.4g} {unit}/s; allowed: within its URDF velocity "
                f"limit {joint.velocity:.4g} {unit}/s (|amplitude| × frequency)",
                parameter="joint_table",
            )
    return arr


def urdf_joint_trajectory(table: ArrayLike, robot: UrdfRobot, time: Array) -> JointTrajectory:
    """Joint motions of a URDF robot from its joint oscillation table (module docstring).

    Args:
        table: n × 5 joint oscillation table, one row per actuated joint in model order
        robot: the robot
        time: sample times [s]

    Returns:
        The trajectory, one column per actuated joint (model order).

    Raises:
        TableError: wrong shape, a non-finite value, a negative frequency, or a joint that
            leaves its position or velocity limits.
    """
    arr = validate_urdf_joint_table(table, robot)
    prismatic = np.array([joint.kind == "prismatic" for joint in robot.joints])
    amplitude = np.where(prismatic, arr[:, 1], arr[:, 0])
    q, qd, qdd = sine_motion(amplitude, arr[:, 2], arr[:, 3], arr[:, 4], time)
    for column, (source, multiplier, offset) in mimic_followers(robot.joints).items():
        q[:, column] = multiplier * q[:, source] + offset
        qd[:, column] = multiplier * qd[:, source]
        qdd[:, column] = multiplier * qdd[:, source]
    return JointTrajectory(time, q, qd, qdd)


def mimic_followers(joints: Sequence[UrdfJoint]) -> dict[int, tuple[int, float, float]]:
    """The mimic joints among actuated ``joints``: column → (leader's column, multiplier, offset).

    A follower's value is ``multiplier · leader + offset`` [rad or m].

    Raises:
        ModelError: a joint that mimics one that is not among ``joints``.
    """
    names = [joint.name for joint in joints]
    followers: dict[int, tuple[int, float, float]] = {}
    for column, joint in enumerate(joints):
        if joint.mimic is None:
            continue
        leader, multiplier, offset = joint.mimic
        if leader not in names:
            raise ModelError(
                f"joint {joint.name!r} mimics {leader!r}, which is not actuated", parameter="joints"
            )
        followers[column] = (names.index(leader), float(multiplier), float(offset))
    return followers
