"""Joint motions of a run as objects: sine table, Fourier, sampled trajectory.

Each makes its trajectory piece by piece and stores itself.

A motion is checked once against the robot (:meth:`Motion.checked`), makes the joints' motion
on each piece's sample times (:meth:`Motion.trajectory`), and declares the tables and
attributes a record keeps about it (:meth:`Motion.record`);
:func:`~aaria_pin.core.run.drives.motion_from_record` loads it back from a record's tables and
attributes through the registry :data:`MOTIONS` (the record's ``motion`` attribute names its
entry; its drive, :mod:`~aaria_pin.core.run.drives`, wraps it). Adding a motion is one class
here (or in any module) plus its entry in :data:`MOTIONS`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol, Self

import numpy as np

from aaria_pin.core.arguments import checked
from aaria_pin.core.excitation import FourierExcitation
from aaria_pin.core.joint_sensors import JointHardware
from aaria_pin.core.run.robot import RunRobot
from aaria_pin.core.sampled_motion import check_trajectory
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory
from aaria_pin.errors import InputFileError, ParameterError

__all__ = [
    "MOTIONS",
    "FollowedMotion",
    "FourierMotion",
    "Motion",
    "SampledTrajectory",
    "SineTable",
    "as_motion",
]


class Motion(Protocol):
    """A run's joint motion.

    Attributes:
        name: the record's ``motion`` attribute (its :data:`MOTIONS` entry)
        drive: the record's ``drive`` attribute: ``"motion"`` (the joints follow it),
            ``"torque"`` (they move under given torques) or a controller's law
        whole: it must be computed in one piece (forward dynamics integrates the whole run)
    """

    @property
    def name(self) -> str:
        """The record's ``motion`` attribute."""
        ...

    @property
    def drive(self) -> str:
        """The record's ``drive`` attribute."""
        ...

    @property
    def whole(self) -> bool:
        """Whether it must be computed in one piece."""
        ...

    def checked(self, robot: RunRobot, samples: int, rate: float) -> Motion:
        """The motion checked for a run of ``robot`` with ``samples`` at ``rate`` [Hz].

        Raises:
            ParameterError: a motion the robot cannot follow.
        """
        ...

    def trajectory(
        self, robot: RunRobot, span: tuple[int, int], times: Array, base: BaseMotion
    ) -> JointTrajectory:
        """The joints' motion (model order) over samples ``span`` = (start, stop) at ``times``."""
        ...

    def record(self, robot: RunRobot) -> tuple[dict[str, Array], dict[str, Any]]:
        """The tables and attributes a record keeps about the motion."""
        ...


class FollowedMotion:
    """Base of a motion the joints follow (``drive`` ``"motion"``), made piece by piece.

    Its :meth:`checked` is the motion itself (checked when it was made, or by the robot);
    a motion that checks itself against the robot overrides it.
    """

    drive: ClassVar[str] = "motion"
    whole: ClassVar[bool] = False

    def checked(self, robot: RunRobot, samples: int, rate: float) -> Self:
        """Itself: checked when it was made (the robot checks its own joint table)."""
        return self

    def with_hardware(self, hardware: JointHardware, seed: int | np.random.SeedSequence) -> Self:
        """Itself: the joints follow it whatever drives them."""
        return self


@dataclass(frozen=True)
class SineTable(FollowedMotion):
    """The robot's joint table: each joint a sine (the default motion)."""

    name: ClassVar[str] = "sine"

    def trajectory(
        self, robot: RunRobot, span: tuple[int, int], times: Array, base: BaseMotion
    ) -> JointTrajectory:
        """The joint table's sines at ``times``."""
        return robot.sines(times)

    def record(self, robot: RunRobot) -> tuple[dict[str, Array], dict[str, Any]]:
        """No table (the robot keeps its joint table); ``motion`` ``sine``."""
        return {}, {"motion": self.name}

    @classmethod
    def from_record(cls, tables: dict[str, Array], attributes: dict[str, Any]) -> SineTable:
        """The sines (the robot's table is the robot's)."""
        return cls()


def _model_columns(robot: RunRobot, q: Array, qd: Array, qdd: Array) -> tuple[Array, ...]:
    """Record columns → the model's joint columns (contiguous)."""
    if robot.columns is None:
        return q, qd, qdd
    return tuple(np.ascontiguousarray(x[:, robot.columns]) for x in (q, qd, qdd))


