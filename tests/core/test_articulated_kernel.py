"""The articulated-body kernel of the torque drive (the ``aba`` dynamics) against Pinocchio.

Per evaluation (against Pinocchio: ``tests/core/test_forward_kernel.py``): beyond the stops it
equals the CRBA kernel (the ``kernel`` dynamics) to 1e-12 relative.
Whole runs equal the CRBA kernel's and the Pinocchio path's, on their stops too (CRBA evaluates
there), and a run inside its stops is the run without them bit for bit; new torque runs record
``aba`` and are made again bit for bit, and a run recorded with ``kernel`` is still made by the
CRBA kernel.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from aaria_pin.apps.remake import remake_record
from aaria_pin.core.catalogue import find_robot
from aaria_pin.core.forward import (
    DYNAMICS,
    forward_simulate,
    reference_forward_simulate,
)
from aaria_pin.core.joint_sensors import ActuatorModel
from aaria_pin.core.run import TorqueDrive
from aaria_pin.core.urdf_robot import read_urdf_file
from aaria_pin.core.urdf_run import simulate_urdf_run
from aaria_pin.files.runfile import read_run, write_run
from tests.core.test_forward_kernel import MOTORS, _case, _robot, aba_and_crba

RTOL = 1e-12


def _close(got: np.ndarray, want: np.ndarray) -> None:
    assert np.isfinite(got).all() and np.isfinite(want).all()
    np.testing.assert_allclose(got, want, rtol=RTOL, atol=RTOL * np.abs(want).max())


@pytest.mark.parametrize(("name", "moving_base"), [("panda", False), ("aaria-fig2", True)])
def test_an_evaluation_beyond_the_stops_equals_the_crba_kernel(
    name: str, moving_base: bool
) -> None:
    robot = _robot(name, moving_base)
    model = robot.model
    n, nb = robot.n_joints, robot.base_nv
    rng = np.random.default_rng(6)
    pin.seed(6)  # randomConfiguration draws from Pinocchio's own generator
    for _ in range(5):
        qf = pin.randomConfiguration(model)
        qf[: 3 * moving_base] = rng.normal(size=3 * moving_base)  # the base: no finite bounds
        vf, af = rng.normal(size=model.nv), rng.normal(size=model.nv)
        af[nb:] = 0.0
        q = qf[robot.base_nq :]
        beyond = rng.random(n) < 0.5  # about half the joints past a stop, the others inside
        stops = (np.where(beyond, q + 0.02, q - 1.0), np.where(beyond, q + 1.0, q + 1.0))
        stops[1][::3] = np.where(beyond[::3], q[::3] - 0.03, stops[1][::3])  # some past the upper
        stops[0][::3] = np.where(beyond[::3], q[::3] - 1.0, stops[0][::3])
        got, crba = aba_and_crba(robot, qf, vf, af, 10 * rng.normal(size=n), MOTORS, stops)
        free, _ = aba_and_crba(robot, qf, vf, af, np.zeros(n), MOTORS)
        _close(got, crba)
        assert np.abs(got - free).max() > 1.0  # the stops act (torques of thousands of N·m)


@pytest.mark.parametrize(
    ("name", "moving_base", "motors", "integrator"),
    [
        ("ur5", False, None, "rk4"),
        ("panda", False, MOTORS, "rk4"),
        ("aaria-fig2", True, MOTORS, "rk4"),
        ("ur5", True, None, "euler"),
    ],
)
def test_a_whole_run_equals_the_crba_kernel_and_the_pinocchio_path(
    name: str, moving_base: bool, motors: ActuatorModel | None, integrator: str
) -> None:
    robot, base, tau, time = _case(name, moving_base)
    n = robot.n_joints
    q0, v0 = np.full(n, 0.1), np.full(n, -0.2)
    options = {"substeps": 4, "actuator": motors, "integrator": integrator}
    got = DYNAMICS["aba"](robot, base, tau, time, q0, v0, **options)  # type: ignore[arg-type]
    crba = forward_simulate(robot, base, tau, time, q0, v0, **options)  # type: ignore[arg-type]
    for a, b in ((got.q, crba.q), (got.qd, crba.qd), (got.qdd, crba.qdd)):
        np.testing.assert_allclose(a, b, rtol=1e-11, atol=1e-11 * np.abs(b).max())
    if integrator == "rk4":
        want = reference_forward_simulate(
            robot, base, tau, time, q0, v0, substeps=4, actuator=motors
        )
        for a, b in ((got.q, want.q), (got.qd, want.qd), (got.qdd, want.qdd)):
            np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-9 * np.abs(b).max())


def test_with_stops_crba_evaluates_beyond_them_and_inside_them_it_is_the_free_run() -> None:
    robot, base, tau, time = _case("aaria-fig2", True)
    n = robot.n_joints
    q0, v0 = np.full(n, 0.1), np.full(n, -0.2)
    hit = {"actuator": MOTORS, "stops": (q0 - 0.01, q0 + 0.01)}  # every joint reaches a stop
    got = DYNAMICS["aba"](robot, base, tau, time, q0, v0, **hit)
    crba = forward_simulate(robot, base, tau, time, q0, v0, **hit)  # type: ignore[arg-type]
    want = reference_forward_simulate(robot, base, tau, time, q0, v0, **hit)  # type: ignore[arg-type]
    for a, b in ((got.q, crba.q), (got.qdd, crba.qdd), (got.q, want.q), (got.qdd, want.qdd)):
        np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-9 * np.abs(b).max())
    free = DYNAMICS["aba"](robot, base, tau, time, q0, v0, actuator=MOTORS)
    assert not np.array_equal(got.q, free.q)  # on its stops
    wide = (np.full(n, -10.0), np.full(n, 10.0))  # never reached
    inside = DYNAMICS["aba"](robot, base, tau, time, q0, v0, actuator=MOTORS, stops=wide)
    np.testing.assert_array_equal(inside.q, free.q)
    np.testing.assert_array_equal(inside.qdd, free.qdd)


def test_new_runs_record_aba_and_kernel_runs_keep_their_kernel(tmp_path: Path) -> None:
    assert TorqueDrive.dynamics == "aba"
    assert DYNAMICS["kernel"] is forward_simulate
    text = read_urdf_file(find_robot("ur5").urdf)
    settings = {"duration": 0.2, "rate": 100.0, "noise": False}
    prescribed = simulate_urdf_run(text, source="ur5", **settings)
    runs = {}
    for name in ("aba", "kernel"):
        driven = simulate_urdf_run(
            text, source="ur5", torques=prescribed.tau, dynamics=name, **settings
        )
        write_run(tmp_path / f"{name}.h5", driven)
        stored = read_run(tmp_path / f"{name}.h5")
        assert stored.attributes["dynamics"] == name
        np.testing.assert_array_equal(remake_record(stored).q, stored.q)
        runs[name] = driven.q
    np.testing.assert_allclose(runs["aba"], runs["kernel"], rtol=1e-11, atol=1e-11)
    default = simulate_urdf_run(text, source="ur5", torques=prescribed.tau, **settings)
    assert default.attributes["dynamics"] == "aba"
    np.testing.assert_array_equal(default.q, runs["aba"])
