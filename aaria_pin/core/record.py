"""The run record: what one simulation run of any robot records, in one layout for every robot.

Every run (a DH arm, a URDF robot, the wrist, the pick-place arm) is a :class:`RunRecord` with the
same arrays, and a run file or a data set stores them under the same names:

=============== ============= ================================================================
name            shape         what
=============== ============= ================================================================
``time``        T             sample times [s]
``q``           T × n         joint values [rad or m], one column per joint of ``joint_names``
``qd``          T × n         joint velocities [rad/s or m/s]
``qdd``         T × n         joint accelerations [rad/s² or m/s²]
``tau``         T × n         joint torques [N·m] or forces [N]
``base_pose``   T × 4 × 4     ``T_world_base`` [m] (the identity on a fixed base)
``base_wrench`` T × 6         wrench the base mount applies, ``[fx fy fz mx my mz]`` in
                              world-aligned axes about the base origin [N, N·m]
``tool_pose``   T × 4 × 4     ``T_world_tool`` [m]
``imu``         T × S × 6     per IMU ``[wx wy wz fx fy fz]``: angular velocity [rad/s] and
                              specific force [m/s²], both in the IMU's own axes
``imu_mount``   S × 4 × 4     each IMU's pose in its parent frame [m]
=============== ============= ================================================================

Beside the arrays a record holds the joint and IMU names, the URDF text of its model, the input
``tables`` that re-make it (e.g. the Aaria ``senSenDH``, ``senSenJ``, ``senSenB``, or a URDF
robot's ``joint_table`` and ``base_table``), column ``views`` (tables whose columns are columns of
the arrays, such as the paper's 91-column ``senSen``: stored as HDF5 virtual datasets, so each
number is stored once) and the run's ``attributes`` (rate, duration, seed, noise, ...).

An IMU whose ``parent`` is ``""`` is a slot left empty (an Aaria module of link type 0): its pose
and its signals are zero.

A run with joint hardware (``RunSettings.encoder``, ``torque_sensor``, ``actuator``,
``current_sensor``) keeps
beside them, as tables, one column per joint of ``joint_names``:

======================== ======= ==============================================================
name                     shape   what
======================== ======= ==============================================================
``q_measured``           T × n   the encoders' reading [rad or m] (``q`` stays the true value)
``tau_measured``         T × n   what the joint torque sensors report [N·m or N]
``tau_motor``            T × n   the motor's torque: ``tau + tau_armature + tau_friction``
``tau_armature``         T × n   the reflected rotor inertia's torque ``armature·qdd``
``tau_friction``         T × n   the joint friction torque (viscous, Coulomb, Stribeck)
``encoder_offset``       1 × n   each encoder's zero offset drawn for the run [rad or m]
``torque_sensor_bias``   1 × n   each torque sensor's zero offset drawn for the run [N·m or N]
``torque_sensor_scale``  1 × n   each torque sensor's scale error drawn for the run [1]
``current_measured``     T × n   what the motor current sensors report [A]
``current_sensor_bias``  1 × n   each current sensor's zero offset drawn for the run [A]
``current_sensor_scale`` 1 × n   each torque constant's error drawn for the run [1]
======================== ======= ==============================================================

The tables of T × n (:data:`JOINT_SERIES`) have a time axis: a data set stores them in its
dtype, as the series, and a run in pieces fills them piece by piece. Those of 1 × n are
rows, as a run file stores a table of one axis. ``tau`` stays the rigid-body (RNEA) torque.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin.core.arguments import checked
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

if TYPE_CHECKING:
    from aaria_pin.core.run_metadata import RunMetadata

__all__ = [
    "CONTROL_RUN_TABLES",
    "CONTROL_SERIES",
    "HARDWARE_UNITS",
    "IMU_SIGNALS",
    "JOINT_RUN_TABLES",
    "JOINT_SERIES",
    "SERIES",
    "TIMED_HARDWARE",
    "VIEW_UNITS",
    "ColumnSource",
    "ColumnView",
    "ImuMount",
    "RunRecord",
    "mounts_from_poses",
    "record_shapes",
    "signal_columns",
    "signals_view",
]

IMU_SIGNALS = ("wx", "wy", "wz", "fx", "fy", "fz")
"""The six signals of an IMU, in ``imu``'s last axis (and in every column layout)."""

SERIES = ("time", "q", "qd", "qdd", "tau", "base_pose", "base_wrench", "tool_pose", "imu")
"""The time series of a record (leading axis T), in file order."""

JOINT_SERIES = (
    "q_measured",
    "tau_measured",
    "tau_motor",
    "tau_armature",
    "tau_friction",
    "current_measured",
)
"""The joint hardware's optional tables with a time axis (T × n), in record order."""

