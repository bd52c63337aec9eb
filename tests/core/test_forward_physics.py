"""Physics checks of the torque drive (the integrator new runs use, ``TorqueDrive.dynamics``).

Each check compares the drive with a computation that shares none of its code: the energy
balance (Pinocchio's kinetic and potential energy against the exact work of the torques), the
convergence order of its RK4 (against scipy's DOP853 on the ODE written here with ``pin.aba``)
and MuJoCo's own RK4 ``mj_step`` on the robot's exported MJCF. Fixed base, no actuator (no
friction), on ur5 and aaria-fig2. Only the public path is used, so the checks hold for any
implementation of the drive.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import cache

import numpy as np
import pinocchio as pin
import pytest

import aaria_pin as ap
from aaria_pin.aaria.dh_robot import build_dh_robot
from aaria_pin.core.forward import DYNAMICS
from aaria_pin.core.model import RobotModel
from aaria_pin.core.run import TorqueDrive
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory, sample_times
from aaria_pin.core.urdf_robot import load_urdf_robot, read_urdf_file


def _ur5() -> tuple[RobotModel, str, str | None]:
    entry = ap.find_robot("ur5")
    robot = load_urdf_robot(
        read_urdf_file(entry.urdf), urdf_dir=entry.urdf.parent, moving_base=False
    )
    return robot.robot, robot.urdf, str(entry.urdf.parent)


def _fig2() -> tuple[RobotModel, str, str | None]:
    dh = build_dh_robot(ap.get_preset("aaria-fig2").table)
    return dh.model(moving_base=False), dh.urdf, None


BUILDERS = {"ur5": _ur5, "aaria-fig2": _fig2}
ROBOTS = tuple(BUILDERS)


@cache
def fixed_robot(name: str) -> tuple[RobotModel, str, str | None]:
    """The robot on a fixed base, its URDF text and the URDF's folder (for meshes)."""
    return BUILDERS[name]()


def start(robot: RobotModel) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """An initial state inside the joints' ranges, and torques near gravity's there.

    Returns:
        q0 [rad or m], v0 [rad/s or m/s] and torques that hold the arm against gravity at q0
        plus a small push of each joint [N·m or N]: the arm falls and swings over the runs
        (through joint ranges: the drive here applies no limits).
    """
    rng = np.random.default_rng(25)
    lower, upper = robot.position_limits
    middle, half = (lower + upper) / 2, np.minimum((upper - lower) / 2, 0.5)
    q0 = middle + 0.4 * half * rng.uniform(-1, 1, robot.n_joints)
    v0 = 0.4 * half * rng.uniform(-1, 1, robot.n_joints)
    model = robot.model
    gravity = pin.computeGeneralizedGravity(model, model.createData(), q0)
    return q0, v0, gravity + 0.5 * rng.uniform(-1, 1, robot.n_joints)


def drive(
    robot: RobotModel, torques: np.ndarray, time: np.ndarray, substeps: int
) -> JointTrajectory:
    """The drive's run from :func:`start`'s state under the given torques, base at rest.

    By the integrator new torque runs use (the default ``TorqueDrive.dynamics``).
    """
    q0, v0, _ = start(robot)
    base = BaseMotion.resting(time.size)
    integrate = DYNAMICS[TorqueDrive.dynamics]
    return integrate(robot, base, torques, time, q0, v0, substeps=substeps)


