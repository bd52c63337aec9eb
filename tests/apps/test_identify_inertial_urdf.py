"""The identified dynamics written back to a URDF: Pinocchio and MuJoCo load it, and the torques
each computes from it (plus the fitted friction and armature) are the run's motor torques."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import replace
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin
import pytest
from conftest import run_cli

from aaria_pin.apps.identify import identify_dynamics
from aaria_pin.apps.identify.inertial_result import DynamicIdentification
from aaria_pin.apps.identify.inertial_urdf import identified_urdf
from aaria_pin.apps.record_model import record_columns, record_model
from aaria_pin.core.record import RunRecord
from aaria_pin.errors import InputFileError, OutputFileError, ParameterError
from aaria_pin.files.source import open_record

HARDWARE = """[actuator]
rotor_inertia = 2.0e-5
gear_ratio = 100.0
viscous = [0.5, 0.6, 0.7, 0.3, 0.2, 0.1]
coulomb = [1.5, 2.5, 2.0, 1.0, 0.5, 0.4]
coulomb_velocity = 0.02
"""


@pytest.fixture(scope="module")
def fitted(tmp_path_factory: pytest.TempPathFactory) -> tuple[RunRecord, DynamicIdentification]:
    folder = tmp_path_factory.mktemp("urdf")
    (folder / "hw.toml").write_text(HARDWARE)
    code, _, err = run_cli(
        "simulate", "--robot", "ur5", "--fixed-base", "--motion", "fourier", "--duration", "6",
        "--rate", "100", "--no-noise", "--hardware", str(folder / "hw.toml"),
        "-o", str(folder / "run.h5"),
    )  # fmt: skip
    assert code == 0, err
    record = open_record(folder / "run.h5", None)
    return record, identify_dynamics(record, torques="motor", consistent=True)


def _joint_data(
    record: RunRecord,
) -> tuple[list[str], np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Joint names (model order), q, qd, qdd and the motor torques in that order."""
    robot = record_model(record, moving_base=False)
    columns = record_columns(record, robot)
    q, qd, qdd, motor = (
        np.asarray(x, dtype=float)[:, columns]
        for x in (record.q, record.qd, record.qdd, record.tables["tau_motor"])
    )
    return list(robot.joint_names), q, qd, qdd, motor


def test_pinocchio_and_mujoco_load_it_and_give_the_motor_torques(
    fitted: tuple[RunRecord, DynamicIdentification], tmp_path: Path
) -> None:
    record, result = fitted
    path = tmp_path / "identified.urdf"
    path.write_text(identified_urdf(record, result))
    names, q, qd, qdd, motor = _joint_data(record)
    friction = result.standard.friction() if result.standard else np.zeros((6, 3))
    fv, fc, ia = friction.T
    dry = fc * np.tanh(qd / 0.02)  # the run's smoothing; URDF's friction is the Coulomb torque
    scale = np.sqrt(np.mean(np.square(motor)))

    model = pin.buildModelFromUrdf(str(path))
    data = model.createData()
    order = [model.idx_vs[model.getJointId(name)] for name in names]
    assert np.allclose(model.damping[order], fv) and np.allclose(model.friction[order], fc)
    tau = np.array([pin.rnea(model, data, *x)[order] for x in zip(q, qd, qdd, strict=True)])
    assert np.sqrt(np.mean(np.square(tau + fv * qd + ia * qdd + dry - motor))) < 1e-6 * scale

    mj = mujoco.MjModel.from_xml_path(str(path))
    joints = [mj.joint(name).dofadr[0] for name in names]
    assert np.allclose(mj.dof_damping[joints], fv) and np.allclose(mj.dof_frictionloss[joints], fc)
    mj.dof_armature[joints] = ia  # URDF has no armature field
    mj.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_FRICTIONLOSS  # dry friction: ours, tanh
    mj.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4  # no implicit damping term in inverse
    mj_data = mujoco.MjData(mj)
    out = []
    for row in zip(q, qd, qdd, strict=True):
        mj_data.qpos[joints], mj_data.qvel[joints], mj_data.qacc[joints] = row
        mujoco.mj_inverse(mj, mj_data)
        out.append(mj_data.qfrc_inverse[joints].copy())
    assert np.sqrt(np.mean(np.square(np.array(out) + dry - motor))) < 1e-6 * scale


def test_the_written_urdf_holds_the_fit(
    fitted: tuple[RunRecord, DynamicIdentification], tmp_path: Path
) -> None:
    record, result = fitted
    root = ET.fromstring(identified_urdf(record, result))
    assert root.find(".//mesh") is None  # meshes dropped (MuJoCo loads STL/OBJ only)
    joint = root.find("joint[@name='shoulder_lift_joint']")
    assert joint is not None
    dynamics = joint.find("dynamics")
    assert dynamics is not None
    assert float(dynamics.get("damping", "nan")) == pytest.approx(0.6, rel=1e-6)
    assert float(dynamics.get("friction", "nan")) == pytest.approx(2.5, rel=1e-6)
    masses = [float(m.get("value", "nan")) for m in root.iter("mass")]
    assert all(np.isfinite(masses)) and min(masses) >= 0
    kept = ET.fromstring(identified_urdf(record, result, keep_meshes=True))
    assert kept.find(".//mesh") is not None


def test_only_a_consistent_fit_is_written(fitted: tuple[RunRecord, DynamicIdentification]) -> None:
    record, _ = fitted
    loose = identify_dynamics(record, torques="motor")
    with pytest.raises(ParameterError) as info:
        identified_urdf(record, loose)
    assert info.value.parameter == "consistent"

    with pytest.raises(InputFileError):
        identified_urdf(replace(record, urdf=""), fitted[1])


def test_identify_request_writes_the_identified_urdf(tmp_path: Path) -> None:
    from aaria_pin.apps.identify.request import IdentifyRequest, identify_files
    from aaria_pin.core.conflicts import OptionConflictError

    (tmp_path / "hw.toml").write_text(HARDWARE)
    code, _, err = run_cli(
        "simulate", "--robot", "ur5", "--fixed-base", "--duration", "2", "--rate", "100",
        "--no-noise", "--hardware", str(tmp_path / "hw.toml"), "-o", str(tmp_path / "run.h5"),
    )  # fmt: skip
    assert code == 0, err
    target = tmp_path / "fitted.urdf"
    request = IdentifyRequest((tmp_path / "run.h5",), dynamics=True, dynamics_urdf=target)
    outcome = identify_files(request)
    assert outcome.report["consistent"] and outcome.report["torques"] == "motor"
    assert any(line.startswith("friction shoulder_pan_joint") for line in outcome.lines)
    model = pin.buildModelFromUrdf(str(target))
    assert model.nv == 6 and np.all(model.damping > 0)
    with pytest.raises(OptionConflictError) as info:
        IdentifyRequest((tmp_path / "run.h5",), consistent=True)  # kinematics: no such option
    assert info.value.parameter == "consistent"
    with pytest.raises(OutputFileError):
        identify_files(replace(request, dynamics_urdf=tmp_path / "fitted.txt"))