CONTROL_SERIES = ("q_reference", "qd_reference", "tau_command")
"""A closed-loop run's tables with a time axis (T × n): the reference it tracked and its
controller's command."""

CONTROL_RUN_TABLES = ("controller_kp", "controller_kd")
"""A closed-loop run's per-run tables (1 × n): its controller's gains."""

TIMED_HARDWARE = (
    *JOINT_SERIES,
    *CONTROL_SERIES,
    "imu_error_jitter",
    "imu_error_bias_random_walk",
)
"""The hardware's tables with a time axis: the joint channels' and the IMU's drawn jitter and
bias random walk. A data set stores them in its dtype, as the series (a run with the IMU's
two is computed in one piece)."""

JOINT_RUN_TABLES = (
    "encoder_offset",
    "torque_sensor_bias",
    "torque_sensor_scale",
    "current_sensor_bias",
    "current_sensor_scale",
)
"""The joint hardware's optional per-run tables (1 × n: one value per joint, float64; a row,
as the files store a table of one axis)."""

UNITS = {
    "time": "s",
    "q": "rad or m",
    "qd": "rad/s or m/s",
    "qdd": "rad/s^2 or m/s^2",
    "tau": "N*m or N",
    "base_pose": "m (4x4 homogeneous transform, world frame)",
    "base_wrench": "N, N*m ([fx fy fz mx my mz], world-aligned axes, about the base origin)",
    "tool_pose": "m (4x4 homogeneous transform, world frame)",
    "imu": "rad/s, m/s^2 ([wx wy wz fx fy fz] in the IMU's own axes)",
    "imu_mount": "m (4x4 homogeneous transform in the parent frame)",
}
"""The ``units`` attribute of each stored array."""

HARDWARE_UNITS = {
    "q_measured": "rad or m (T x n)",
    "tau_measured": "N*m or N (T x n)",
    "tau_motor": "N*m or N (T x n)",
    "tau_armature": "N*m or N (T x n)",
    "tau_friction": "N*m or N (T x n)",
    "encoder_offset": "rad or m (1 x n)",
    "torque_sensor_bias": "N*m or N (1 x n)",
    "torque_sensor_scale": "1 (1 x n)",
    "current_measured": "A (T x n)",
    "current_sensor_bias": "A (1 x n)",
    "current_sensor_scale": "1 (1 x n)",
    "q_reference": "rad or m (T x n)",
    "qd_reference": "rad/s or m/s (T x n)",
    "tau_command": "N*m or N (T x n)",
    "controller_kp": "N*m/rad or N/m (pd), 1/s^2 (computed-torque) (1 x n)",
    "controller_kd": "N*m*s/rad or N*s/m (pd), 1/s (computed-torque) (1 x n)",
    "imu_error_scale": "1 (S x 6, [wx wy wz fx fy fz])",
    "imu_error_cross_axis": "1 (S x 2 x 3 x 3, gyro then accel)",
    "imu_error_misalignment": "1 (S x 2 x 3 x 3 rotations, gyro then accel)",
    "imu_error_matrix": "1 (S x 2 x 3 x 3, gyro then accel)",
    "imu_error_g_sensitivity": "rad/s per m/s^2 (S x 3 x 3)",
    "imu_error_nonlinearity": "s/rad (wx wy wz), s^2/m (fx fy fz) (S x 6)",
    "imu_error_bias_offset": "rad/s (wx wy wz), m/s^2 (fx fy fz) (S x 6)",
    "imu_error_time_offset": "s (S)",
    "imu_error_jitter": "s (T x S)",
    "imu_error_bias_random_walk": "rad/s (wx wy wz), m/s^2 (fx fy fz) (T x 6S, slot by slot)",
}
"""The ``units`` (and shape) of the hardware's optional tables: the joint channels' and the IMU's
drawn errors (docs/guide/joint-sensors.md, docs/guide/imu.md)."""

VIEW_UNITS = "see columns: s, rad or m, rad/s, m/s^2"
"""The ``units`` of a view of time, joint values and IMU signals (e.g. ``senSen``)."""


@checked
@dataclass(frozen=True)
class ImuMount:
    """An IMU rigidly mounted on a frame of the robot.

    Attributes:
        name: the IMU's name (also its frame's name in the model)
        parent: the frame it is mounted on (a link, joint or fixed frame of the URDF); ``""``
            for an empty slot (no IMU: zero pose, zero signals)
        T_parent_imu: its pose in the parent frame, 4 × 4 [m]
    """

    name: str
    parent: str
    T_parent_imu: Array


