"""The motor torque split of a run with actuators: rigid body, armature, friction, limit."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.apps.torques import MotorTorques, motor_torques, record_torque_report, torque_text
from aaria_pin.core.actuator import ActuatorModel, actuator_torques
from aaria_pin.core.joint_sensors import model_attributes
from aaria_pin.core.record import RunRecord

LIMITS = (0.0, 0.0, 1.0, 0.0, 0.0, 0.0)
"""Module 3's motor (prismatic) limited to 1 N (it needs more); the others: the URDF's effort."""


def with_actuator(record: RunRecord, model: ActuatorModel) -> RunRecord:
    """The run with the actuator's tables and attribute, as the engine records them."""
    torques = actuator_torques(model, record.qd, record.qdd)
    tables = {"tau_armature": torques.armature, "tau_friction": torques.friction}
    tables["tau_motor"] = record.tau + torques.armature + torques.friction
    attributes = {**record.attributes, "actuator": model_attributes(model)}
    return replace(record, tables={**record.tables, **tables}, attributes=attributes)


@pytest.fixture(scope="module")
def fig3_run() -> RunRecord:
    preset = get_preset("aaria-fig3")  # module 2 empty: a zero column, no joint
    record = simulate_run(
        preset.table, preset.joint_table, preset.base_table, duration=0.5, rate=50, noise=False
    )
    model = ActuatorModel(
        rotor_inertia=1e-4, gear_ratio=100.0, viscous=0.5, coulomb=2.0, torque_limit=LIMITS
    )
    return with_actuator(record, model)


def test_each_joint_gets_the_peak_and_rms_of_each_part(fig3_run: RunRecord) -> None:
    split = motor_torques(fig3_run)
    assert split is not None and [m.joint for m in split] == ["joint1", *fig3_run.joint_names[2:]]
    columns = [0, 2, 3, 4, 5]
    tables = {
        "rigid": fig3_run.tau,
        "armature": fig3_run.tables["tau_armature"],
        "friction": fig3_run.tables["tau_friction"],
        "motor": fig3_run.tables["tau_motor"],
    }
    for k, motor in zip(columns, split, strict=True):
        for part, table in tables.items():
            assert motor.peak[part] == np.abs(table[:, k]).max()
            assert motor.rms[part] == pytest.approx(np.sqrt(np.mean(table[:, k] ** 2)), rel=1e-14)
    assert split[0].peak["friction"] > 2.0 and split[0].peak["armature"] > 0.0
    # the limit: the motor's for module 3, the URDF's effort (1e4) elsewhere
    assert [m.limit for m in split] == [1e4, 1.0, 1e4, 1e4, 1e4]
    assert [m.exceeded for m in split] == [False, True, False, False, False]


def test_the_report_carries_the_split_and_its_text_shows_it(fig3_run: RunRecord) -> None:
    report = record_torque_report(fig3_run)
    split = motor_torques(fig3_run)
    assert split is not None
    assert [j["motor"]["limit"] for j in report["joints"]] == [m.limit for m in split]
    assert MotorTorques(**report["joints"][1]["motor"]) == split[1]
    text = torque_text(report).splitlines()
    tables = {k: v for k, v in fig3_run.tables.items() if not k.startswith("tau_")}
    plain = torque_text(record_torque_report(replace(fig3_run, tables=tables))).splitlines()
    assert text[: len(plain)] == plain  # the split only adds its table below
    assert text[len(plain)] == "motor torque = rigid (tau) + armature + friction:"
    heads = text[len(plain) + 1].split()
    assert heads[:4] == ["module", "joint", "peak", "rigid"] and heads[-1] == "limit"
    rows = text[len(plain) + 2 :]
    assert len(rows) == 5 and rows[1].split()[:2] == ["3", "joint3"]
    assert rows[1].endswith(" 1 N  EXCEEDED") and "EXCEEDED" not in rows[0]
    values = [float(x) for x in rows[0].split()[2:10]]
    expected = [split[0].peak["rigid"], split[0].rms["rigid"], split[0].peak["armature"]]
    np.testing.assert_allclose(values[:3], expected, rtol=1e-3)


def test_a_run_without_the_tables_has_no_split(fig3_run: RunRecord) -> None:
    old = replace(fig3_run, tables={k: v for k, v in fig3_run.tables.items() if k != "tau_motor"})
    assert motor_torques(old) is None
    assert all("motor" not in joint for joint in record_torque_report(old)["joints"])
    # no actuator attribute: no motor limit, the URDF's effort limits
    bare = replace(fig3_run, attributes={**fig3_run.attributes, "actuator": None})
    split = motor_torques(bare)
    assert split is not None and [m.limit for m in split] == [1e4] * 5
