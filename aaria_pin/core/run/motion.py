"""Joint motions of a run as objects: sine table, Fourier, sampled trajectory, torque drive.

Each makes its trajectory piece by piece and stores itself.

A motion is checked once against the robot (:meth:`Motion.checked`), makes the joints' motion
on each piece's sample times (:meth:`Motion.trajectory`), and declares the tables and
attributes a record keeps about it (:meth:`Motion.record`); :func:`motion_from_record` loads it
back from a record's tables and attributes through the registry :data:`MOTIONS` (the record's
``motion`` attribute names its entry; a ``torque_table`` wraps it in a :class:`TorqueDrive`).
Adding a motion is one class here (or in any module) plus its entry in :data:`MOTIONS`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from typing import Any, ClassVar, Protocol, Self, TypedDict

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.core.arguments import checked
from aaria_pin.core.excitation import FourierExcitation
from aaria_pin.core.forward import Progress
from aaria_pin.core.joint_limits import (
    DEFAULT_LIMITS,
    JointBounds,
    limit_policy,
    model_velocity_limits,
    stored_limits,
)
from aaria_pin.core.joint_sensors import (
    CLOSED_LOOP_DRIVES,
    ActuatorModel,
    JointHardware,
    select_joints,
)
from aaria_pin.core.run.robot import RunRobot
from aaria_pin.core.sampled_motion import check_trajectory
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory
from aaria_pin.errors import InputFileError, ParameterError

__all__ = [
    "MOTIONS",
    "DriveOptions",
    "FollowedMotion",
    "FourierMotion",
    "Motion",
    "SampledTrajectory",
    "SineTable",
    "TorqueDrive",
    "as_motion",
    "driven",
    "equipped",
    "joint_bounds",
    "motion_from_record",
    "recorded_dynamics",
    "stored_drive",
]


class Motion(Protocol):
    """A run's joint motion.

    Attributes:
        name: the record's ``motion`` attribute (its :data:`MOTIONS` entry)
        drive: the record's ``drive`` attribute: ``"motion"`` (the joints follow it) or
            ``"torque"`` (they move under given torques)
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


@checked
@dataclass(frozen=True)
class TorqueDrive:
    """The joints move under given torques by forward dynamics, from ``start``'s state at t = 0.

    Stored as ``start``'s tables and attributes, the table ``torque_table`` and ``drive``
    ``torque``; computed in one piece. With an actuator (the run's ``RunSettings.actuator``,
    set by the engine: :func:`actuated`) the torques are motor torques: the forward dynamics
    add the armature and take off the friction. The integrated motion is then held to the
    model's position and velocity limits by the policy ``limits``
    (:mod:`~aaria_pin.core.joint_limits`), stored as the attribute ``limits``.

    Attributes:
        torques: (T, n) joint torques [N·m] or forces [N] by record column (columns of an Aaria
            arm's empty modules are ignored)
        start: the motion whose values and velocities at t = 0 start the run
        actuator: the joints' motors, by record column (None: none)
        limits: ``stop`` (the run ends with a :class:`~aaria_pin.errors.JointLimitError` at
            the first sample beyond a limit), ``clamp`` (stiff-damped stops in the dynamics) or
            ``ignore``
        dynamics: the integrator, by its name in :data:`~aaria_pin.core.forward.DYNAMICS`
            (recorded: a run is re-made by the one that made it)
        progress: told ``(samples done, samples)`` as the integration goes (None: silent)
    """

    torques: ArrayLike
    start: Motion = field(default_factory=SineTable)
    actuator: ActuatorModel | None = None
    limits: str = DEFAULT_LIMITS
    dynamics: str = "aba"
    progress: Progress | None = field(default=None, compare=False)
    drive: ClassVar[str] = "torque"
    whole: ClassVar[bool] = True

    def with_hardware(
        self, hardware: JointHardware, seed: int | np.random.SeedSequence
    ) -> TorqueDrive:
        """The drive with the run's actuator (its torques are then motor torques)."""
        if hardware.actuator == self.actuator:
            return self
        return replace(self, actuator=hardware.actuator)

    @property
    def name(self) -> str:
        """The ``motion`` attribute: the starting motion's."""
        return self.start.name

    def checked(self, robot: RunRobot, samples: int, rate: float) -> TorqueDrive:
        """The starting motion, the torque table (``check_torques``) and the policy checked.

        Raises:
            ParameterError: a bad table, or ``limits`` that names no policy built.
        """
        from aaria_pin.core.forward import check_torques

        limit_policy(self.limits)
        start = self.start.checked(robot, samples, rate)
        n_columns = len(robot.joint_names)
        tau = check_torques(self.torques, samples, n_columns, robot.torque_name)
        return replace(self, torques=tau, start=start)

    def trajectory(
        self, robot: RunRobot, span: tuple[int, int], times: Array, base: BaseMotion
    ) -> JointTrajectory:
        """Forward dynamics under the torques (the whole run: one piece), then its policy.

        Raises:
            JointLimitError: the policy ``stop`` and a sample beyond the model's limits.
        """
        from aaria_pin.core.forward import DYNAMICS

        initial = self.start.trajectory(robot, span, times, base)
        torques = np.asarray(self.torques, dtype=float)
        tau = torques if robot.columns is None else torques[:, robot.columns]
        motors = self.actuator
        if motors is not None:
            motors = select_joints(motors, torques.shape[1], robot.columns)
        policy, bounds = limit_policy(self.limits), joint_bounds(robot)
        moved = DYNAMICS[self.dynamics](
            robot.model,
            base,
            tau,
            times,
            initial.q[0],
            initial.qd[0],
            actuator=motors,
            progress=self.progress,
            **policy.forward_options(bounds),
        )
        return policy.applied(moved, bounds)

    def record(self, robot: RunRobot) -> tuple[dict[str, Array], dict[str, Any]]:
        """The starting motion's, ``torque_table`` and the attributes ``limits``, ``dynamics``."""
        tables, attributes = self.start.record(robot)
        tau = np.asarray(self.torques, dtype=float)
        attributes = {**attributes, "limits": self.limits, "dynamics": self.dynamics}
        return {**tables, "torque_table": tau}, attributes