def mounts_from_poses(
    names: Sequence[str], parents: Sequence[str], poses: Array
) -> tuple[ImuMount, ...]:
    """IMU mounts from stored names, parents and poses; an all-zero pose is an empty slot.

    A file that stores the parents once for many runs (a data set of random Aaria arms) or not
    at all (0.1.0) marks a slot empty in one run by its zero pose: its parent is then ``""``.

    Args:
        names: the S IMU names
        parents: each IMU's parent frame
        poses: each IMU's pose in its parent frame, S × 4 × 4 [m]
    """
    return tuple(
        ImuMount(name, parent if np.any(pose) else "", pose)
        for name, parent, pose in zip(names, parents, poses, strict=True)
    )


@dataclass(frozen=True)
class ColumnSource:
    """One column of a view: a column of one of the record's time series.

    Attributes:
        array: the series' name (one of :data:`SERIES`)
        index: the index into the series' axes after time (``()`` for ``time``, ``(j,)`` for
            joint j of ``q``, ``(s, k)`` for signal k of IMU s)
    """

    array: str
    index: tuple[int, ...]


@dataclass(frozen=True)
class ColumnView:
    """A T × C table whose columns are columns of the record's series (stored once, viewed).

    Attributes:
        columns: the C column names
        sources: where each column comes from, one per column
        units: the view's ``units`` attribute
    """

    columns: tuple[str, ...]
    sources: tuple[ColumnSource, ...]
    units: str = ""

    def __post_init__(self) -> None:
        if len(self.columns) != len(self.sources):
            raise ParameterError(
                f"view has {len(self.columns)} columns and {len(self.sources)} sources; "
                "allowed: one source per column",
                parameter="columns",
            )

    def materialise(self, series: Mapping[str, Array]) -> Array:
        """The view as a T × C array (a copy) from the series it refers to.

        Args:
            series: the record's series by name (the leading axis is time, or runs × time)
        """
        lead = np.shape(series["time"])
        first = np.asarray(series[self.sources[0].array])
        out = np.empty((*lead, len(self.sources)), dtype=first.dtype)
        for c, source in enumerate(self.sources):
            array = np.asarray(series[source.array])
            index: tuple[Any, ...] = (Ellipsis, *source.index)
            out[..., c] = array[index] if source.index else array
        return out


def _position(what: str, name: str, names: Sequence[str]) -> int:
    """The position of ``name`` among a run's ``names`` of one kind (IMUs, joints, views).

    Raises:
        ParameterError: no ``what`` of that name.
    """
    if name not in names:
        raise ParameterError(
            f"{what} {name!r} is not in this run; allowed: {', '.join(names) or 'none'}",
            parameter="name",
        )
    return names.index(name)


def record_shapes(samples: int, joints: int, imus: int) -> dict[str, tuple[int, ...]]:
    """The shape of each series (:data:`SERIES`) and of ``imu_mount``, in file order.

    Args:
        samples: T, the number of samples
        joints: n, the number of joints
        imus: S, the number of IMUs (slots)
    """
    return {
        "time": (samples,),
        "q": (samples, joints),
        "qd": (samples, joints),
        "qdd": (samples, joints),
        "tau": (samples, joints),
        "base_pose": (samples, 4, 4),
        "base_wrench": (samples, 6),
        "tool_pose": (samples, 4, 4),
        "imu": (samples, imus, len(IMU_SIGNALS)),
        "imu_mount": (imus, 4, 4),
    }


def signal_columns(joint_names: Sequence[str], imu_names: Sequence[str]) -> tuple[str, ...]:
    """Names of the flat signal table: ``time``, ``q:<joint>`` per joint, ``<imu>_<signal>``."""
    return (
        "time",
        *(f"q:{joint}" for joint in joint_names),
        *(f"{imu}_{signal}" for imu in imu_names for signal in IMU_SIGNALS),
    )


def signals_view(
    joint_names: Sequence[str],
    imu_names: Sequence[str],
    columns: Sequence[str] | None = None,
    units: str = "see columns",
) -> ColumnView:
    """The flat signal table (:attr:`RunRecord.columns`) as a view of ``time``, ``q``, ``imu``.

    Args:
        joint_names: the n joints of ``q``
        imu_names: the S IMUs of ``imu``
        columns: other names for the same 1 + n + 6 S columns (default :func:`signal_columns`;
            the Aaria ``senSen`` names them ``time``, ``q1`` …, ``<slot>_<signal>``)
        units: the view's ``units`` attribute
    """
    sources = (
        ColumnSource("time", ()),
        *(ColumnSource("q", (j,)) for j in range(len(joint_names))),
        *(
            ColumnSource("imu", (s, k))
            for s in range(len(imu_names))
            for k in range(len(IMU_SIGNALS))
        ),
    )
    names = signal_columns(joint_names, imu_names) if columns is None else tuple(columns)
    return ColumnView(names, sources, units)


