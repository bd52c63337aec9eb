"""The compiled forward dynamics of the torque drive against Pinocchio.

Per evaluation: the kernel's joint accelerations equal ``pin.aba`` on fixed-base robots (ur5,
panda; with an actuator, ``model.armature`` set and the friction taken from the torques) and,
on a moving base (aaria-fig2, ur5), the joints' block of ``pin.crba`` solved against
``pin.rnea`` with the base's velocity and acceleration (ABA would let the base react); so do the
articulated-body kernel's (the ``aba`` dynamics), to 1e-12, and they equal the CRBA kernel's. Whole
runs: the kernel equals the Pinocchio path (:func:`reference_forward_simulate`, same RK4, same
sub-steps); semi-implicit Euler converges at first order; models the kernel cannot do take the
Pinocchio path; a run records the integrator that made it. The stops of the ``clamp`` policy:
their torque by hand, and the kernel equals the Pinocchio path with joints on their stops.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from aaria_pin.aaria.dh_robot import build_dh_robot
from aaria_pin.aaria.presets import get_preset
from aaria_pin.apps.remake import remake_record
from aaria_pin.core._articulated_kernel import (
    articulated_at,
    articulated_stops,
    articulated_workspace,
)
from aaria_pin.core._forward_kernel import _at, joint_accelerations, workspace
from aaria_pin.core.actuator import armature, friction
from aaria_pin.core.catalogue import find_robot
from aaria_pin.core.forward import (
    STOP_OMEGA_H,
    flatten_dynamics,
    forward_simulate,
    kernel_motor,
    kernel_stops,
    reference_forward_simulate,
    stop_torques,
)
from aaria_pin.core.joint_sensors import ActuatorModel
from aaria_pin.core.model import RobotModel
from aaria_pin.core.oscillation import base_motion
from aaria_pin.core.run import recorded_dynamics
from aaria_pin.core.trajectory import BaseMotion, sample_times
from aaria_pin.core.urdf_robot import load_urdf_robot, read_urdf_file
from aaria_pin.core.urdf_run import simulate_urdf_run
from aaria_pin.errors import InputFileError, ParameterError
from aaria_pin.files.runfile import read_run, write_run

MOTORS = ActuatorModel(
    rotor_inertia=2e-5,
    gear_ratio=50.0,
    viscous=0.3,
    coulomb=0.8,
    coulomb_velocity=0.05,
    stribeck_torque=0.4,
    stribeck_velocity=0.2,
)


def _robot(name: str, moving_base: bool) -> RobotModel:
    if name.startswith("aaria"):
        return build_dh_robot(get_preset(name).table).model(moving_base=moving_base)
    text = read_urdf_file(find_robot(name).urdf)
    return load_urdf_robot(text, moving_base=moving_base).robot


def _kernel_qdd(
    robot: RobotModel,
    qf: np.ndarray,
    vf: np.ndarray,
    af: np.ndarray,
    tau: np.ndarray,
    actuator: ActuatorModel | None,
) -> np.ndarray:
    flat = flatten_dynamics(robot)
    assert flat is not None
    nb_q, nb_v = robot.base_nq, robot.base_nv
    out = np.empty(robot.n_joints)
    motor = kernel_motor(actuator, robot.n_joints)
    joint_accelerations(
        flat,
        qf[:nb_q].copy(),
        vf[:nb_v].copy(),
        af[:nb_v].copy(),
        qf[nb_q:].copy(),
        vf[nb_v:].copy(),
        tau,
        motor,
        (False, np.zeros(robot.n_joints), np.zeros(robot.n_joints), 0.0),
        workspace(robot.model.njoints, robot.n_joints),
        out,
    )
    return out


def aba_and_crba(
    robot: RobotModel,
    qf: np.ndarray,
    vf: np.ndarray,
    af: np.ndarray,
    tau: np.ndarray,
    actuator: ActuatorModel | None,
    stops: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """The ABA kernel's and the CRBA kernel's accelerations at one full state.

    The base's state held over two samples and read at k = 0 (its interpolation is then the
    sample itself), the torques likewise.
    """
    flat = flatten_dynamics(robot)
    assert flat is not None
    n, nb_q, nb_v = robot.n_joints, robot.base_nq, robot.base_nv
    base = tuple(
        np.ascontiguousarray(np.tile(x, (2, 1))) for x in (qf[:nb_q], vf[:nb_v], af[:nb_v])
    )
    torques = np.tile(tau, (2, 1))
    q, v = qf[nb_q:].copy(), vf[nb_v:].copy()
    motor, stop = kernel_motor(actuator, n), kernel_stops(stops, n, 1e-3)
    aba, crba = np.empty(n), np.empty(n)
    work = articulated_workspace(len(flat[0]))
    articulated_at(flat, base, torques, False, 0.0, q, v, motor, work, aba)
    if stops is not None:
        articulated_stops(flat, q, v, stop, work, aba)
    _at(flat, base, torques, False, 0.0, q, v, motor, stop, workspace(len(flat[0]), n), crba)
    return aba, crba


@pytest.mark.parametrize("name", ["ur5", "panda"])
@pytest.mark.parametrize("motors", [None, MOTORS])
def test_an_evaluation_equals_pinocchio_aba_on_a_fixed_base(
    name: str, motors: ActuatorModel | None
) -> None:
    robot = _robot(name, moving_base=False)
    model = robot.model.copy()
    n = robot.n_joints
    rng = np.random.default_rng(3)
    for _ in range(5):
        q = pin.randomConfiguration(model)
        v, tau = rng.normal(size=n), 10 * rng.normal(size=n)
        expected_tau = tau
        if motors is not None:
            model.armature = armature(motors, n)
            expected_tau = tau - friction(motors, v)
        expected = pin.aba(model, model.createData(), q, v, expected_tau)
        got = _kernel_qdd(robot, q, v, np.zeros(n), tau, motors)
        np.testing.assert_allclose(got, expected, rtol=1e-10, atol=1e-10 * np.abs(expected).max())
        aba, crba = aba_and_crba(robot, q, v, np.zeros(n), tau, motors)
        for want in (expected, crba):
            np.testing.assert_allclose(aba, want, rtol=1e-12, atol=1e-12 * np.abs(want).max())


@pytest.mark.parametrize("name", ["aaria-fig2", "ur5", "panda"])
def test_an_evaluation_on_a_moving_base_equals_pinocchio_crba_and_rnea(name: str) -> None:
    robot = _robot(name, moving_base=True)
    model = robot.model
    data = model.createData()
    nb = robot.base_nv
    rng = np.random.default_rng(4)
    for _ in range(5):
        q = pin.randomConfiguration(model)
        q[:3] = rng.normal(size=3)
        v, a = rng.normal(size=model.nv), rng.normal(size=model.nv)
        a[nb:] = 0.0
        tau = 10 * rng.normal(size=robot.n_joints)
        bias = pin.rnea(model, data, q, v, a)[nb:]
        mass = pin.crba(model, data, q)
        mass = np.triu(mass) + np.triu(mass, 1).T
        expected = np.linalg.solve(mass[nb:, nb:], tau - bias)
        got = _kernel_qdd(robot, q, v, a, tau, None)
        np.testing.assert_allclose(got, expected, rtol=1e-10, atol=1e-10 * np.abs(expected).max())
        aba, crba = aba_and_crba(robot, q, v, a, tau, None)
        for want in (expected, crba):
            np.testing.assert_allclose(aba, want, rtol=1e-12, atol=1e-12 * np.abs(want).max())


def _case(name: str, moving_base: bool) -> tuple[RobotModel, BaseMotion, np.ndarray, np.ndarray]:
    robot = _robot(name, moving_base)
    time = sample_times(0.2, 100.0)
    base = BaseMotion.resting(time.size)
    if moving_base:
        base = base_motion(get_preset("aaria-fig2").base_table, time)
    rng = np.random.default_rng(5)
    tau = 2 * rng.normal(size=(time.size, robot.n_joints))
    return robot, base, tau, time


@pytest.mark.parametrize(
    ("name", "moving_base", "motors"),
    [
        ("ur5", False, None),
        ("panda", False, MOTORS),
        ("aaria-fig2", True, MOTORS),
        ("ur5", True, None),
    ],
)
def test_a_whole_run_equals_the_pinocchio_path(
    name: str, moving_base: bool, motors: ActuatorModel | None
) -> None:
    robot, base, tau, time = _case(name, moving_base)
    n = robot.n_joints
    q0, v0 = np.full(n, 0.1), np.full(n, -0.2)
    got = forward_simulate(robot, base, tau, time, q0, v0, substeps=4, actuator=motors)
    want = reference_forward_simulate(robot, base, tau, time, q0, v0, substeps=4, actuator=motors)
    for a, b in ((got.q, want.q), (got.qd, want.qd), (got.qdd, want.qdd)):
        np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-9 * np.abs(b).max())


def test_a_stop_is_a_critically_damped_spring_beyond_its_limit_only() -> None:
    stops = (np.array([-1.0, -1.0, -1.0]), np.array([1.0, 1.0, 1.0]))
    q, v = np.array([1.5, -1.25, 0.5]), np.array([2.0, -3.0, 7.0])
    inertia, omega = np.array([2.0, 4.0, 9.0]), 10.0
    got = stop_torques(q, v, inertia, stops, omega)
    # k = m·ω², c = 2·m·ω: joint 1 is 0.5 past its upper limit, joint 2 0.25 below its lower
    want = [-2 * 100 * 0.5 - 2 * 2 * 10 * 2.0, -4 * 100 * -0.25 - 2 * 4 * 10 * -3.0, 0.0]
    np.testing.assert_allclose(got, want, rtol=1e-15)


@pytest.mark.parametrize(
    ("name", "moving_base", "motors"),
    [("ur5", False, None), ("aaria-fig2", True, MOTORS), ("ur5", True, None)],
)
def test_with_stops_a_run_equals_the_pinocchio_path_and_is_held_near_its_limits(
    name: str, moving_base: bool, motors: ActuatorModel | None
) -> None:
    robot, base, tau, time = _case(name, moving_base)
    n = robot.n_joints
    q0, v0 = np.full(n, 0.1), np.full(n, -0.2)
    stops = (q0 - 0.01, q0 + 0.01)  # every joint reaches a stop within the run
    options = {"substeps": 4, "actuator": motors, "stops": stops}
    got = forward_simulate(robot, base, tau, time, q0, v0, **options)  # type: ignore[arg-type]
    want = reference_forward_simulate(robot, base, tau, time, q0, v0, **options)  # type: ignore[arg-type]
    for a, b in ((got.q, want.q), (got.qd, want.qd), (got.qdd, want.qdd)):
        np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-9 * np.abs(b).max())
    free = forward_simulate(robot, base, tau, time, q0, v0, substeps=4, actuator=motors)
    beyond = np.maximum(got.q - stops[1], stops[0] - got.q)
    out = np.maximum(free.q - stops[1], stops[0] - free.q).max()
    assert (beyond > 0).any() and beyond.max() < 0.5 * out  # on the stops, a little past them
    assert STOP_OMEGA_H / (float(time[1] - time[0]) / 4) == pytest.approx(60.0)  # ω [rad/s]


def test_semi_implicit_euler_converges_at_first_order() -> None:
    robot, base, tau, time = _case("aaria-fig2", True)
    n = robot.n_joints
    q0, v0 = np.zeros(n), np.zeros(n)
    exact = forward_simulate(robot, base, tau, time, q0, v0, substeps=64).q[-1]
    errors = [
        np.abs(
            forward_simulate(robot, base, tau, time, q0, v0, substeps=s, integrator="euler").q[-1]
            - exact
        ).max()
        for s in (8, 16, 32)
    ]
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all((ratios > 1.7) & (ratios < 2.4)), ratios


def test_an_unknown_integrator_is_refused() -> None:
    robot, base, tau, time = _case("ur5", False)
    n = robot.n_joints
    with pytest.raises(ParameterError, match="integrator is 'rk2'; allowed: rk4, euler") as info:
        forward_simulate(robot, base, tau, time, np.zeros(n), np.zeros(n), integrator="rk2")
    assert info.value.parameter == "integrator"


def test_continuous_joints_take_the_pinocchio_path() -> None:
    robot = _robot("kinova", moving_base=False)
    assert flatten_dynamics(robot) is None
    time = sample_times(0.1, 100.0)
    n = robot.n_joints
    tau = np.ones((time.size, n))
    base = BaseMotion.resting(time.size)
    got = forward_simulate(robot, base, tau, time, np.zeros(n), np.zeros(n))
    want = reference_forward_simulate(robot, base, tau, time, np.zeros(n), np.zeros(n))
    np.testing.assert_array_equal(got.q, want.q)
    with pytest.raises(ParameterError, match="allowed: rk4") as info:
        forward_simulate(robot, base, tau, time, np.zeros(n), np.zeros(n), integrator="euler")
    assert info.value.parameter == "integrator"


def test_a_run_records_its_integrator_and_is_made_again(tmp_path: Path) -> None:
    text = read_urdf_file(find_robot("ur5").urdf)
    settings = {"duration": 0.2, "rate": 100.0, "noise": False}
    prescribed = simulate_urdf_run(text, source="ur5", **settings)
    driven = simulate_urdf_run(text, source="ur5", torques=prescribed.tau, **settings)
    write_run(tmp_path / "t.h5", driven)
    stored = read_run(tmp_path / "t.h5")
    assert stored.attributes["dynamics"] == "aba"
    again = remake_record(stored)
    np.testing.assert_array_equal(again.q, stored.q)
    # an older run (no attribute) was made by the Pinocchio path; an unknown name is refused
    assert recorded_dynamics({}) == "reference"
    with pytest.raises(InputFileError) as info:
        recorded_dynamics({"dynamics": "fast"})
    assert info.value.parameter == "dynamics"
