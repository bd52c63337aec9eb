"""The Aaria arm as the run engine's robot: a DH table's arm, built once, and its adapter.

:func:`dh_arm` checks a run's joint and base tables and gives the :class:`DHArmRun` adapter the
engine (:func:`~aaria_pin.core.run.simulate`) runs: the record's columns are the paper's six
modules ``joint1`` … ``joint6`` (zero columns for an empty module), its IMUs the 14 slots in
``senSen`` order (an empty module's slots have parent ``""``), its tables ``senSenDH``,
``senSenJ``, ``senSenB`` and its view ``senSen``. :func:`cached_arm` builds an arm once per
table.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from dataclasses import asdict, dataclass, fields, replace
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.aaria.dh_robot import BodyDimensions, DHRobot, build_dh_robot
from aaria_pin.aaria.sensen import JOINT_NAMES, N_MODULES, sensen_view
from aaria_pin.aaria.sine_tables import default_joint_table, joint_trajectory, validate_joint_table
from aaria_pin.core.arguments import checked
from aaria_pin.core.model import RobotModel
from aaria_pin.core.oscillation import base_motion, default_base_table, validate_base_table
from aaria_pin.core.record import ColumnView, ImuMount
from aaria_pin.core.sampled_motion import JointColumns
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory

__all__ = [
    "ARM_CACHE_SIZE",
    "DH_ROBOT",
    "DHArmRun",
    "DHArmSpec",
    "DHImuSlots",
    "cached_arm",
    "dh_arm",
    "dh_imu_mounts",
    "dh_joint_columns",
    "preset_arm",
    "read_imu_mounts",
]

DH_ROBOT = "aaria-arm"
"""The ``robot`` attribute of a run whose DH table is not named (not a preset)."""


def _module_columns(columns: list[int], values: Array) -> Array:
    """Scatter per-joint columns into the six module columns (zeros for empty modules).

    An arm with every module (``columns`` 0 … 5) keeps ``values`` as they are when they are a
    C-ordered float array already (the run's fresh arrays): no copy.
    """
    if (
        columns == list(range(N_MODULES))
        and values.dtype == np.float64
        and values.shape[1:] == (N_MODULES,)
        and values.flags.c_contiguous
    ):
        return values
    out = np.zeros((values.shape[0], N_MODULES))
    out[:, columns] = values
    return out


def dh_imu_mounts(robot: DHRobot) -> tuple[ImuMount, ...]:
    """A DH robot's IMU slots as the record's mounts (parent ``""``, zero pose: an empty slot).

    Each pose is a copy: the record owns its arrays (the robot may be a cached one).
    """
    return tuple(
        ImuMount(slot.name, slot.parent, np.array(slot.T_parent_imu, dtype=float))
        if slot.parent
        else ImuMount(slot.name, "", np.zeros((4, 4)))
        for slot in robot.imu_slots
    )


ARM_CACHE_SIZE = 8
"""DH arms kept by :func:`cached_arm` (the latest tables, dimensions and mounts used)."""

_ARMS: OrderedDict[tuple[Any, ...], tuple[DHRobot, RobotModel]] = OrderedDict()
_ARMS_LOCK = threading.Lock()


def cached_arm(
    dh_table: ArrayLike,
    dims: BodyDimensions | None = None,
    imu_mount: ArrayLike | None = None,
) -> tuple[DHRobot, RobotModel]:
    """The DH arm of an Aaria table and its moving-base Pinocchio model, built once per table.

    Building the arm (bodies, inertias, IMU slots), its Pinocchio model and, when a record
    keeps it, its URDF text cost 0.8 + 0.7 + 1.5 ms per run of ``aaria-fig2`` (measured
    apart; a 10,000-sample record costs about 20 ms): about 3 ms, or 0.3× the floor of
    ``benchmarks/bench_record.py``; a look-up costs 13 µs. The arm's URDF is written on first
    use (:attr:`DHRobot.urdf`) and kept with it. The last :data:`ARM_CACHE_SIZE` arms are
    kept, keyed by the exact values of the table, the mounts and the dimensions, so runs of
    one table (a preset, a study, the chunks of a long run) build it once; a data set of
    random tables builds each one (a miss costs the key). The arm and the model are only
    read by the runs that share them; a record gets copies of the arrays it keeps.

    Args:
        dh_table: 8 × 5 extended DH table
        dims: body dimensions and densities (default :class:`BodyDimensions`)
        imu_mount: 14 × 4 × 4 IMU mounting poses, or None for the default slots

    Returns:
        The arm and its model on a moving base.

    Raises:
        TableError, ParameterError: as :func:`~aaria_pin.aaria.dh_robot.build_dh_robot`.
    """
    # A snapshot of the dimensions: the arm keeps it, so a caller changing its own
    # density_overrides mapping afterwards changes neither the cached arm nor its key.
    dims = dims or BodyDimensions()
    overrides = dict(sorted(dims.density_overrides.items()))
    dims = replace(dims, density_overrides=overrides)
    try:
        table = np.asarray(dh_table, dtype=float)
        mount = None if imu_mount is None else np.asarray(imu_mount, dtype=float)
        key: tuple[Any, ...] | None = (
            table.shape,
            table.tobytes(),
            None if mount is None else (mount.shape, mount.tobytes()),
            tuple(
                (
                    f.name,
                    tuple(overrides.items())
                    if f.name == "density_overrides"
                    else getattr(dims, f.name),
                )
                for f in fields(dims)
            ),
        )
        hash(key)
    except (TypeError, ValueError):
        key = None  # not numbers (the builder says what is wrong) or not hashable: no cache
    if key is not None:
        with _ARMS_LOCK:
            if key in _ARMS:
                _ARMS.move_to_end(key)
                return _ARMS[key]
    robot = build_dh_robot(dh_table, "aaria", dims, imu_mount=imu_mount)
    arm = robot, robot.model(moving_base=True)
    if key is not None:
        with _ARMS_LOCK:
            _ARMS[key] = arm
            while len(_ARMS) > ARM_CACHE_SIZE:
                _ARMS.popitem(last=False)
    return arm


class DHImuSlots:
    """The IMUs of a DH robot's run (a mix-in of the run adapters of DH robots).

    The robot's slots in record order; a slot without parent belongs to an empty module: its
    signals and mount are zero.
    """

    arm: DHRobot

    @property
    def imu_slots(self) -> list[int]:
        """The slots of the IMUs that exist (not of an empty module)."""
        return [k for k, slot in enumerate(self.arm.imu_slots) if slot.parent is not None]

    @property
    def imu_frames(self) -> list[str]:
        """The model frames of the IMUs that exist."""
        return [self.arm.imu_slots[k].name for k in self.imu_slots]

    @property
    def n_slots(self) -> int:
        """The robot's IMU slots."""
        return len(self.arm.imu_slots)

    @property
    def imu_mounts(self) -> tuple[ImuMount, ...]:
        """The slots as the record's mounts (:func:`dh_imu_mounts`)."""
        return dh_imu_mounts(self.arm)


@dataclass(frozen=True)
class DHArmRun(DHImuSlots):
    """An Aaria DH arm as the run engine's robot (:class:`~aaria_pin.core.run.RunRobot`).

    Made by :func:`dh_arm`. The record's columns are the six modules ``joint1`` … ``joint6``
    (zero columns for an empty module), its IMUs the 14 slots in ``senSen`` order (an empty
    module's slots have parent ``""``); it keeps the tables ``senSenDH``, ``senSenJ``,
    ``senSenB`` and the view ``senSen``.

    Attributes:
        arm: the DH arm
        model: its Pinocchio model on a moving base
        joint_table: 8 × 5 joint oscillation table (``senSenJ``), checked
        base_table: base oscillation table (``senSenB``), checked
        robot_name: the ``robot`` attribute
        keep_urdf: keep the arm's URDF text in the record
    """

    arm: DHRobot
    model: RobotModel
    joint_table: Array
    base_table: Array
    robot_name: str = DH_ROBOT
    keep_urdf: bool = True
    kind: ClassVar[str] = "dh"
    joint_names: ClassVar[tuple[str, ...]] = JOINT_NAMES
    torque_name: ClassVar[str] = "torque table"

    @property
    def columns(self) -> list[int]:
        """The module column (0 … 5) of each of the arm's joints."""
        return [module - 1 for module in self.arm.chain.modules]

    @property
    def limits(self) -> tuple[Array, Array]:
        """Joint limits by module (±inf for an empty module) [rad or m]."""
        lower, upper = np.full(N_MODULES, -np.inf), np.full(N_MODULES, np.inf)
        for joint in self.arm.chain.joints:
            lower[joint.module - 1], upper[joint.module - 1] = joint.lower, joint.upper
        return lower, upper

    @property
    def urdf(self) -> str:
        """The arm's URDF text, or "" (not kept)."""
        return self.arm.urdf if self.keep_urdf else ""

    @property
    def tables(self) -> dict[str, Array]:
        """``senSenDH``, ``senSenJ``, ``senSenB``."""
        return {
            "senSenDH": self.arm.chain.table.copy(),
            "senSenJ": self.joint_table,
            "senSenB": self.base_table,
        }

    @property
    def views(self) -> dict[str, ColumnView]:
        """The paper's 91-column ``senSen``."""
        return {"senSen": sensen_view()}

    def sines(self, times: Array) -> JointTrajectory:
        """``senSenJ``'s sines at ``times``."""
        return joint_trajectory(self.joint_table, self.arm.chain, times)

    def base(self, times: Array) -> BaseMotion:
        """``senSenB``'s motion at ``times``."""
        return base_motion(self.base_table, times)

    def record_columns(self, values: Array) -> Array:
        """The six module columns (:func:`_module_columns`)."""
        return _module_columns(self.columns, values)

    def attributes(self, peaks: Array) -> dict[str, Any]:
        """``robot``, ``body_dimensions``, ``base_frame``, ``tool_frame``."""
        return {
            "robot": self.robot_name,
            "body_dimensions": {
                **asdict(self.arm.dims),
                "density_overrides": dict(self.arm.dims.density_overrides),
            },
            "base_frame": self.model.base_frame,
            "tool_frame": self.model.tool_frame,
        }


@checked
@dataclass(frozen=True)
class DHArmSpec:
    """The inputs of a DH arm beside its DH table (what :func:`dh_arm` builds it from).

    Attributes:
        joint_table: 8 × 5 joint oscillation table (``senSenJ``); None moves every module
        base_table: 2 × 4 or 6 × 4 base oscillation table (``senSenB``); None a gentle motion
        dims: body dimensions and densities (None: :class:`BodyDimensions`)
        imu_mount: 14 × 4 × 4 pose of each IMU slot in its parent frame (None: the default
            slots)
        robot_name: the ``robot`` attribute (a preset's name, or the table's)
        keep_urdf: keep the arm's URDF text in the record
    """

    joint_table: ArrayLike | None = None
    base_table: ArrayLike | None = None
    dims: BodyDimensions | None = None
    imu_mount: ArrayLike | None = None
    robot_name: str = DH_ROBOT
    keep_urdf: bool = True


@checked
def dh_arm(dh_table: ArrayLike, spec: DHArmSpec | None = None) -> DHArmRun:
    """An Aaria arm of a DH table as the run engine's robot, its tables checked.

    Args:
        dh_table: 8 × 5 extended DH table (``senSenDH``)
        spec: the joint and base tables, body dimensions, IMU mounts, name (default
            :class:`DHArmSpec`)

    Returns:
        The robot (the arm is built once per table: :func:`cached_arm`).

    Raises:
        TableError, ParameterError: a bad table.
    """
    spec = DHArmSpec() if spec is None else spec
    arm, model = cached_arm(dh_table, spec.dims, spec.imu_mount)
    senSenJ = (
        default_joint_table(arm.chain)
        if spec.joint_table is None
        else np.array(spec.joint_table, float)
    )
    validate_joint_table(senSenJ, arm.chain)
    senSenB = (
        default_base_table() if spec.base_table is None else validate_base_table(spec.base_table)
    )
    return DHArmRun(arm, model, senSenJ, senSenB, spec.robot_name, spec.keep_urdf)


@checked
def preset_arm(name: str, spec: DHArmSpec | None = None) -> DHArmRun:
    """An Aaria preset's arm as the run engine's robot: its table, joint and base tables.

    Args:
        name: an Aaria preset (e.g. ``aaria-fig2``)
        spec: inputs that replace the preset's (its joint and base tables where given; the
            ``robot_name`` is the preset's)

    Raises:
        ParameterError: an unknown preset, or one that is not an Aaria 8 × 5 table.
    """
    from aaria_pin.aaria.presets import get_preset
    from aaria_pin.errors import ParameterError

    preset = get_preset(name)
    if preset.convention != "aaria":
        raise ParameterError(
            f"preset {name!r} is a {preset.convention} DH table; allowed: an Aaria 8 × 5 table",
            parameter="preset",
            value=name,
            allowed="an Aaria preset",
        )
    spec = DHArmSpec() if spec is None else spec
    joints = preset.joint_table if spec.joint_table is None else spec.joint_table
    base = preset.base_table if spec.base_table is None else spec.base_table
    return dh_arm(preset.table, replace(spec, joint_table=joints, base_table=base, robot_name=name))


def dh_joint_columns(dh_table: ArrayLike) -> JointColumns:
    """An Aaria arm's motion columns: the six modules, those of its joints to be given.

    Raises:
        TableError: a bad DH table.
    """
    from aaria_pin.aaria.dh import chain_from_aaria

    modules = tuple(joint.module - 1 for joint in chain_from_aaria(dh_table).joints)
    return JointColumns(JOINT_NAMES, modules)


def read_imu_mounts(path: Path) -> Array:
    """A DH arm's IMU mounting poses from a file: ``.npy`` (14 × 4 × 4) or a run file's.

    Raises:
        InputFileError: a file that cannot be read (parameter ``imu_mount``), or of other
            values than numbers (parameter ``file``).
        ParameterError: a run file's mounts that are not the Aaria arm's slots (another
            robot's: :func:`~aaria_pin.core.imu_layout.check_slot_mounts`).
    """
    from aaria_pin.errors import InputFileError
    from aaria_pin.files.io import numeric_array

    if path.suffix.lower() == ".npy":
        try:
            poses = np.load(path, allow_pickle=False)
        except (OSError, ValueError) as exc:
            raise InputFileError(
                f"{path}: cannot be read as .npy ({exc})", parameter="imu_mount"
            ) from None
        return numeric_array(path, poses)
    from aaria_pin.aaria.dh_robot import imu_slot_links, imu_slot_names
    from aaria_pin.core.imu_layout import check_slot_mounts
    from aaria_pin.files.runfile import read_run_inputs

    stored = read_run_inputs(path)
    slots = tuple(zip(imu_slot_names(), imu_slot_links(), strict=True))
    check_slot_mounts(stored.imu_mounts, slots, str(path))
    return stored.imu_mount