def joint_bounds(robot: RunRobot) -> JointBounds:
    """The robot's position limits and its model's velocity limits, model order."""
    lower, upper = robot.limits
    columns = list(range(lower.size)) if robot.columns is None else robot.columns
    names = [robot.joint_names[c] for c in columns]
    return JointBounds(names, lower[columns], upper[columns], model_velocity_limits(robot.model))


class DriveOptions(TypedDict, total=False):
    """How a run's joints are driven: the request options :func:`driven` reads (all optional).

    Attributes:
        torques: (T, n) torques by record column: the joints move under them (a torque drive)
        drive: ``motion``, ``torque`` (with ``torques``), or a closed-loop drive (``pd``,
            ``computed-torque``: the motion is the controller's reference)
        limits: the joint-limit policy of a torque or closed-loop drive (``stop``, ``clamp``,
            ``ignore``)
        dynamics: a torque drive's integrator by its recorded name (``kernel``, ``reference``)
        integrator: a closed-loop drive's integrator (``rk4``, ``euler``)
        progress: told ``(samples done, samples)`` as a driven run's integration goes
    """

    torques: ArrayLike | None
    drive: str
    limits: str
    dynamics: str
    integrator: str
    progress: Progress | None


def driven(motion: Motion, options: Mapping[str, Any]) -> Motion:
    """The run's motion under a request's options (:class:`DriveOptions`).

    A :class:`TorqueDrive` when they give torques, a
    :class:`~aaria_pin.core.run.closed_loop.ClosedLoopDrive` tracking ``motion`` when
    ``drive`` names a law, else ``motion`` itself.

    Args:
        motion: the motion (a torque drive's start, a closed-loop drive's reference)
        options: a request's options

    Raises:
        ParameterError: an unknown ``drive``, torques with a closed-loop drive, or ``limits``
            for a run that is not driven (only a driven run has a policy).
    """
    torques, limits = options.get("torques"), options.get("limits")
    drive = options.get("drive")
    known = ("motion", "torque", *CLOSED_LOOP_DRIVES)
    if drive is not None and drive not in known:
        raise ParameterError(parameter="drive", value=drive, allowed=", ".join(known))
    progress = options.get("progress")
    if drive in CLOSED_LOOP_DRIVES:
        if torques is not None:
            raise ParameterError(
                f"torques are given for drive {drive!r}; allowed: torques with drive torque",
                parameter="torques",
                allowed="torques with drive torque",
            )
        from aaria_pin.core.run.closed_loop import ClosedLoopDrive

        integrator = options.get("integrator", "rk4")
        limits = limits or DEFAULT_LIMITS
        return ClosedLoopDrive(motion, drive, limits, integrator, progress=progress)
    if torques is None:
        if limits is not None:
            raise ParameterError(
                f"limits is {limits!r} for a run without torques; allowed: limits with torques "
                "or a closed-loop drive",
                parameter="limits",
                value=limits,
            )
        return motion
    dynamics = options.get("dynamics", TorqueDrive.dynamics)
    limits = limits or DEFAULT_LIMITS
    return TorqueDrive(torques, motion, limits=limits, dynamics=dynamics, progress=progress)


