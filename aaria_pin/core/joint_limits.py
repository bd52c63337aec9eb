"""What a torque-driven run does when its joints leave the model's limits: the ``limits`` policies.

A run driven by torques (:class:`~aaria_pin.core.run.TorqueDrive`) integrates the whole run,
then hands its trajectory to its policy, named by the run's ``limits`` attribute:

- ``stop`` (the default of a new run): the first sample where a joint's position is beyond its
  model limit (by more than :data:`~aaria_pin.core.oscillation.RANGE_TOLERANCE`, as the check
  of a prescribed motion), its speed beyond the model's ``velocityLimit``, or either is not a
  number ends the run with a :class:`~aaria_pin.errors.JointLimitError` naming the joint, the
  time, the value and the limit; nothing is written.
- ``ignore``: the trajectory as integrated (what every torque run did before the policy was
  recorded; a record without the attribute reads as ``ignore``, so it is re-made bit for bit).
- ``clamp``: stiff-damped stops. Holding a joint at its limit is a force in the dynamics, not a
  clip of the integrated values: the policy hands its position bounds to the forward dynamics
  (:meth:`LimitPolicy.forward_options`, the option ``stops`` of
  :func:`~aaria_pin.core.forward.forward_simulate`), which adds at every integrator stage a
  critically damped one-sided spring-damper beyond each limit
  (:func:`~aaria_pin.core.forward.stop_torques`); the trajectory is then kept as integrated.
  A joint pressed on its stop sinks slightly past it (the stop is stiff, not rigid).

Torque limits are the actuator's: with one, the motor torques are saturated at its limits inside
the forward dynamics (:func:`~aaria_pin.core.forward.forward_simulate`); without, a URDF robot's
run records the joints whose torques exceed the model's ``effortLimit`` (``effort_exceeded``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol

import numpy as np

from aaria_pin.core.model import RobotModel
from aaria_pin.core.oscillation import RANGE_TOLERANCE
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import JointTrajectory
from aaria_pin.errors import InputFileError, JointLimitError, ParameterError

__all__ = [
    "DEFAULT_LIMITS",
    "LIMIT_POLICIES",
    "STORED_LIMITS",
    "JointBounds",
    "LimitPolicy",
    "limit_policy",
    "model_velocity_limits",
    "stored_limits",
]

DEFAULT_LIMITS = "stop"
"""The policy of a new torque-driven run."""

STORED_LIMITS = "ignore"
"""The policy of a record written before the policy was recorded (its limits were never checked)."""


@dataclass(frozen=True)
class JointBounds:
    """The limits a torque-driven run is held to, one entry per model joint (model order).

    Attributes:
        names: the joints' names, as the record's columns name them
        lower: lower position limits [rad or m] (-inf: none)
        upper: upper position limits [rad or m] (inf: none)
        speed: largest |velocity| [rad/s or m/s] (inf: none)
    """

    names: Sequence[str]
    lower: Array
    upper: Array
    speed: Array


class LimitPolicy(Protocol):
    """What a torque-driven run does with a trajectory that leaves its bounds.

    Attributes:
        name: the run's ``limits`` attribute
    """

    name: ClassVar[str]

    def applied(self, trajectory: JointTrajectory, bounds: JointBounds) -> JointTrajectory:
        """The run's trajectory under the policy.

        Raises:
            JointLimitError: the policy ends the run.
        """
        ...

    def forward_options(self, bounds: JointBounds) -> dict[str, Any]:
        """What the policy adds to the forward dynamics' options (``ForwardOptions``)."""
        ...


class IgnoreLimits:
    """``ignore``: the trajectory as integrated, wherever it goes."""

    name: ClassVar[str] = "ignore"

    def applied(self, trajectory: JointTrajectory, bounds: JointBounds) -> JointTrajectory:
        """The trajectory itself."""
        return trajectory

    def forward_options(self, bounds: JointBounds) -> dict[str, Any]:
        """Nothing: the dynamics has no stops."""
        return {}


