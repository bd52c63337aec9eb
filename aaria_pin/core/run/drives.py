"""How a run's joints are driven: followed, moved by torques, or tracked by a controller.

- :class:`TorqueDrive`: the joints move under given torques by forward dynamics
  (:func:`~aaria_pin.core.forward.forward_simulate`);
- :class:`~aaria_pin.core.run.closed_loop.ClosedLoopDrive`: a joint controller tracks the motion;
- :func:`driven`: a request's drive options (:class:`DriveOptions`) around a motion;
  :func:`stored_drive` and :func:`motion_from_record`: the drive a record stores;
  :func:`equipped`: the drive with the run's hardware (the engine's step).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any, ClassVar, TypedDict

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.core.arguments import checked
from aaria_pin.core.forward import DEFAULT_SUBSTEPS, Progress, check_integrator
from aaria_pin.core.joint_limits import (
    DEFAULT_LIMITS,
    limit_policy,
    stored_limits,
)
from aaria_pin.core.joint_sensors import (
    CLOSED_LOOP_DRIVES,
    ActuatorModel,
    JointHardware,
    select_joints,
)
from aaria_pin.core.run.closed_loop import ClosedLoopDrive
from aaria_pin.core.run.motion import MOTIONS, Motion, SineTable
from aaria_pin.core.run.robot import RunRobot, joint_bounds
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory
from aaria_pin.errors import InputFileError, ParameterError

__all__ = [
    "DriveOptions",
    "TorqueDrive",
    "driven",
    "equipped",
    "motion_from_record",
    "recorded_dynamics",
    "remade_drive",
    "stored_drive",
]


@checked
@dataclass(frozen=True)
class TorqueDrive:
    """The joints move under given torques by forward dynamics, from ``start``'s state at t = 0.

    Stored as ``start``'s tables and attributes, the table ``torque_table`` and ``drive``
    ``torque``; computed in one piece. With an actuator (the run's ``RunSettings.actuator``,
    set by the engine: :func:`equipped`) the torques are motor torques: the forward dynamics
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
        integrator: ``rk4`` or ``euler`` (semi-implicit; the compiled kernel's only)
        substeps: integration steps per sample
    """

    torques: ArrayLike
    start: Motion = field(default_factory=SineTable)
    actuator: ActuatorModel | None = None
    limits: str = DEFAULT_LIMITS
    dynamics: str = "aba"
    progress: Progress | None = field(default=None, compare=False)
    integrator: str = "rk4"
    substeps: int = DEFAULT_SUBSTEPS
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
        """The starting motion, the torque table (``check_torques``), the policy, the integrator.

        Raises:
            ParameterError: a bad table, ``limits`` that names no policy built, an unknown
                integrator or substeps < 1.
        """
        from aaria_pin.core.torque_table import check_torques

        limit_policy(self.limits)
        check_integrator(self.integrator)
        if isinstance(self.substeps, bool) or not isinstance(self.substeps, int | np.integer):
            raise ParameterError(
                parameter="substeps", value=self.substeps, allowed="an integer >= 1"
            )
        if self.substeps < 1:
            raise ParameterError(parameter="substeps", value=self.substeps, allowed=">= 1")
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
            integrator=self.integrator,
            substeps=int(self.substeps),
            **policy.forward_options(bounds),
        )
        return policy.applied(moved, bounds)

    def record(self, robot: RunRobot) -> tuple[dict[str, Array], dict[str, Any]]:
        """The starting motion's, ``torque_table`` and the attributes ``limits``, ``dynamics``.

        And ``integrator``, ``substeps`` when they are not the defaults (a record without them
        was integrated by RK4 with :data:`~aaria_pin.core.forward.DEFAULT_SUBSTEPS`).
        """
        tables, attributes = self.start.record(robot)
        tau = np.asarray(self.torques, dtype=float)
        attributes = {**attributes, "limits": self.limits, "dynamics": self.dynamics}
        if self.integrator != "rk4" or self.substeps != DEFAULT_SUBSTEPS:
            attributes.update(integrator=self.integrator, substeps=int(self.substeps))
        return {**tables, "torque_table": tau}, attributes


class DriveOptions(TypedDict, total=False):
    """How a run's joints are driven: the request options :func:`driven` reads (all optional).

    Attributes:
        torques: (T, n) torques by record column: the joints move under them (a torque drive)
        drive: ``motion``, ``torque`` (with ``torques``), or a closed-loop drive (``pd``,
            ``computed-torque``: the motion is the controller's reference)
        limits: the joint-limit policy of a torque or closed-loop drive (``stop``, ``clamp``,
            ``ignore``)
        dynamics: a torque drive's integrator by its recorded name (``aba``, ``kernel``,
            ``reference``)
        integrator: a driven run's integrator (``rk4``, ``euler``)
        substeps: a torque drive's integration steps per sample (a closed-loop drive's are its
            control rate's)
        progress: told ``(samples done, samples)`` as a driven run's integration goes
    """

    torques: ArrayLike | None
    drive: str
    limits: str
    dynamics: str
    integrator: str
    substeps: int
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
        if options.get("substeps") is not None:
            raise ParameterError(
                f"substeps is given for drive {drive!r}; allowed: substeps with drive torque "
                "(a controller steps at its control rate)",
                parameter="substeps",
                value=options.get("substeps"),
            )
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
    integration = {k: options[k] for k in ("integrator", "substeps") if options.get(k) is not None}
    return TorqueDrive(
        torques, motion, limits=limits, dynamics=dynamics, progress=progress, **integration
    )


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
            **_stored_integration({k: v for k, v in attributes.items() if k == "integrator"}),
        }
    if "torque_table" in tables:
        return {
            "torques": tables["torque_table"],
            "limits": stored_limits(dict(attributes)),
            "dynamics": recorded_dynamics(dict(attributes)),
            **_stored_integration(attributes),
        }
    return {}


def remade_drive(
    tables: Mapping[str, Array], attributes: Mapping[str, Any], overrides: Mapping[str, Any]
) -> dict[str, Any]:
    """The drive of a run re-made from its record: the stored one, or the one ``overrides`` name.

    ``--from`` a torque or closed-loop run with ``--drive motion`` (or another drive) makes the
    run of that drive, without the stored torques, policy or integrator (and, for a drive that
    is not closed-loop, without the stored controller).
    """
    stored = stored_drive(tables, attributes)
    drive = overrides.get("drive")
    stored_name = stored.get("drive", "torque" if "torques" in stored else "motion")
    if drive is None or drive == stored_name:
        return dict(stored)
    return {} if drive in CLOSED_LOOP_DRIVES else {"controller": None}


def _stored_integration(attributes: Mapping[str, Any]) -> DriveOptions:
    """A torque run's ``integrator`` and ``substeps`` (none recorded: the defaults).

    Raises:
        InputFileError: an integrator that is not one, or substeps that are not a count.
    """
    stored: DriveOptions = {}
    if "integrator" in attributes:
        try:
            stored["integrator"] = check_integrator(str(attributes["integrator"]))
        except ParameterError as exc:
            raise InputFileError(str(exc), parameter="integrator", element="run") from None
    if "substeps" in attributes:
        substeps = attributes["substeps"]
        if not (isinstance(substeps, int | np.integer) and substeps >= 1):
            raise InputFileError(
                parameter="substeps", value=substeps, allowed="an integer >= 1", element="run"
            )
        stored["substeps"] = int(substeps)
    return stored


def equipped(motion: Motion, hardware: JointHardware, seed: int | np.random.SeedSequence) -> Motion:
    """The motion with the run's joint models and noise seed (``Motion.with_hardware``).

    A torque drive takes the run's actuator (its torques are motor torques), a closed-loop
    drive its actuator, sensors and controller; a followed motion is itself. A motion made
    outside the package without the method is followed as given.
    """
    with_hardware = getattr(motion, "with_hardware", None)
    return motion if with_hardware is None else with_hardware(hardware, seed)


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
    return driven(motion, stored_drive(tables, attributes)) if drive else motion


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