@dataclass
class RunRecord:
    """Everything one run of any robot records (module docstring: names, shapes, units).

    Attributes:
        time: sample times, T [s]
        joint_names: the n joints of ``q`` … ``tau``, in column order
        q: joint values, T × n [rad or m]
        qd: joint velocities, T × n [rad/s or m/s]
        qdd: joint accelerations, T × n [rad/s² or m/s²]
        tau: joint torques [N·m] or forces [N], T × n
        base_pose: ``T_world_base``, T × 4 × 4 [m]
        base_wrench: wrench the base mount applies, ``[fx fy fz mx my mz]`` in world-aligned
            axes about the base origin, T × 6 [N, N·m]
        tool_pose: ``T_world_tool``, T × 4 × 4 [m]
        imu: IMU signals, T × S × 6 ``[wx wy wz fx fy fz]`` in each IMU's own axes
            [rad/s, m/s²]
        imu_mounts: the S IMUs, in ``imu`` order
        urdf: the URDF text of the model the run was computed on
        tables: the input tables that re-make the run, by name
        views: column views of the series, by name (e.g. ``senSen``)
        attributes: rate, duration, seed, noise settings, gravity, robot, tool frame, version
    """

    time: Array
    joint_names: tuple[str, ...]
    q: Array
    qd: Array
    qdd: Array
    tau: Array
    base_pose: Array
    base_wrench: Array
    tool_pose: Array
    imu: Array
    imu_mounts: tuple[ImuMount, ...]
    urdf: str = ""
    tables: dict[str, Array] = field(default_factory=dict)
    views: dict[str, ColumnView] = field(default_factory=dict)
    attributes: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.joint_names = tuple(self.joint_names)
        self.imu_mounts = tuple(self.imu_mounts)
        samples, joints, imus = np.shape(self.time)[0], len(self.joint_names), len(self.imu_mounts)
        shapes = record_shapes(samples, joints, imus)
        for name in SERIES:
            if np.shape(getattr(self, name)) != shapes[name]:
                raise ParameterError(
                    f"run record {name} has shape {np.shape(getattr(self, name))}; "
                    f"allowed: {shapes[name]}",
                    parameter=name,
                )
        for name, view in self.views.items():
            for source in view.sources:
                if source.array not in SERIES:
                    raise ParameterError(
                        f"view {name} column source is {source.array!r}; allowed: "
                        + ", ".join(SERIES),
                        parameter="views",
                    )

    @property
    def n_samples(self) -> int:
        """T, the number of samples."""
        return int(np.shape(self.time)[0])

    @property
    def metadata(self) -> RunMetadata:
        """The attributes as typed fields (:class:`~aaria_pin.core.run.RunMetadata`)."""
        from aaria_pin.core.run_metadata import RunMetadata

        return RunMetadata.from_attributes(self.attributes)

    @property
    def imu_names(self) -> tuple[str, ...]:
        """The IMU names, in ``imu`` order."""
        return tuple(mount.name for mount in self.imu_mounts)

    @property
    def imu_mount(self) -> Array:
        """Each IMU's pose in its parent frame, S × 4 × 4 [m] (zeros for an empty slot)."""
        if not self.imu_mounts:
            return np.zeros((0, 4, 4))
        return np.stack([np.asarray(mount.T_parent_imu, dtype=float) for mount in self.imu_mounts])

    @property
    def columns(self) -> tuple[str, ...]:
        """Names of the flat signal table :meth:`signals`."""
        return signal_columns(self.joint_names, self.imu_names)

    def series(self) -> dict[str, Array]:
        """The time series by name, in file order (:data:`SERIES`)."""
        return {name: getattr(self, name) for name in SERIES}

    def arrays(self) -> dict[str, Array]:
        """Every stored array by name, in file order: the series, ``imu_mount``, the tables."""
        return {**self.series(), "imu_mount": self.imu_mount, **self.tables}

    def imu_signals(self, name: str) -> Array:
        """The T × 6 signals ``[wx wy wz fx fy fz]`` of one IMU by name.

        Raises:
            ParameterError: no IMU of that name.
        """
        return self.imu[:, _position("IMU", name, self.imu_names)]

    def joint(self, name: str) -> int:
        """The column of a joint by name.

        Raises:
            ParameterError: no joint of that name.
        """
        return _position("joint", name, self.joint_names)

    def signals(self) -> Array:
        """The flat T × C table of :attr:`columns`: time, joint values, IMU signals (a copy)."""
        samples = self.n_samples
        return np.concatenate(
            [self.time[:, None], self.q, np.reshape(self.imu, (samples, -1))], axis=1
        )

    def view(self, name: str) -> Array:
        """A column view by name as a T × C array (e.g. ``record.view("senSen")``).

        Raises:
            ParameterError: no view of that name.
        """
        _position("view", name, tuple(self.views))
        return self.views[name].materialise(self.series())