class StopAtLimits:
    """``stop``: the run ends at the first sample beyond a position or velocity limit."""

    name: ClassVar[str] = "stop"

    def forward_options(self, bounds: JointBounds) -> dict[str, Any]:
        """Nothing: the dynamics has no stops (the trajectory is checked after)."""
        return {}

    def applied(self, trajectory: JointTrajectory, bounds: JointBounds) -> JointTrajectory:
        """The trajectory, if every sample is within the bounds.

        Raises:
            JointLimitError: the first sample (then the first joint) whose value is beyond its
                position limits, whose speed is beyond its velocity limit, or that is not a
                number (parameter ``limits``).
        """
        q, qd = trajectory.q, trajectory.qd
        low, high = bounds.lower - RANGE_TOLERANCE, bounds.upper + RANGE_TOLERANCE
        position = ~((q >= low) & (q <= high))  # NaN is outside
        speed = ~(np.abs(qd) <= bounds.speed + RANGE_TOLERANCE)
        if not (position.any() or speed.any()):
            return trajectory
        rows = np.flatnonzero((position | speed).any(axis=1))
        row = int(rows[0])
        time = float(trajectory.time[row])
        joint = int(np.flatnonzero(position[row] | speed[row])[0])
        name = bounds.names[joint]
        if position[row, joint]:
            what, value = "position", float(q[row, joint])
            allowed = f"{bounds.lower[joint]:.6g} to {bounds.upper[joint]:.6g}"
        else:
            what, value = "velocity", float(qd[row, joint])
            allowed = f"|velocity| <= {bounds.speed[joint]:.6g}"
        raise JointLimitError(
            f"{name} {what} at t = {time:.6g} s is {value:.6g}; allowed: {allowed} (the "
            "model's limits; the run stops there: limits stop)",
            parameter="limits",
            value=value,
            element=f"{name} at t = {time:.6g} s",
        )


class ClampAtLimits:
    """``clamp``: stiff-damped stops in the dynamics at the position limits."""

    name: ClassVar[str] = "clamp"

    def applied(self, trajectory: JointTrajectory, bounds: JointBounds) -> JointTrajectory:
        """The trajectory itself: the stops acted in the dynamics."""
        return trajectory

    def forward_options(self, bounds: JointBounds) -> dict[str, Any]:
        """The position bounds, as the forward dynamics' ``stops``."""
        return {"stops": (np.asarray(bounds.lower, float), np.asarray(bounds.upper, float))}


_POLICIES: dict[str, LimitPolicy] = {
    p.name: p for p in (StopAtLimits(), ClampAtLimits(), IgnoreLimits())
}

LIMIT_POLICIES = ("stop", "clamp", "ignore")
"""The policies' names, as ``--limits`` offers them."""


def limit_policy(name: Any) -> LimitPolicy:
    """The policy named ``name``.

    Raises:
        ParameterError: an unknown name (parameter ``limits``).
    """
    policy = _POLICIES.get(name) if isinstance(name, str) else None
    if policy is not None:
        return policy
    raise ParameterError(parameter="limits", value=name, allowed=", ".join(LIMIT_POLICIES))


def stored_limits(attributes: dict[str, Any]) -> str:
    """The policy a torque-driven run's record names (:data:`STORED_LIMITS` if none).

    Raises:
        InputFileError: a ``limits`` attribute that names no policy (parameter ``limits``).
    """
    name = attributes.get("limits", STORED_LIMITS)
    if name not in _POLICIES:
        raise InputFileError(
            parameter="limits", value=name, allowed=", ".join(_POLICIES), element="run"
        )
    return str(name)


def model_velocity_limits(robot_model: RobotModel) -> Array:
    """The Pinocchio model's ``velocityLimit`` of each model joint [rad/s or m/s].

    Args:
        robot_model: the model (its base's entries left out)

    Returns:
        The limits, model order; inf where the model gives none (0, or huge).
    """
    speed = np.asarray(robot_model.model.velocityLimit, dtype=float)[robot_model.base_nv :]
    return np.where((speed > 0) & (speed < 1e300), speed, np.inf)
