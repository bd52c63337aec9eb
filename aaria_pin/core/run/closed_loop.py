"""The closed-loop drives as a run's motion: a controller tracks the run's motion as its reference.

A :class:`ClosedLoopDrive` wraps a motion (sine table, Fourier, sampled trajectory): that motion
is the reference, and the joints move as the controller (:mod:`aaria_pin.core.control`) drives
them through the dynamics, with the run's hardware in the loop (its actuators in the plant, its
encoders and torque sensors as the controller's inputs, the same sensors the record's channels
read: :func:`~aaria_pin.core.run.measured.sensor_streams`). The record keeps the reference's
own tables and attributes, ``drive`` (the law: ``pd`` or ``computed-torque``), ``limits`` and
``integrator``, the model ``controller`` (``RunSettings.controller``), and the tables the drive
made (:data:`~aaria_pin.core.run.measured.JOINT_TABLES` ``controller``): ``q_reference``,
``qd_reference``, ``tau_command`` (T × n) and the gains ``controller_kp``, ``controller_kd``
(1 × n). The noise the controller's sensors read at its ticks comes from the run's
``controller`` sensor stream (:func:`~aaria_pin.core.seeds.sensor_sequence`), one child per
sensor, so a run re-made from its record reads the same.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any, ClassVar

import numpy as np

from aaria_pin.core.arguments import checked
from aaria_pin.core.control import (
    LAWS,
    LOST_SPEED,
    LOST_TRACKING,
    ClosedLoopRun,
    ControllerSensing,
    closed_loop_simulate,
)
from aaria_pin.core.forward import Progress, check_integrator
from aaria_pin.core.joint_limits import DEFAULT_LIMITS, limit_policy
from aaria_pin.core.joint_sensors import ControllerModel, JointHardware, per_joint, select_joints
from aaria_pin.core.run.measured import sensor_streams
from aaria_pin.core.run.motion import Motion, SineTable
from aaria_pin.core.run.robot import RunRobot, joint_bounds
from aaria_pin.core.se3 import Array
from aaria_pin.core.seeds import sensor_sequence
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory
from aaria_pin.errors import ParameterError, TrackingError

__all__ = ["ClosedLoopDrive"]


@checked
@dataclass(frozen=True)
class ClosedLoopDrive:
    """The joints track ``reference`` under a controller, by forward dynamics, from its start.

    Attributes:
        reference: the motion to track (its values and velocities at t = 0 start the run)
        law: the controller's law, one of :data:`~aaria_pin.core.control.LAWS`
        limits: the joint-limit policy of the motion that results (``stop``, ``clamp``,
            ``ignore``: :mod:`~aaria_pin.core.joint_limits`)
        integrator: ``rk4`` or ``euler``, at the control period
        hardware: the run's joint models (set by the engine: :meth:`with_hardware`; None: the
            default controller, no sensors, no actuator)
        seed: the run's noise seed (set with ``hardware``)
        progress: told ``(samples done, samples)`` as the run goes (None: silent)
    """

    reference: Motion = field(default_factory=SineTable)
    law: str = "pd"
    limits: str = DEFAULT_LIMITS
    integrator: str = "rk4"
    hardware: JointHardware | None = field(default=None, compare=False)
    seed: int | np.random.SeedSequence | None = field(default=None, compare=False)
    progress: Progress | None = field(default=None, compare=False)
    whole: ClassVar[bool] = True

    @property
    def name(self) -> str:
        """The ``motion`` attribute: the reference's."""
        return self.reference.name

    @property
    def drive(self) -> str:
        """The ``drive`` attribute: the law."""
        return self.law

    def checked(self, robot: RunRobot, samples: int, rate: float) -> ClosedLoopDrive:
        """The reference, the law, the policy and the integrator checked.

        Raises:
            ParameterError: an unknown law (parameter ``drive``), policy or integrator.
        """
        if self.law not in LAWS:
            raise ParameterError(parameter="drive", value=self.law, allowed=", ".join(LAWS))
        check_integrator(self.integrator)
        limit_policy(self.limits)
        return replace(self, reference=self.reference.checked(robot, samples, rate))

    def with_hardware(
        self, hardware: JointHardware, seed: int | np.random.SeedSequence
    ) -> ClosedLoopDrive:
        """The drive with the run's joint models and noise seed."""
        return replace(self, hardware=hardware, seed=seed)

    def trajectory(
        self, robot: RunRobot, span: tuple[int, int], times: Array, base: BaseMotion
    ) -> JointTrajectory:
        """The closed-loop motion (the whole run: one piece), under its policy, with its tables.

        Raises:
            TrackingError: a joint lost its reference (naming it, the time and the gains).
            JointLimitError: the policy ``stop`` and a sample beyond the model's limits.
        """
        reference = self.reference.trajectory(robot, span, times, base)
        hardware = self.hardware
        controller = _controller(hardware)
        n_columns = len(robot.joint_names)
        actuator = None if hardware is None else hardware.actuator
        if actuator is not None:
            actuator = select_joints(actuator, n_columns, robot.columns)
        model_controller = select_joints(controller, n_columns, robot.columns)
        policy, bounds = limit_policy(self.limits), joint_bounds(robot)
        run = closed_loop_simulate(
            robot.model,
            base,
            reference,
            self.law,
            model_controller,
            actuator=actuator,
            integrator=self.integrator,
            sensing=_sensing(robot, hardware, self.seed),
            progress=self.progress,
            **policy.forward_options(bounds),
        )
        if run.lost >= 0:
            raise _lost(robot, run, reference, self.law, model_controller)
        moved = policy.applied(run.trajectory, bounds)
        tables = {
            "q_reference": reference.q,
            "qd_reference": reference.qd,
            "tau_command": run.command,
            "controller_kp": run.kp[None, :],
            "controller_kd": run.kd[None, :],
        }
        return replace(moved, tables=tables)

    def record(self, robot: RunRobot) -> tuple[dict[str, Array], dict[str, Any]]:
        """The reference's tables and attributes, and ``limits``, ``integrator``."""
        tables, attributes = self.reference.record(robot)
        return tables, {**attributes, "limits": self.limits, "integrator": self.integrator}


