"""``aaria torques`` on a run with actuators prints the motor split; an old run, today's text."""

from __future__ import annotations

import json
import shutil
from dataclasses import replace
from pathlib import Path

import numpy as np
from click.testing import CliRunner

from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.cli import main
from aaria_pin.core.actuator import ActuatorModel, actuator_torques
from aaria_pin.core.joint_sensors import model_attributes
from aaria_pin.files.runfile import read_run, write_run

FIXTURES = Path(__file__).resolve().parents[1] / "fixtures" / "v0_3_0"


def torques(*args: str) -> str:
    result = CliRunner().invoke(main, ["torques", *args])
    assert result.exit_code == 0, result.output
    return result.stdout


def test_a_run_with_actuators_shows_the_split(tmp_path: Path) -> None:
    preset = get_preset("aaria-fig2")
    record = simulate_run(preset.table, duration=0.2, rate=100, noise=False)
    model = ActuatorModel(rotor_inertia=2e-4, gear_ratio=100.0, coulomb=3.0, torque_limit=150.0)
    parts = actuator_torques(model, record.qd, record.qdd)
    tables = {"tau_armature": parts.armature, "tau_friction": parts.friction}
    tables["tau_motor"] = record.tau + parts.armature + parts.friction
    actuated = replace(
        record,
        tables={**record.tables, **tables},
        attributes={**record.attributes, "actuator": model_attributes(model)},
    )
    write_run(tmp_path / "plain.h5", record)
    write_run(tmp_path / "motor.h5", actuated)
    plain = torques(str(tmp_path / "plain.h5")).splitlines()
    lines = torques(str(tmp_path / "motor.h5")).splitlines()
    assert lines[: len(plain)] == plain
    assert lines[len(plain)] == "motor torque = rigid (tau) + armature + friction:"
    rows = [line.split() for line in lines[len(plain) + 2 :]]
    assert [row[1] for row in rows] == list(record.joint_names)
    motor_peaks = np.abs(tables["tau_motor"]).max(axis=0)
    np.testing.assert_allclose([float(row[8]) for row in rows], motor_peaks, rtol=1e-3)
    exceeded = [row[-1] == "EXCEEDED" for row in rows]
    assert exceeded == (motor_peaks > 150.0).tolist() and any(exceeded) and not all(exceeded)
    report = json.loads(torques(str(tmp_path / "motor.h5"), "--json"))
    assert [j["motor"]["exceeded"] for j in report["joints"]] == exceeded
    assert "motor" not in json.loads(torques(str(tmp_path / "plain.h5"), "--json"))["joints"][0]


def test_an_old_run_prints_todays_text(tmp_path: Path) -> None:
    old = tmp_path / "dh_run.h5"
    shutil.copy(FIXTURES / "dh_run.h5", old)
    lines = torques(str(old)).splitlines()
    record = read_run(old)
    assert len(lines) == 1 + len(record.joint_names) + 1  # heads, a row per joint, base wrench
    assert lines[-1].startswith("base wrench peaks: ") and not any("motor" in x for x in lines)