def stored_drive(tables: Mapping[str, Array], attributes: Mapping[str, Any]) -> DriveOptions:
    """The drive a record stores, as request options (:class:`DriveOptions`; none: followed).

    A torque run's ``torque_table``, ``limits`` and ``dynamics``; a closed-loop run's
    ``drive``, ``limits`` and ``integrator``.
    """
    drive = attributes.get("drive")
    if drive in CLOSED_LOOP_DRIVES:
        return {
            "drive": str(drive),
            "limits": stored_limits(dict(attributes)),
            "integrator": str(attributes.get("integrator", "rk4")),
        }
    if "torque_table" in tables:
        return {
            "torques": tables["torque_table"],
            "limits": stored_limits(dict(attributes)),
            "dynamics": recorded_dynamics(dict(attributes)),
        }
    return {}


def equipped(motion: Motion, hardware: JointHardware, seed: int | np.random.SeedSequence) -> Motion:
    """The motion with the run's joint models and noise seed (``Motion.with_hardware``).

    A torque drive takes the run's actuator (its torques are motor torques), a closed-loop
    drive its actuator, sensors and controller; a followed motion is itself. A motion made
    outside the package without the method is followed as given.
    """
    with_hardware = getattr(motion, "with_hardware", None)
    return motion if with_hardware is None else with_hardware(hardware, seed)  # type: ignore[no-any-return]


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


def motion_from_record(
    tables: dict[str, Array], attributes: dict[str, Any], drive: bool = True
) -> Motion:
    """The motion a record stores (:meth:`Motion.record`), to re-make the run.

    A record without a ``motion`` attribute (written before motions were stored) follows its
    joint table's sines; one with a ``torque_table`` is driven by it (with ``drive``; without,
    the motion that starts it) under its ``limits`` (:func:`stored_limits`).

    Raises:
        InputFileError: an unknown ``motion``, or one whose table or settings are missing.
    """
    name = attributes.get("motion", SineTable.name)
    load = MOTIONS.get(name)
    if load is None:
        raise InputFileError(
            parameter="motion", value=name, allowed=", ".join(MOTIONS), element="run"
        )
    motion = load(tables, attributes)
    if drive and attributes.get("drive") in CLOSED_LOOP_DRIVES:
        from aaria_pin.core.run.closed_loop import closed_loop_from_record

        return closed_loop_from_record(motion, tables, attributes)
    if drive and "torque_table" in tables:
        return TorqueDrive(
            tables["torque_table"],
            motion,
            limits=stored_limits(attributes),
            dynamics=recorded_dynamics(attributes),
        )
    return motion


def recorded_dynamics(attributes: dict[str, Any]) -> str:
    """The torque drive's integrator a record names (``TorqueDrive.dynamics``).

    A run written before the compiled kernel has no ``dynamics``: it was made by the Pinocchio
    path (``"reference"``), which re-makes it bit for bit.

    Raises:
        InputFileError: a name :data:`~aaria_pin.core.forward.DYNAMICS` does not hold.
    """
    from aaria_pin.core.forward import DYNAMICS

    name = str(attributes.get("dynamics", "reference"))
    if name not in DYNAMICS:
        raise InputFileError(
            parameter="dynamics", value=name, allowed=", ".join(DYNAMICS), element="run"
        )
    return name


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
