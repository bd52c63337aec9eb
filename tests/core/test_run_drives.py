"""The drives of a run (``core/run/drives.py``): the torque drive's integrator and sub-steps.

Semi-implicit Euler is checked for its order (first: the error halves with the step, against
RK4 at a fine step), and a run made with a chosen integrator and sub-steps records them and is
re-made from its file bit for bit through the command line.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import run_cli

import aaria_pin as ap
from aaria_pin.core.catalogue import find_robot
from aaria_pin.core.forward import forward_simulate
from aaria_pin.core.run import TorqueDrive, driven, motion_from_record
from aaria_pin.core.run.motion import SineTable
from aaria_pin.core.trajectory import BaseMotion
from aaria_pin.core.urdf_robot import read_urdf_file
from aaria_pin.core.urdf_run import urdf_request
from aaria_pin.errors import ParameterError
from aaria_pin.files.runfile import read_run


def test_semi_implicit_euler_is_first_order() -> None:
    text = read_urdf_file(find_robot("ur5").urdf)
    record = urdf_request(text, source="ur5", noise=False, moving_base=False, duration=0.5).record()
    robot = ap.load_urdf_robot(text, moving_base=False).robot
    base = BaseMotion.resting(record.time.size)
    args = (robot, base, record.tau * 0.97, record.time, record.q[0], record.qd[0])
    truth = forward_simulate(*args, substeps=64).q[-1]
    errors = [
        np.abs(forward_simulate(*args, substeps=s, integrator="euler").q[-1] - truth).max()
        for s in (4, 8, 16)
    ]
    ratios = [errors[0] / errors[1], errors[1] / errors[2]]
    assert all(1.7 < r < 2.3 for r in ratios), (errors, ratios)


def test_a_chosen_integrator_is_recorded_and_re_made(tmp_path: Path) -> None:
    first = tmp_path / "run.h5"
    code, _, err = run_cli("simulate", "--robot", "ur5", "--duration", "0.5", "-o", str(first))
    assert code == 0, err
    driven_file = tmp_path / "euler.h5"
    code, _, err = run_cli(
        "simulate", "--robot", "ur5", "--drive", "torque", "--torques", str(first),
        "--integrator", "euler", "--substeps", "8", "--limits", "ignore", "-o", str(driven_file),
    )  # fmt: skip
    assert code == 0, err
    stored = read_run(driven_file)
    assert stored.attributes["integrator"] == "euler" and stored.attributes["substeps"] == 8
    again = tmp_path / "again.h5"
    code, _, err = run_cli("simulate", "--from", str(driven_file), "-o", str(again))
    assert code == 0, err
    np.testing.assert_array_equal(read_run(again).q, stored.q)
    rk4 = tmp_path / "rk4.h5"
    code, _, err = run_cli(
        "simulate", "--robot", "ur5", "--drive", "torque", "--torques", str(first),
        "--limits", "ignore", "-o", str(rk4),
    )  # fmt: skip
    assert code == 0, err
    assert "integrator" not in read_run(rk4).attributes  # the defaults: as before
    assert not np.array_equal(read_run(rk4).q, stored.q)


def test_the_stored_drive_is_the_drive_made() -> None:
    tau = np.zeros((5, 6))
    made = driven(SineTable(), {"torques": tau, "integrator": "euler", "substeps": 3})
    assert isinstance(made, TorqueDrive)
    tables, attributes = made.record(None)  # type: ignore[arg-type]
    again = motion_from_record({**tables, "joint_table": np.zeros((6, 5))}, attributes)
    assert isinstance(again, TorqueDrive)
    assert (again.integrator, again.substeps, again.limits) == ("euler", 3, "stop")


def test_substeps_with_a_controller_and_an_unknown_drive_are_refused() -> None:
    with pytest.raises(ParameterError, match="substeps is given for drive 'pd'"):
        driven(SineTable(), {"drive": "pd", "substeps": 4})
    with pytest.raises(ParameterError, match="drive is 'fly'"):
        driven(SineTable(), {"drive": "fly"})
