"""``aaria mjcf``: MuJoCo models from presets, robots and run files; a run replays in MuJoCo."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import aaria_pin as ap
from aaria_pin.apps.record_model import replay_in_mujoco
from aaria_pin.core.export.mjcf_emit import BASE_JOINTS

mujoco = pytest.importorskip("mujoco")

FIXTURES = Path(__file__).resolve().parents[1] / "fixtures" / "v0_1_0"


def run_mjcf(*args: str) -> tuple[int, str, str]:
    """``aaria mjcf ARGS`` in-process: exit status, stdout, stderr (the group's error handling)."""
    from aaria_pin.cli import main
    from aaria_pin.cli.mjcf_cmd import mjcf

    group = main
    if "mjcf" not in main.commands:  # until the command is registered in cli/_app.py
        group = type(main)(commands={"mjcf": mjcf})
    result = CliRunner().invoke(group, ["mjcf", *args])
    return result.exit_code, result.stdout, result.stderr


def test_a_preset_on_a_moving_base(tmp_path: Path) -> None:
    out = tmp_path / "fig2.xml"
    code, stdout, _ = run_mjcf("--preset", "aaria-fig2", "-o", str(out))
    assert code == 0 and "6 joints, 14 IMU sites" in stdout and "compiles in MuJoCo" in stdout
    model = mujoco.MjModel.from_xml_path(str(out))
    assert [model.joint(k).name for k in range(6)] == list(BASE_JOINTS)
    assert model.nsensor == 28 and model.nsite == 15


def test_a_run_file_replays_in_mujoco(tmp_path: Path) -> None:
    entry = ap.find_robot("ur5")
    run = ap.simulate_urdf_run(
        entry.urdf.read_text(), urdf_dir=entry.urdf.parent, duration=1.0, noise=False
    )
    ap.write_run(tmp_path / "ur5.h5", run)
    out = tmp_path / "ur5.xml"
    code, stdout, stderr = run_mjcf("--from", str(tmp_path / "ur5.h5"), "-o", str(out))
    assert code == 0 and "moving base" in stdout
    assert "7 visual mesh file(s) left out" in stderr  # COLLADA: the STL collision meshes drawn
    imu, tau = replay_in_mujoco(ap.read_run(tmp_path / "ur5.h5"), out.read_text())
    for part in (slice(0, 3), slice(3, 6)):
        scale = np.abs(run.imu[..., part]).max()
        np.testing.assert_allclose(imu[..., part], run.imu[..., part], atol=1e-9 * scale)
    np.testing.assert_allclose(tau, run.tau, atol=1e-9 * np.abs(run.tau).max())


def test_a_robot_on_a_fixed_base_and_an_old_run_file(tmp_path: Path) -> None:
    out = tmp_path / "panda.xml"
    code, stdout, _ = run_mjcf("--robot", "panda", "--fixed-base", "--rate", "500", "-o", str(out))
    assert code == 0 and "9 joints, 20 IMU sites" in stdout and "fixed base" in stdout
    model = mujoco.MjModel.from_xml_path(str(out))
    assert model.nq == 9 and model.opt.timestep == 0.002 and model.neq == 1  # the finger mimic
    old = tmp_path / "old.xml"  # a 0.1.0 DH file stores no URDF: the run's arm is re-made
    code, stdout, _ = run_mjcf("--from", str(FIXTURES / "dh_run.h5"), "-o", str(old))
    assert code == 0 and "moving base" in stdout
    assert mujoco.MjModel.from_xml_path(str(old)).nsensor == 2 * int(stdout.split()[5])


def test_a_urdf_whose_inertia_mujoco_refuses_is_written_balanced(tmp_path: Path) -> None:
    urdf = tmp_path / "flat.urdf"
    urdf.write_text(
        '<robot name="flat"><link name="root"/><link name="plate"><inertial><mass value="1"/>'
        '<inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.01"/></inertial>'
        '</link><joint name="spin" type="continuous"><parent link="root"/>'
        '<child link="plate"/></joint></robot>'
    )
    out = tmp_path / "flat.xml"
    code, stdout, stderr = run_mjcf("--urdf", str(urdf), "-o", str(out))
    assert code == 0 and "compiles in MuJoCo" in stdout
    assert "break A + B >= C ('plate'" in stderr and 'balanceinertia="true"' in out.read_text()


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("--preset", "aaria-fig2", "--robot", "ur5"), "give one robot"),
        ((), "give one robot"),
        (("--preset", "aaria-fig2", "--tool", "tool0"), "--tool is given with --preset"),
        (("--robot", "ur5", "--density", "1000"), "--density is given with --robot"),
        (("--preset", "aaria-fig2", "--rate", "0"), "--rate is 0; allowed: 0 < rate <= 100000 Hz"),
        (("--robot", "ur5", "--tool", "nowhere"), "frame 'nowhere' is not in model"),
        (("--preset", "no-such-arm"), "no-such-arm"),
    ],
)
def test_bad_options_exit_2_and_write_nothing(
    tmp_path: Path, args: tuple[str, ...], message: str
) -> None:
    out = tmp_path / "m.xml"
    code, _, stderr = run_mjcf(*args, "-o", str(out))
    assert code == 2 and message in stderr and len(stderr.strip().splitlines()) == 1
    assert not out.exists()


def test_a_run_with_actuators_carries_them(tmp_path: Path) -> None:
    from dataclasses import replace

    from aaria_pin.core.actuator import ActuatorModel
    from aaria_pin.core.joint_sensors import model_attributes
    from aaria_pin.files.runfile import write_run

    run = ap.simulate_run(ap.get_preset("aaria-fig2").table, duration=0.1, noise=False)
    model = ActuatorModel(rotor_inertia=1e-4, gear_ratio=[50.0, 100, 100, 100, 50, 20], coulomb=2.0)
    stored = {**run.attributes, "actuator": model_attributes(model)}
    write_run(tmp_path / "run.h5", replace(run, attributes=stored))
    code, _, _ = run_mjcf("--from", str(tmp_path / "run.h5"), "-o", str(tmp_path / "run.xml"))
    compiled = mujoco.MjModel.from_xml_path(str(tmp_path / "run.xml"))
    assert code == 0 and compiled.nv == 6 + 6  # the base chain (no actuator) and the joints
    np.testing.assert_allclose(compiled.dof_armature[6:], [0.25, 1, 1, 1, 0.25, 0.04], rtol=1e-14)
    assert compiled.dof_frictionloss[6:].tolist() == [2.0] * 6 and not np.any(compiled.dof_damping)
    assert "stribeck_torque = 0.0" in (tmp_path / "run.xml").read_text()
