"""The joint models refuse bad values in one line naming the field; per-joint values, the joint
subset of a model and the prismatic joints of a robot's model."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import aaria_pin as ap
from aaria_pin.core.joint_sensors import (
    ActuatorModel,
    EncoderModel,
    TorqueSensorModel,
    model_attributes,
    model_from_attributes,
    prismatic_joints,
    select_joints,
)
from aaria_pin.errors import ParameterError

BAD = [
    (EncoderModel, "noise", -1e-3, ">= 0"),
    (EncoderModel, "offset", [0.1, float("nan")], "finite"),
    (EncoderModel, "counts_per_revolution", -4096, ">= 0"),
    (EncoderModel, "counts_per_metre", "many", "finite numbers"),
    (TorqueSensorModel, "bias", -0.1, ">= 0"),
    (TorqueSensorModel, "resolution", float("inf"), "finite"),
    (TorqueSensorModel, "scale_error", 1.0, "< 1"),
    (TorqueSensorModel, "noise", [[0.1]], "one per joint"),
    (ActuatorModel, "gear_ratio", 0.0, "> 0"),
    (ActuatorModel, "coulomb_velocity", 0.0, "> 0"),
    (ActuatorModel, "stribeck_velocity", -0.1, "> 0"),
    (ActuatorModel, "rotor_inertia", -1e-5, ">= 0"),
    (ActuatorModel, "viscous", [], "one per joint"),
    (ActuatorModel, "coulomb", -1.0, ">= 0"),
    (ActuatorModel, "torque_limit", -5.0, ">= 0"),
]


@pytest.mark.parametrize(("cls", "name", "value", "allowed"), BAD)
def test_a_bad_value_is_one_line_naming_its_field(
    cls: Any, name: str, value: Any, allowed: str
) -> None:
    with pytest.raises(ParameterError) as caught:
        cls(**{name: value})
    message = str(caught.value)
    assert caught.value.parameter == name
    assert message.startswith(f"{name} is ") and "; allowed: " in message
    assert allowed in message.split("; allowed: ")[1]
    assert "\n" not in message


def test_good_values_pass_and_sequences_become_tuples() -> None:
    model = ActuatorModel(rotor_inertia=[1e-4, 2e-4], gear_ratio=np.array([100.0, 50.0]))
    assert model.rotor_inertia == (1e-4, 2e-4) and model.gear_ratio == (100.0, 50.0)
    assert hash(model)  # still a frozen, hashable value
    assert TorqueSensorModel(scale_error=0.999).scale_error == 0.999
    stored = model_attributes(model)
    assert stored["gear_ratio"] == [100.0, 50.0]
    assert model_from_attributes(ActuatorModel, stored) == model


def test_select_joints_takes_the_columns_of_the_models_joints() -> None:
    model = EncoderModel(counts_per_revolution=[1.0, 2.0, 3.0, 4.0], noise=0.5)
    picked = select_joints(model, 4, [0, 2, 3])
    assert picked.counts_per_revolution == (1.0, 3.0, 4.0)
    assert picked.noise == (0.5, 0.5, 0.5)
    assert select_joints(model, 4, None) is model


def test_prismatic_joints_are_the_aaria_modules_of_link_type_2() -> None:
    robot = ap.preset_arm("aaria-fig2")
    link_type = robot.tables["senSenDH"][:6, 4]  # Table 3: 1 revolute, 2 prismatic
    np.testing.assert_array_equal(prismatic_joints(robot.model), link_type == 2)
