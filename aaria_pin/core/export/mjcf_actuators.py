"""A run's actuators in MJCF: each joint's armature, damping, friction loss and force range.

MuJoCo's joint attributes for an :class:`~aaria_pin.core.joint_sensors.ActuatorModel`
(:mod:`aaria_pin.core.actuator`):

- ``armature``: the reflected rotor inertia ``rotor_inertia·gear_ratio²`` [kg·m² or kg]; MuJoCo
  adds it to the joint's diagonal of the mass matrix (``dof_armature``);
- ``damping``: the viscous coefficient ``viscous`` [N·m·s/rad or N·s/m]; MuJoCo's passive force
  ``-damping·qd`` (``dof_damping``);
- ``frictionloss``: the Coulomb torque ``coulomb`` [N·m or N]; MuJoCo's dry friction, a
  constraint whose force reaches ``±frictionloss`` against the motion once it saturates
  (``dof_frictionloss``);
- ``actuatorfrcrange`` with ``actuatorfrclimited``: ``±`` the torque limit
  (:func:`~aaria_pin.core.actuator.torque_limits`, 0: the URDF's ``effort``; none where that
  is not given), the range of the forces MuJoCo's actuators may put on the joint.

Not MuJoCo terms, so not exported (the MJCF says so in a comment with their values): the
``tanh(qd/coulomb_velocity)`` smoothing of the Coulomb term (MuJoCo's friction loss is dry
friction solved as a soft constraint) and the Stribeck term (``stribeck_torque``,
``stribeck_velocity``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from aaria_pin.core.actuator import ActuatorModel, armature, torque_limits
from aaria_pin.core.joint_sensors import model_attributes, per_joint
from aaria_pin.core.urdf_emitter import exact_number
from aaria_pin.core.urdf_tree import UrdfDocument

__all__ = ["NOT_EXPORTED", "actuator_comment", "joint_actuator_attributes"]

NOT_EXPORTED = ("coulomb_velocity", "stribeck_torque", "stribeck_velocity")
"""Fields of an :class:`~aaria_pin.core.joint_sensors.ActuatorModel` MuJoCo has no term for."""


def joint_actuator_attributes(
    model: ActuatorModel, joint_names: Sequence[str], document: UrdfDocument
) -> dict[str, str]:
    """The MJCF attributes of each actuated joint, by joint name.

    Args:
        model: the actuators, per-joint values in the order of ``joint_names``
        joint_names: the joints the model's values belong to (a run's record columns); names
            that are not joints of the URDF (an empty module's column) are left out
        document: the parsed URDF (its joints' ``effort`` is the limit where the model's is 0)

    Returns:
        Joint name → ``' armature="…" damping="…" frictionloss="…"'`` and, where the joint has a
        finite limit, ``' actuatorfrclimited="true" actuatorfrcrange="-l l"'``.

    Raises:
        ParameterError: a per-joint value with another count than ``joint_names``.
    """
    n = len(joint_names)
    joints = {joint.name: joint for joint in document.joints}
    effort = [joints[name].effort if name in joints else np.inf for name in joint_names]
    terms = {
        "armature": armature(model, n),
        "damping": per_joint(model.viscous, n, "viscous"),
        "frictionloss": per_joint(model.coulomb, n, "coulomb"),
    }
    limits = torque_limits(model, effort)
    out = {}
    for j, name in enumerate(joint_names):
        if name not in joints:
            continue
        text = "".join(f' {key}="{exact_number(value[j])}"' for key, value in terms.items())
        if np.isfinite(limits[j]):
            text += (
                ' actuatorfrclimited="true" actuatorfrcrange='
                f'"{exact_number(-limits[j])} {exact_number(limits[j])}"'
            )
        out[name] = text
    return out


def _values(value: object) -> str:
    return " ".join(exact_number(v) for v in np.atleast_1d(np.asarray(value, dtype=float)))


def actuator_comment(model: ActuatorModel) -> str:
    """An MJCF comment naming the actuator's terms MuJoCo has no name for, with their values.

    Args:
        model: the actuators

    Returns:
        One line ``<!-- … -->`` (no newline), ASCII.
    """
    stored: Mapping[str, object] = model_attributes(model)
    values = ", ".join(f"{key} = {_values(stored[key])}" for key in NOT_EXPORTED)
    text = (
        "actuators: armature = rotor_inertia*gear_ratio^2, damping = viscous, frictionloss ="
        " coulomb, actuatorfrcrange = +-torque_limit; not MuJoCo terms, not exported: the"
        " smoothing tanh(qd/coulomb_velocity) of the Coulomb friction (frictionloss is dry"
        " friction solved as a constraint) and the Stribeck term"
        f" ({values})"
    )
    return f"<!-- {text} -->"