@checked
@dataclass(frozen=True)
class SampledTrajectory(FollowedMotion):
    """A given trajectory of the run's samples, one column per record joint column.

    Stored as the table ``joint_trajectory`` (T × (1 + 3n): time, q, qd, qdd).

    Attributes:
        samples: the trajectory (e.g.
            :func:`~aaria_pin.core.sampled_motion.trajectory_from_samples`)
    """

    samples: JointTrajectory
    name: ClassVar[str] = "trajectory"

    def checked(self, robot: RunRobot, samples: int, rate: float) -> SampledTrajectory:
        """Checked against the run's time grid and the robot's limits (``check_trajectory``)."""
        lower, upper = robot.limits
        checked = check_trajectory(self.samples, samples, rate, lower, upper, robot.joint_names)
        return SampledTrajectory(checked)

    def trajectory(
        self, robot: RunRobot, span: tuple[int, int], times: Array, base: BaseMotion
    ) -> JointTrajectory:
        """The trajectory's samples of the piece (model columns)."""
        start, stop = span
        given = self.samples
        q, qd, qdd = (x[start:stop] for x in (given.q, given.qd, given.qdd))
        return JointTrajectory(times, *_model_columns(robot, q, qd, qdd))

    def record(self, robot: RunRobot) -> tuple[dict[str, Array], dict[str, Any]]:
        """``joint_trajectory`` and ``motion`` ``trajectory``."""
        s = self.samples
        table = np.column_stack([s.time, s.q, s.qd, s.qdd])
        return {"joint_trajectory": table}, {"motion": self.name}

    @classmethod
    def from_record(cls, tables: dict[str, Array], attributes: dict[str, Any]) -> SampledTrajectory:
        """The stored ``joint_trajectory``.

        Raises:
            InputFileError: the table is missing or not T × (1 + 3n).
        """
        table = _stored_table(tables, "joint_trajectory", cls.name)
        if table.ndim != 2 or (table.shape[1] - 1) % 3 or table.shape[1] < 4:
            raise InputFileError(
                f"run table joint_trajectory has shape {table.shape}; allowed: T × (1 + 3n)",
                parameter="joint_trajectory",
                element="run",
            )
        n = (table.shape[1] - 1) // 3
        return cls(
            JointTrajectory(
                table[:, 0].copy(),
                np.ascontiguousarray(table[:, 1 : 1 + n]),
                np.ascontiguousarray(table[:, 1 + n : 1 + 2 * n]),
                np.ascontiguousarray(table[:, 1 + 2 * n :]),
            )
        )


@checked
@dataclass(frozen=True)
class FourierMotion(FollowedMotion):
    """A Fourier excitation, one row per record joint column.

    Stored as the table ``fourier_coefficients`` and the attribute ``fourier`` (its settings and
    base frequency). Each sample depends only on its own time, so pieces put together are the
    whole run's motion bit for bit.

    Attributes:
        excitation: the excitation (e.g. ``dh_fourier_excitation``, ``urdf_fourier_excitation``)
    """

    excitation: FourierExcitation
    name: ClassVar[str] = "fourier"

    def checked(self, robot: RunRobot, samples: int, rate: float) -> FourierMotion:
        """Checked: one row per record joint column, every joint within its limits.

        Raises:
            ParameterError: another number of rows, or a joint outside its limits at a
                sample (parameter ``motion``).
        """
        n_joints = len(robot.joint_names)
        if self.excitation.n_joints != n_joints:
            raise ParameterError(
                f"motion is a Fourier excitation of {self.excitation.n_joints} joints; "
                f"allowed: {n_joints}",
                parameter="motion",
                value=self.excitation.n_joints,
                allowed=f"{n_joints} joints",
            )
        self.excitation.check_range(samples, rate, robot.limits, robot.joint_names)
        return self

    def trajectory(
        self, robot: RunRobot, span: tuple[int, int], times: Array, base: BaseMotion
    ) -> JointTrajectory:
        """The excitation evaluated at ``times`` (model columns)."""
        whole = self.excitation.trajectory(times)
        return JointTrajectory(times, *_model_columns(robot, whole.q, whole.qd, whole.qdd))

    def record(self, robot: RunRobot) -> tuple[dict[str, Array], dict[str, Any]]:
        """``fourier_coefficients``, ``motion`` ``fourier`` and ``fourier``."""
        e = self.excitation
        settings = {**e.settings, "base_frequency": float(e.base_frequency)}
        return {"fourier_coefficients": e.table()}, {"motion": self.name, "fourier": settings}

    @classmethod
    def from_record(cls, tables: dict[str, Array], attributes: dict[str, Any]) -> FourierMotion:
        """The stored coefficients and settings.

        Raises:
            InputFileError: the table or the ``fourier`` attribute is missing.
        """
        table = _stored_table(tables, "fourier_coefficients", cls.name)
        settings = attributes.get("fourier")
        if not isinstance(settings, dict) or "base_frequency" not in settings:
            raise InputFileError(
                "run has motion 'fourier' but no attribute fourier with its base_frequency; "
                "allowed: a run written by this toolkit",
                parameter="fourier",
                element="run",
            )
        return cls(FourierExcitation.from_table(table, float(settings["base_frequency"]), settings))


MOTIONS: dict[str, Callable[[dict[str, Array], dict[str, Any]], Motion]] = {
    SineTable.name: SineTable.from_record,
    SampledTrajectory.name: SampledTrajectory.from_record,
    FourierMotion.name: FourierMotion.from_record,
}
"""How each stored motion (the record's ``motion`` attribute) loads itself from a record."""

_WRAPPERS: dict[type, Callable[[Any], Motion]] = {
    type(None): lambda _: SineTable(),
    JointTrajectory: SampledTrajectory,
    FourierExcitation: FourierMotion,
}


def as_motion(value: Motion | JointTrajectory | FourierExcitation | None) -> Motion:
    """A motion from what the producers take: None (sines), a trajectory, an excitation.

    Raises:
        ParameterError: something else (parameter ``motion``).
    """
    wrap = _WRAPPERS.get(type(value))
    if wrap is not None:
        return wrap(value)
    if all(hasattr(value, a) for a in ("checked", "trajectory", "record", "drive")):
        return value  # type: ignore[return-value]
    raise ParameterError(
        parameter="motion",
        value=type(value).__name__,
        allowed="None, a JointTrajectory, a FourierExcitation or a Motion",
    )


def _stored_table(tables: dict[str, Array], name: str, motion: str) -> Array:
    """A motion's stored table as floats, or one line naming what is missing."""
    if name not in tables:
        raise InputFileError(
            f"run has motion {motion!r} but no table {name}; allowed: a run written by this "
            "toolkit",
            parameter=name,
            element="run",
        )
    return np.asarray(tables[name], dtype=float)
