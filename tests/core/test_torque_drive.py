"""Torque drive for URDF robots: a run's own torques, fed back by forward dynamics, reproduce its
motion (the original is the joint table's sine motion, known in closed form), through the Python
API and the command line; joint counts that do not match are refused in one line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import run_cli

from aaria_pin.core.catalogue import find_robot
from aaria_pin.core.record import RunRecord
from aaria_pin.core.urdf_robot import read_urdf_file
from aaria_pin.core.urdf_run import simulate_urdf_run
from aaria_pin.errors import ParameterError
from aaria_pin.files.runfile import read_run, write_run

SETTINGS = {"duration": 1.0, "rate": 500.0, "noise": False}
"""1 s at 500 Hz, noise off (the issue's check)."""


@pytest.fixture(scope="module")
def ur5_run() -> RunRecord:
    """ur5 from its default tables on the default moving base."""
    return simulate_urdf_run(read_urdf_file(find_robot("ur5").urdf), source="ur5", **SETTINGS)


def test_feeding_back_the_torques_reproduces_the_motion(ur5_run: RunRecord) -> None:
    t = ur5_run.time
    table = ur5_run.tables["joint_table"]
    amplitude, bias, w, phase = table[:, 0], table[:, 2], table[:, 3], table[:, 4]
    np.testing.assert_allclose(  # the original follows its sines (all UR5 joints revolute)
        ur5_run.q, amplitude * np.sin(np.outer(t, w) + phase) + bias, atol=1e-12
    )
    driven = simulate_urdf_run(
        read_urdf_file(find_robot("ur5").urdf), source="ur5", torques=ur5_run.tau, **SETTINGS
    )
    assert np.abs(driven.q - ur5_run.q).max() < 2e-3
    assert np.abs(driven.qd - ur5_run.qd).max() < 2e-2
    assert driven.attributes["drive"] == "torque"
    np.testing.assert_array_equal(driven.tables["torque_table"], ur5_run.tau)
    np.testing.assert_allclose(driven.tau, ur5_run.tau, atol=1e-6)  # RNEA of the result


def test_cli_drive_torque_from_a_run_file(ur5_run: RunRecord, tmp_path: Path) -> None:
    code, _, err = run_cli(
        "simulate", "--robot", "ur5", "--duration", "1", "--rate", "500", "--no-noise",
        "-o", str(tmp_path / "run.h5"),
    )  # fmt: skip
    assert code == 0, err
    original = read_run(tmp_path / "run.h5")
    np.testing.assert_array_equal(original.q, ur5_run.q)
    driven_file = tmp_path / "driven.h5"
    code, out, err = run_cli(  # the time grid comes from the torque run
        "simulate", "--robot", "ur5", "--drive", "torque", "--torques", str(tmp_path / "run.h5"),
        "--no-noise", "-o", str(driven_file),
    )  # fmt: skip
    assert code == 0, err
    assert "501 samples at 500 Hz" in out
    driven = read_run(driven_file)
    assert np.abs(driven.q - original.q).max() < 2e-3
    assert driven.attributes["drive"] == "torque"
    again = tmp_path / "again.h5"  # --from re-makes the torque-driven run from its file
    assert run_cli("simulate", "--from", str(driven_file), "-o", str(again))[0] == 0
    np.testing.assert_array_equal(read_run(again).q, driven.q)


def test_mismatched_joint_counts_are_refused(ur5_run: RunRecord, tmp_path: Path) -> None:
    with pytest.raises(ParameterError, match=r"allowed: \(501 samples, 9 joints\)"):
        simulate_urdf_run(read_urdf_file(find_robot("panda").urdf), torques=ur5_run.tau, **SETTINGS)
    write_run(tmp_path / "ur5.h5", ur5_run)
    np.save(tmp_path / "tau.npy", ur5_run.tau[:, :5])
    for source, joints in (("ur5.h5", 9), ("tau.npy", 6)):
        robot = "panda" if source == "ur5.h5" else "ur5"
        output = tmp_path / "x.h5"
        code, _, err = run_cli(
            "simulate", "--robot", robot, "--duration", "1", "--rate", "500", "--drive",
            "torque", "--torques", str(tmp_path / source), "-o", str(output),
        )  # fmt: skip
        assert code == 2 and err.count("\n") == 1, err
        assert "--torques" in err and f"(501 samples, {joints} joints)" in err
        assert not output.exists()


def test_continuous_joints_are_driven_too() -> None:
    """kinova's continuous joints (cos θ, sin θ in Pinocchio's configuration)."""
    text = read_urdf_file(find_robot("kinova").urdf)
    settings = {"duration": 0.5, "rate": 500.0, "noise": False}
    prescribed = simulate_urdf_run(text, **settings)
    driven = simulate_urdf_run(text, torques=prescribed.tau, **settings)
    assert np.abs(driven.q - prescribed.q).max() < 2e-3


@pytest.mark.parametrize("kind", ["dh", "urdf"])
def test_a_limits_policy_needs_torques(kind: str) -> None:
    """Only a torque-driven run has a limits policy: one without torques is refused, not ignored."""
    from aaria_pin.aaria.presets import get_preset
    from aaria_pin.aaria.simulate import dh_request
    from aaria_pin.core.urdf_run import urdf_request

    entry = find_robot("ur5")
    with pytest.raises(ParameterError, match=r"^limits is 'stop' for a run without torques") as e:
        if kind == "dh":
            dh_request(get_preset("aaria-fig2").table, duration=0.1, limits="stop")
        else:
            urdf_request(read_urdf_file(entry.urdf), duration=0.1, limits="stop")
    assert e.value.parameter == "limits"
