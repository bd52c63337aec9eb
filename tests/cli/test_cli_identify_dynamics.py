"""``aaria identify --dynamics`` as a real robot gives them: motor torques with friction and
armature, physically consistent bodies, the fitted URDF written.

The oracles: the friction the hardware file gave the simulation (noise-free run: the fit is
exact up to the smoothing), the pseudo-inertias' eigenvalues recomputed here from the URDF's
inertials, and Pinocchio's RNEA of the written URDF against the run's rigid-body torques.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

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


def test_motor_currents_with_a_torque_constant(tmp_path: Path) -> None:
    hardware = tmp_path / "hardware.toml"
    hardware.write_text(
        "[actuator]\ngear_ratio = 100.0\nviscous = 0.8\ncoulomb = 2.0\n\n"
        "[current_sensor]\ntorque_constant = 0.1\nnoise = 0.003\n"
    )
    run = tmp_path / "ur5.h5"
    code, _, err = run_cli(
        "simulate", "--robot", "ur5", "--fixed-base", "--motion", "fourier", "--duration", "6",
        "--rate", "100", "--no-noise", "--hardware", str(hardware), "-o", str(run),
    )  # fmt: skip
    assert code == 0, err

    def fit(*extra: str) -> dict[str, Any]:
        code, out, err = run_cli(
            "identify", "--dynamics", str(run), "--torques", "current", "--json", *extra
        )
        assert code == 0, err
        return json.loads(out)

    def friction(report: dict[str, Any]) -> np.ndarray:
        return np.array([[row["Fv"], row["Fc"]] for row in report["friction"]])

    from_run = fit()
    assert friction(from_run)[:, 0] == pytest.approx(0.8, rel=0.05)
    assert friction(from_run)[:, 1] == pytest.approx(2.0, rel=0.05)
    given = fit("--torque-constant", "0.1", "--gear-ratio", "100")
    assert np.allclose(friction(given), friction(from_run))
    # a wrong torque constant: the base wrench (rigid-body loads, in newtons) no longer agrees
    # with the joints' torques, so the held-out error grows far above the noise
    wrong = fit("--torque-constant", "0.2")
    assert wrong["worst_holdout_relative_rms"] > 10 * from_run["worst_holdout_relative_rms"]
    # and it is estimated: each joint's k_t·N against the base wrench, half the one given
    for row in wrong["torque_scale"]:
        assert row["scale"] == pytest.approx(0.5, abs=max(3 * row["std"], 0.005))
    for row in from_run["torque_scale"]:
        assert row["scale"] == pytest.approx(1.0, abs=max(3 * row["std"], 0.01))
    # said in one line of the text output, naming the joints
    code, out, err = run_cli(
        "identify", "--dynamics", str(run), "--torques", "current", "--torque-constant", "0.2"
    )
    assert code == 0, err
    said = [line for line in out.splitlines() if line.startswith("torque constant × gear ratio")]
    assert len(said) == 1 and "is off" in said[0]
    shown = re.search(r"shoulder_pan_joint ([0-9.]+) ±", said[0])
    assert shown is not None and float(shown.group(1)) == pytest.approx(0.5, abs=0.01)
    code, out, err = run_cli("identify", "--dynamics", str(run), "--torques", "current")
    assert "the base wrench agrees with the one given on shoulder_pan_joint" in out


@pytest.mark.parametrize("torques", ["rigid", "measured", "motor"])
def test_a_torque_constant_with_other_torques_is_refused(ur5_run: Path, torques: str) -> None:
    # k_t and N turn currents into torques: with other torques they would be ignored
    for flag, value in (("--torque-constant", "0.1"), ("--gear-ratio", "50")):
        code, out, err = run_cli(
            "identify", "--dynamics", str(ur5_run), "--torques", torques, flag, value
        )
        assert code == 2 and out == "" and len(err.strip().splitlines()) == 1
        assert f"{flag} is given with --torques {torques}" in err
