"""A recorded run in memory: measured signals only, each sensor with its own time stamps.

A robot in a lab logs its IMUs, joint states and wrenches at their own rates and instants (a
ROS bag, a CSV). A :class:`RecordedRun` holds them as they were measured: one
:class:`SensorStream` per sensor, its time as float64 seconds from the run's
``time_origin_ns`` (int64 nanoseconds, the first stamp: float64 seconds from it hold a stamp to
the nanosecond for recordings up to 30 days; float32 would not, and issue 26 traced wrong fits
to float32 time), its values as float64 rows. There is no truth (no true joint values, no
torques by RNEA), unlike a simulated :class:`~aaria_pin.core.record.RunRecord`, whose single
time axis could not hold sensors at their own rates anyway.

Each stream is checked when it is made (:meth:`SensorStream.__post_init__`): a time axis
strictly increasing, values finite, one row per stamp, the columns its kind has.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = [
    "STREAM_COLUMNS",
    "JointStates",
    "RecordedRun",
    "SensorStream",
    "first_repeated",
    "joint_groups",
]

STREAM_COLUMNS = {
    "imu": ("wx", "wy", "wz", "fx", "fy", "fz"),
    "wrench": ("fx", "fy", "fz", "mx", "my", "mz"),
}
"""The columns of an IMU stream (angular velocity [rad/s], specific force [m/s²]) and of a
wrench stream (force [N], moment [N·m]); a joint stream has ``q:<joint>``, ``qd:<joint>``,
``tau:<joint>`` groups, each there or not for the whole stream."""


@dataclass(frozen=True)
class SensorStream:
    """One sensor's measurements, at its own time stamps.

    Attributes:
        name: the sensor (an IMU's or wrench's name; ``joints`` for the joint states)
        kind: ``imu``, ``joints`` or ``wrench``
        time: (N,) time stamps, seconds from the run's ``time_origin_ns`` [s]
        values: (N, C) measurements, float64 (columns: :data:`STREAM_COLUMNS`, or the joint
            groups)
        columns: the name of each column
        source: where it came from (a topic, a frame id, a file)

    Raises:
        ParameterError: an unknown kind, values not (N, C) with C columns, a time axis that is
            not strictly increasing (naming the first sample that is not), or a value that is
            not finite (naming the sample and the column).
    """

    name: str
    kind: str
    time: Array
    values: Array
    columns: tuple[str, ...]
    source: str = ""

    def __post_init__(self) -> None:
        kinds = (*STREAM_COLUMNS, "joints")
        if self.kind not in kinds:
            raise ParameterError(parameter="kind", value=self.kind, allowed=", ".join(kinds))
        time = np.asarray(self.time, dtype=np.float64)
        values = np.asarray(self.values, dtype=np.float64)
        expected = STREAM_COLUMNS.get(self.kind, self.columns)
        if values.shape != (time.size, len(expected)) or tuple(self.columns) != tuple(expected):
            raise ParameterError(
                f"stream {self.name} has values {values.shape} with columns {self.columns}; "
                f"allowed: ({time.size}, {len(expected)}) with columns {expected}",
                parameter="values",
                element=self.name,
            )
        steps = np.diff(time)
        if steps.size and not (steps > 0).all():
            k = int(np.argmax(~(steps > 0))) + 1
            raise ParameterError(
                f"stream {self.name} time at sample {k} is {time[k]!r} s after {time[k - 1]!r} "
                "s; allowed: strictly increasing",
                parameter="time",
                value=float(time[k]),
                element=self.name,
            )
        bad = np.argwhere(~np.isfinite(values))
        if bad.size:
            row, col = (int(x) for x in bad[0])
            raise ParameterError(
                f"stream {self.name} sample {row} {self.columns[col]} is {values[row, col]}; "
                "allowed: a finite number",
                parameter="values",
                value=float(values[row, col]),
                element=self.name,
            )
        object.__setattr__(self, "time", time)
        object.__setattr__(self, "values", values)
        object.__setattr__(self, "columns", tuple(self.columns))

    @property
    def rate(self) -> float:
        """The median rate of the stamps [Hz] (0 for fewer than two)."""
        return float(1.0 / np.median(np.diff(self.time))) if self.time.size > 1 else 0.0


def first_repeated(names: Sequence[str]) -> str | None:
    """The first (sorted) name given more than once, or None."""
    repeated = sorted({n for n in names if names.count(n) > 1})
    return repeated[0] if repeated else None


def joint_groups(stream: SensorStream) -> tuple[list[str], dict[str, list[int]]]:
    """A joint stream's joints (in order) and each group's columns (``q``, ``qd``, ``tau``)."""
    groups: dict[str, list[int]] = {"q": [], "qd": [], "tau": []}
    joints: list[str] = []
    for index, column in enumerate(stream.columns):
        group, _, joint = column.partition(":")
        groups.setdefault(group, []).append(index)
        if joint not in joints:
            joints.append(joint)
    return joints, groups


@dataclass(frozen=True)
class JointStates:
    """A joint stream's groups, by joint (what an estimator takes of the encoders).

    Attributes:
        time: (N,) time stamps, seconds from the run's ``time_origin_ns`` [s]
        names: the joints, in column order
        q: (N, n) joint values [rad or m], or None when not recorded
        qd: (N, n) joint velocities [rad/s or m/s], or None
        tau: (N, n) joint torques [N·m] or forces [N], or None
    """

    time: Array
    names: tuple[str, ...]
    q: Array | None
    qd: Array | None
    tau: Array | None


@dataclass(frozen=True)
class RecordedRun:
    """A run as a robot recorded it: its sensors' streams, no truth.

    Attributes:
        streams: the sensors' streams (names unique)
        time_origin_ns: the stamp every stream's time counts from [ns]
        source: the recording it came from (a file)

    Raises:
        ParameterError: two streams of one name.
    """

    streams: Sequence[SensorStream]
    time_origin_ns: int = 0
    source: str = ""
    _by_name: dict[str, SensorStream] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        repeated = first_repeated([s.name for s in self.streams])
        if repeated is not None:
            raise ParameterError(
                f"stream {repeated} is recorded twice; allowed: one stream per sensor",
                parameter="streams",
                value=repeated,
            )
        object.__setattr__(self, "streams", tuple(self.streams))
        object.__setattr__(self, "_by_name", {s.name: s for s in self.streams})

    def of_kind(self, kind: str) -> tuple[SensorStream, ...]:
        """The streams of one kind (``imu``, ``joints``, ``wrench``), in order."""
        return tuple(s for s in self.streams if s.kind == kind)

    def stream(self, name: str) -> SensorStream:
        """The stream of a sensor.

        Raises:
            ParameterError: no stream of that name (the names recorded listed).
        """
        found = self._by_name.get(name)
        if found is None:
            raise ParameterError(
                parameter="stream", value=name, allowed=", ".join(self._by_name) or "none"
            )
        return found

    @property
    def imu_names(self) -> tuple[str, ...]:
        """The IMUs' names, in order."""
        return tuple(s.name for s in self.of_kind("imu"))

    def imu(self, name: str) -> tuple[Array, Array]:
        """An IMU's time [s] (N,) and signals (N, 6: ``wx wy wz`` [rad/s], ``fx fy fz`` [m/s²]).

        Raises:
            ParameterError: no stream of that name.
        """
        stream = self.stream(name)
        return stream.time, stream.values

    def joint_states(self, name: str = "joints") -> JointStates:
        """A joint stream's time and its ``q``, ``qd``, ``tau`` by joint (None: not recorded).

        Raises:
            ParameterError: no stream of that name.
        """
        stream = self.stream(name)
        joints, groups = joint_groups(stream)
        parts = {g: stream.values[:, groups[g]] if groups[g] else None for g in ("q", "qd", "tau")}
        return JointStates(stream.time, tuple(joints), **parts)