def _controller(hardware: JointHardware | None) -> ControllerModel:
    """The run's controller (the default one when the run's settings have none)."""
    model = None if hardware is None else hardware.controller
    return ControllerModel() if model is None else model


def _sensing(
    robot: RunRobot, hardware: JointHardware | None, seed: int | np.random.SeedSequence | None
) -> ControllerSensing | None:
    """What the controller reads with: the run's own encoders and torque sensors, model order."""
    if hardware is None or seed is None:
        return None
    encoder, torque = sensor_streams(robot, hardware, seed)
    if encoder is None and torque is None:
        return None
    columns = list(range(len(robot.joint_names))) if robot.columns is None else robot.columns
    n = len(columns)
    zeros = np.zeros(n)
    children = sensor_sequence(seed, "controller").spawn(2)
    return ControllerSensing(
        encoder_step=None if encoder is None else encoder.step[columns],
        encoder_offset=zeros if encoder is None else encoder.offset[columns],
        encoder_noise=zeros if encoder is None else encoder.sigma[columns],
        torque_scale=None if torque is None else torque.scale[columns],
        torque_bias=zeros if torque is None else torque.bias[columns],
        torque_resolution=zeros if torque is None else torque.resolution[columns],
        torque_noise=zeros if torque is None else torque.sigma[columns],
        encoder_generator=np.random.default_rng(children[0]),
        torque_generator=np.random.default_rng(children[1]),
    )


def _lost(
    robot: RunRobot,
    run: ClosedLoopRun,
    reference: JointTrajectory,
    law: str,
    controller: ControllerModel,
) -> TrackingError:
    """One line: the joint, the time, how far (in position or speed), the gains."""
    at = run.lost
    moved = run.trajectory
    errors = (
        np.abs(moved.q[at] - reference.q[at]) / LOST_TRACKING,
        np.abs(moved.qd[at] - reference.qd[at]) / LOST_SPEED,
    )
    ratios = np.where(np.isfinite(errors), errors, np.inf)
    what, joint = np.unravel_index(int(np.argmax(ratios)), ratios.shape)
    columns = list(range(moved.q.shape[1])) if robot.columns is None else robot.columns
    name = robot.joint_names[columns[joint]]
    error = float(ratios[what, joint]) * (LOST_TRACKING, LOST_SPEED)[what]
    far = f"{error:.3g} " + ("from it", "faster or slower than it")[what]
    if not np.isfinite(error):
        far = "not a number (it diverged)"
    bound = (f"{LOST_TRACKING:g} rad or m", f"{LOST_SPEED:g} rad/s or m/s")[what]
    frequency = per_joint(controller.frequency, moved.q.shape[1], "frequency")[joint]
    return TrackingError(
        f"drive {law} lost its reference: joint {name} at t = {reference.time[at]:.4g} s is "
        f"{far} (kp {run.kp[joint]:.4g}, kd {run.kd[joint]:.4g}, frequency "
        f"{frequency:.4g} Hz, rate {controller.rate:.4g} Hz); allowed: within {bound} (stable "
        "gains, a reference the motors can follow)",
        parameter="controller",
        value=error,
        element=name,
    )
