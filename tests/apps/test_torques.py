from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from aaria_pin.aaria.dh_robot import build_dh_robot
from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.aaria.sine_tables import base_motion, joint_trajectory
from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.apps.dataset.generate import generate_dataset
from aaria_pin.apps.torques import record_torque_report, torque_split, torque_text
from aaria_pin.cli import main
from aaria_pin.core.trajectory import sample_times
from aaria_pin.files.runfile import write_run


@pytest.mark.parametrize("name", ["aaria-fig2", "aaria-fig3"])
def test_split_adds_up_to_rnea_at_every_sample(name: str) -> None:
    preset = get_preset(name)
    record = simulate_run(
        preset.table, preset.joint_table, preset.base_table, duration=2.0, rate=50, noise=False
    )
    robot = build_dh_robot(preset.table)
    model = robot.model(moving_base=True)
    time = sample_times(2.0, 50)
    split = torque_split(
        model,
        base_motion(preset.base_table, time),
        joint_trajectory(preset.joint_table, robot.chain, time),
    )
    columns = [m - 1 for m in robot.chain.modules]
    np.testing.assert_allclose(sum(split.values()), record.tau[:, columns], atol=1e-9)
    assert all(np.abs(term).max() > 1e-3 for term in split.values())
    # each term against Pinocchio's own g(q), C(q, v)·v + g(q) and M(q) (CRBA), sample by sample
    import pinocchio as pin

    from aaria_pin.core.kinematics import full_state

    base = base_motion(preset.base_table, time)
    q, v, a = full_state(model, base, joint_trajectory(preset.joint_table, robot.chain, time))
    data = model.model.createData()
    for k in range(0, time.size, 9):
        gravity = pin.computeGeneralizedGravity(model.model, data, q[k])
        nonlinear = pin.nonLinearEffects(model.model, data, q[k], v[k])
        mass = pin.crba(model.model, data, q[k])
        mass = np.triu(mass) + np.triu(mass, 1).T  # crba fills the upper triangle
        np.testing.assert_allclose(split["gravity"][k], gravity[6:], atol=1e-9)
        np.testing.assert_allclose(split["coriolis"][k], (nonlinear - gravity)[6:], atol=1e-9)
        np.testing.assert_allclose(split["inertial"][k], (mass @ a[k])[6:], atol=1e-9)


def test_resting_arm_is_gravity_only() -> None:
    table = get_preset("aaria-fig2").table
    senJ = np.zeros((8, 5))
    senJ[:6, 2] = [0.02, 0.4, -0.3, 0.8, 0.01, 0.5]
    record = simulate_run(table, senJ, np.zeros((2, 4)), duration=0.5, rate=20, noise=False)
    report = record_torque_report(record)
    assert report["split_residual"] < 1e-9
    for joint in report["joints"]:
        assert joint["rms_terms"]["coriolis"] < 1e-12 and joint["rms_terms"]["inertial"] < 1e-12
        assert joint["shares"]["gravity"] == pytest.approx(1.0)
        assert joint["energy_abs_J"] == 0.0


def test_cli_on_a_run_file_and_a_dataset(tmp_path: Path) -> None:
    preset = get_preset("aaria-fig3")
    record = simulate_run(
        preset.table, preset.joint_table, preset.base_table, duration=1.0, rate=50, noise=False
    )
    write_run(tmp_path / "run.h5", record)
    result = CliRunner().invoke(main, ["torques", str(tmp_path / "run.h5"), "--json"])
    assert result.exit_code == 0, result.output
    report = json.loads(result.stdout)
    assert [j["module"] for j in report["joints"]] == [1, 3, 4, 5, 6]
    np.testing.assert_allclose(
        [j["peak_abs"] for j in report["joints"]],
        np.abs(record.tau[:, [0, 2, 3, 4, 5]]).max(axis=0),
    )
    generate_dataset(tmp_path / "ds.h5", DhDatasetSpec(n_runs=6, seed=2, duration=0.5), workers=1)
    result = CliRunner().invoke(main, ["torques", str(tmp_path / "ds.h5"), "--json"])
    summary = json.loads(result.stdout)
    assert (
        summary["largest"]
        and sum(
            stats["runs"] for kinds in summary["by_module"].values() for stats in kinds.values()
        )
        > 0
    )
    one = CliRunner().invoke(main, ["torques", str(tmp_path / "ds.h5"), "--run", "3"])
    assert one.exit_code == 0 and "base wrench peaks" in one.stdout
    bad = CliRunner().invoke(main, ["torques", str(tmp_path / "run.h5"), "--run", "1"])
    assert bad.exit_code == 2 and "--run is " in bad.stderr and "run file" in bad.stderr


def test_torque_text_of_a_run_and_of_a_data_set() -> None:
    joint = {"module": 2, "joint": "joint2", "type": "prismatic", "unit": "N", "peak_abs": 12.5}
    joint |= {"rms": 3.0, "energy_net_J": 1.5, "energy_abs_J": 2.0}
    joint["rms_terms"] = {"gravity": 2.0, "coriolis": 0.5, "inertial": 1.0}
    report = {"joints": [joint], "base_wrench_peak": {"fx": 4.0, "mz": 0.25}}
    lines = torque_text(report).splitlines()
    assert len(lines) == 3 and lines[0].split()[:3] == ["module", "joint", "type"]
    assert lines[1].split() == "2 joint2 prismatic 12.5 N 3 2 0.5 1 1.5 J 2 J".split()
    assert lines[2] == "base wrench peaks: fx 4 N, mz 0.25 N*m"
    summary = {"joints": {"3": "joint3"}, "by_module": {"3": {"revolute": {"runs": 4}}}}
    summary["by_module"]["3"]["revolute"] |= {"median": 1.0, "p95": 2.0, "max": 3.0}
    summary["largest"] = [{"run": 7, "module": 3, "type": "revolute", "peak_abs": 3.0}]
    text = torque_text(summary, one_run=False).splitlines()
    assert text[0].split() == (
        "module 3 (joint3) revolute runs 4 peak |tau| median 1 N*m p95 2 N*m max 3 N*m".split()
    )
    assert text[1] == "largest peaks: run 7 module 3 (revolute) 3 N*m"
