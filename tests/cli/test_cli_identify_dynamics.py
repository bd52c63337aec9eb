"""``aaria identify --dynamics`` as a real robot gives them: motor torques with friction and
armature, physically consistent bodies, the fitted URDF written.

The oracles: the friction the hardware file gave the simulation (noise-free run: the fit is
exact up to the smoothing), the pseudo-inertias' eigenvalues recomputed here from the URDF's
inertials, and Pinocchio's RNEA of the written URDF against the run's rigid-body torques.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from conftest import run_cli

from aaria_pin.files.source import open_record


@pytest.fixture(scope="module")
def ur5_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("dynamics")
    hardware = folder / "hardware.toml"
    hardware.write_text(
        "[actuator]\nrotor_inertia = 3.0e-5\ngear_ratio = 100.0\nviscous = 0.8\ncoulomb = 2.0\n"
    )
    run = folder / "ur5.h5"
    code, _, err = run_cli(
        "simulate", "--robot", "ur5", "--fixed-base", "--motion", "fourier", "--duration", "6",
        "--rate", "100", "--no-noise", "--hardware", str(hardware),
        "-o", str(run),
    )  # fmt: skip
    assert code == 0, err
    return run


def test_motor_torques_friction_consistent_urdf(ur5_run: Path, tmp_path: Path) -> None:
    urdf = tmp_path / "fitted.urdf"
    code, out, err = run_cli(
        "identify", "--dynamics", str(ur5_run), "--torques", "motor", "--consistent",
        "--write-urdf", str(urdf), "--json",
    )  # fmt: skip
    assert code == 0, err
    report = json.loads(out)
    for row in report["friction"]:
        assert row["Fv"] == pytest.approx(0.8, rel=0.02)
        assert row["Fc"] == pytest.approx(2.0, rel=0.02)
    model = pin.buildModelFromUrdf(str(urdf))
    for inertia in model.inertias[1:]:  # the pseudo-inertia [[Σ, m·c], [m·cᵀ, m]] is PSD
        m, c = inertia.mass, inertia.lever
        about_origin = inertia.inertia + m * (np.dot(c, c) * np.eye(3) - np.outer(c, c))
        sigma = 0.5 * np.trace(about_origin) * np.eye(3) - about_origin
        pseudo = np.block([[sigma, m * c[:, None]], [m * c[None, :], np.array([[m]])]])
        assert np.linalg.eigvalsh(pseudo).min() > -1e-9
    record = open_record(ur5_run, None)
    data = model.createData()
    tau = np.array(
        [
            pin.rnea(model, data, q, v, a)
            for q, v, a in zip(record.q, record.qd, record.qdd, strict=True)
        ]
    )
    assert np.sqrt(np.mean((tau - record.tau) ** 2)) < 0.02 * np.sqrt(np.mean(record.tau**2))


def test_dynamics_flags_need_dynamics(ur5_run: Path) -> None:
    code, _, err = run_cli("identify", str(ur5_run), "--consistent")
    assert code == 2 and "--consistent is given without --dynamics" in err