def energy(model: pin.Model, q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Kinetic plus potential energy at each sample [J] (Pinocchio's own functions)."""
    data = model.createData()
    return np.array(
        [
            pin.computeKineticEnergy(model, data, qk, vk)
            + pin.computePotentialEnergy(model, data, qk)
            for qk, vk in zip(q, v, strict=True)
        ]
    )


@pytest.mark.parametrize("name", ROBOTS)
def test_the_work_of_the_torques_is_the_change_of_energy_to_fourth_order(name: str) -> None:
    """Constant torques do the exact work ``tauᵀ·(q(T) − q(0))``: the balance
    ``ΔE − W`` is the integrator's error alone and falls 2⁴ = 16× when the step halves."""
    robot, _, _ = fixed_robot(name)
    _, _, tau = start(robot)
    residuals, scale = [], 0.0
    for rate in (50.0, 100.0, 200.0):  # RK4 steps of 5, 2.5 and 1.25 ms
        time = sample_times(1.0, rate)
        run = drive(robot, np.tile(tau, (time.size, 1)), time, substeps=4)
        e = energy(robot.model, run.q, run.qd)
        work = tau @ (run.q[-1] - run.q[0])
        residuals.append(abs(e[-1] - e[0] - work))
        scale = max(np.abs(e - e[0]).max(), abs(work))
        assert np.ptp(run.q, axis=0).max() > 0.1  # the arm really moves
    ratios = np.array(residuals[:-1]) / np.array(residuals[1:])
    assert np.all((ratios > 12) & (ratios < 20)), (residuals, ratios)
    assert residuals[-1] < 1e-7 * scale, (residuals, scale)  # small: 1e-7 of the energy moved


def dop853_reference(
    robot: RobotModel, torques: np.ndarray, time: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The final joint values and velocities by scipy's DOP853 at 1e-12 tolerances.

    The ODE is written here: ``qdd = aba(q, qd, tau(t))`` with the torques linear between
    samples, as the drive holds them; each sample interval is solved on its own so the
    integrator never steps across a kink of the torque.
    """
    from scipy.integrate import solve_ivp

    model = robot.model
    data = model.createData()
    n = robot.n_joints
    dt = float(time[1] - time[0])

    def rate_of(i: int) -> Callable[[float, np.ndarray], np.ndarray]:
        def f(t: float, x: np.ndarray) -> np.ndarray:
            w = (t - time[i]) / dt
            tau = (1 - w) * torques[i] + w * torques[i + 1]
            return np.concatenate([x[n:], pin.aba(model, data, x[:n], x[n:], tau)])

        return f

    q0, v0, _ = start(robot)
    x = np.concatenate([q0, v0])
    for i in range(time.size - 1):
        span = (float(time[i]), float(time[i + 1]))
        x = solve_ivp(rate_of(i), span, x, method="DOP853", rtol=1e-12, atol=1e-12).y[:, -1]
    return x[:n], x[n:]


@pytest.mark.parametrize("name", ROBOTS)
def test_rk4_converges_at_fourth_order_to_dop853(name: str) -> None:
    """Torques linear between samples at 50 Hz over 0.5 s; 1, 2, 4 sub-steps per sample:
    the final-state error against DOP853 falls 16× (12–20) each time the step halves."""
    robot, _, _ = fixed_robot(name)
    _, _, tau = start(robot)
    time = sample_times(0.5, 50.0)
    wobble = np.sin(2 * np.pi * 3.0 * time)[:, None] * np.linspace(0.5, 1.5, robot.n_joints)
    torques = tau + wobble
    q_ref, v_ref = dop853_reference(robot, torques, time)
    errors = []
    for substeps in (1, 2, 4):
        run = drive(robot, torques, time, substeps)
        errors.append(max(np.abs(run.q[-1] - q_ref).max(), np.abs(run.qd[-1] - v_ref).max()))
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all((ratios > 12) & (ratios < 20)), (errors, ratios)
    assert errors[-1] < 1e-4, errors


def mujoco_run(
    name: str, torque: np.ndarray, time: np.ndarray, substeps: int
) -> tuple[np.ndarray, np.ndarray]:
    """Joint values and velocities at the samples by MuJoCo's RK4 ``mj_step``.

    The exported MJCF (fixed base), timestep = sample step / ``substeps``, constraints off
    (no contacts or limits act, as the replay does), the constant ``torque`` applied as
    ``qfrc_applied`` (held over each step, like the drive's constant torques).
    """
    mujoco = pytest.importorskip("mujoco")
    from aaria_pin.core.export.mjcf_emit import emit_mjcf, load_mjcf

    robot, urdf, folder = fixed_robot(name)
    dt = float(time[1] - time[0])
    xml, _ = emit_mjcf(urdf, (), moving_base=False, rate=1 / dt, urdf_dir=folder)
    model = load_mjcf(xml)
    model.opt.timestep = dt / substeps
    model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    model.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)
    joints = [model.joint(joint) for joint in robot.joint_names]
    position = [int(joint.qposadr[0]) for joint in joints]
    dof = [int(joint.dofadr[0]) for joint in joints]
    assert model.nq == model.nv == robot.n_joints
    data = mujoco.MjData(model)
    q0, v0, _ = start(robot)
    data.qpos[position], data.qvel[dof] = q0, v0
    data.qfrc_applied[dof] = torque
    q, v = np.empty((time.size, robot.n_joints)), np.empty((time.size, robot.n_joints))
    q[0], v[0] = q0, v0
    for i in range(1, time.size):
        for _ in range(substeps):
            mujoco.mj_step(model, data)
        q[i], v[i] = data.qpos[position], data.qvel[dof]
    return q, v


@pytest.mark.parametrize("name", ROBOTS)
def test_the_drive_follows_mujocos_rk4_over_one_second(name: str) -> None:
    """Same robot, same constant torques, same RK4 at the same step (100 Hz, 4 sub-steps):
    the two share their truncation error, so the trajectories agree far inside it. Bound:
    1 % of the drive's own RK4 error over the run (estimated from the same run at half the
    step: error ≈ 16/15 · |x(h) − x(h/2)|)."""
    robot, _, _ = fixed_robot(name)
    _, _, tau = start(robot)
    time = sample_times(1.0, 100.0)
    ours = drive(robot, np.tile(tau, (time.size, 1)), time, substeps=4)
    finer = drive(robot, np.tile(tau, (time.size, 1)), time, substeps=8)
    q, v = mujoco_run(name, tau, time, substeps=4)
    rk4_error = 16 / 15 * max(np.abs(ours.q - finer.q).max(), np.abs(ours.qd - finer.qd).max())
    assert rk4_error > 0  # the scheme's error is measurable at this step
    difference = max(np.abs(ours.q - q).max(), np.abs(ours.qd - v).max())
    assert difference < 0.01 * rk4_error, (difference, rk4_error)
    assert np.ptp(q, axis=0).max() > 0.1  # the arm really moves


def print_figures() -> None:
    """Print the figures the tests check (the docs quote them), robot by robot."""
    for name in ROBOTS:
        robot, _, _ = fixed_robot(name)
        _, _, tau = start(robot)
        for rate in (50.0, 100.0, 200.0):
            time = sample_times(1.0, rate)
            run = drive(robot, np.tile(tau, (time.size, 1)), time, substeps=4)
            e = energy(robot.model, run.q, run.qd)
            work = tau @ (run.q[-1] - run.q[0])
            print(f"{name} energy {rate:g} Hz x 4: |dE - W| {abs(e[-1] - e[0] - work):.2e} J"
                  f" of W = {work:.1f} J")  # fmt: skip
        time = sample_times(0.5, 50.0)
        wobble = np.sin(2 * np.pi * 3.0 * time)[:, None] * np.linspace(0.5, 1.5, robot.n_joints)
        q_ref, v_ref = dop853_reference(robot, tau + wobble, time)
        for substeps in (1, 2, 4, 8):
            run = drive(robot, tau + wobble, time, substeps)
            error = max(np.abs(run.q[-1] - q_ref).max(), np.abs(run.qd[-1] - v_ref).max())
            print(f"{name} RK4 50 Hz x {substeps}: final-state error to DOP853 {error:.2e}")
        time = sample_times(1.0, 100.0)
        ours = drive(robot, np.tile(tau, (time.size, 1)), time, substeps=4)
        finer = drive(robot, np.tile(tau, (time.size, 1)), time, substeps=8)
        q, v = mujoco_run(name, tau, time, substeps=4)
        error = 16 / 15 * max(np.abs(ours.q - finer.q).max(), np.abs(ours.qd - finer.qd).max())
        difference = max(np.abs(ours.q - q).max(), np.abs(ours.qd - v).max())
        print(f"{name} MuJoCo RK4 100 Hz x 4 over 1 s: difference {difference:.1e},"
              f" RK4 error {error:.1e}")  # fmt: skip


if __name__ == "__main__":
    print_figures()
