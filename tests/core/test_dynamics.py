"""Torques and base wrench: vs per-sample RNEA, a static hand calculation, and energy balance."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import paper_frames
from pinocchio_oracles import reference_inverse_dynamics

from aaria_pin.aaria.dh_robot import BodyDimensions, build_dh_robot
from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.aaria.sine_tables import (
    base_motion,
    default_base_table,
    default_joint_table,
    joint_trajectory,
)
from aaria_pin.core.dynamics import inverse_dynamics
from aaria_pin.core.trajectory import sample_times

g = 9.81


@pytest.mark.parametrize("name", ["aaria-fig2", "aaria-fig3"])
def test_batched_equals_per_sample_rnea(name: str) -> None:
    robot = build_dh_robot(get_preset(name).table)
    model = robot.model(moving_base=True)
    time = sample_times(2.0, 50)
    trajectory = joint_trajectory(default_joint_table(robot.chain), robot.chain, time)
    base = base_motion(default_base_table(), time)
    for fast, reference in zip(
        inverse_dynamics(model, base, trajectory, threads=2),
        reference_inverse_dynamics(model, base, trajectory),
        strict=True,
    ):
        np.testing.assert_allclose(fast, reference, atol=1e-9)


def test_a_one_sample_batch_keeps_its_sample_axis() -> None:
    """Pinocchio returns a one-sample batch as a vector; batched_rnea keeps (1, nv)."""
    import pinocchio as pin

    from aaria_pin.core.dynamics import batched_rnea

    model = build_dh_robot(get_preset("aaria-fig2").table).model().model
    q = np.full((1, model.nq), 0.3)
    v, a = np.full((1, model.nv), 0.2), np.full((1, model.nv), -0.1)
    tau = batched_rnea(model, q, v, a)
    assert tau.shape == (1, model.nv)
    np.testing.assert_allclose(tau[0], pin.rnea(model, model.createData(), q[0], v[0], a[0]))


def test_horizontal_link_under_gravity_by_hand() -> None:
    a, a_tool = 0.8, 0.1
    table = np.zeros((8, 5))
    table[0] = [0.0, a, 0.0, 0.0, 1]  # revolute about DH z = world -y
    table[6, 1] = a_tool
    senJ = np.zeros((8, 5))
    senJ[0, 2] = np.pi / 2  # link along DH y = world -x: horizontal
    senB = np.zeros((2, 4))
    dims = BodyDimensions()
    record = simulate_run(table, senJ, senB, duration=0.2, rate=10, noise=False, dims=dims)
    section = dims.link_width * dims.link_height * dims.density
    m_link, m_tool = section * a, section * a_tool
    m_housing = np.pi * dims.housing_radius**2 * dims.housing_length * dims.density
    moment = (m_link * a / 2 + m_tool * (a + a_tool / 2)) * g  # lever arms along world -x
    np.testing.assert_allclose(record.tau[:, 0], -moment, rtol=1e-12)
    np.testing.assert_allclose(record.tau[:, 1:], 0.0)
    expected_wrench = [0, 0, (m_link + m_tool + m_housing) * g, 0, moment, 0]
    np.testing.assert_allclose(record.base_wrench, np.tile(expected_wrench, (3, 1)), atol=1e-10)


def _body_poses(table, senJ, senB, t):
    """World poses of the bodies: the base, then each non-empty module's post-joint frame."""
    T_base, modules, _ = paper_frames(table, senJ, senB, t)
    return [T_base, *(T for T in modules if T is not None)]


def _energy(inertias, poses_m, poses_0, poses_p, h) -> float:
    total = 0.0
    for inertia, Tm, T0, Tp in zip(inertias, poses_m, poses_0, poses_p, strict=True):
        c = [T[:3, :3] @ inertia.lever + T[:3, 3] for T in (Tm, T0, Tp)]
        v = (c[2] - c[0]) / (2 * h)
        S = T0[:3, :3].T @ (Tp[:3, :3] - Tm[:3, :3]) / (2 * h)
        w = np.array([S[2, 1], S[0, 2], S[1, 0]])
        total += (
            0.5 * inertia.mass * v @ v + 0.5 * w @ inertia.inertia @ w + inertia.mass * g * c[1][2]
        )
    return total


@pytest.mark.parametrize("name", ["aaria-fig2", "aaria-fig3"])
def test_power_of_torques_and_base_wrench_equals_rate_of_energy(name: str) -> None:
    table = get_preset(name).table
    senB = np.array([[0.05, 0.0, 1.5, 0.0], [0.1, 0.05, 1.1, 0.4]])
    record = simulate_run(table, base_table=senB, duration=2.0, rate=4, noise=False)
    model = build_dh_robot(table).model(moving_base=True).model
    inertias = list(model.inertias)[1:]  # base body (root joint), then one per module
    h, dt = 1e-5, 1e-3
    for k in range(1, record.time.size, 2):
        t = record.time[k]
        energy = [
            _energy(
                inertias,
                *(_body_poses(table, record.tables["senSenJ"], senB, s + e) for e in (-h, 0.0, h)),
                h,
            )
            for s in (t - dt, t + dt)
        ]
        rate_of_energy = (energy[1] - energy[0]) / (2 * dt)
        base = _body_poses(table, record.tables["senSenJ"], senB, t)[0]
        base_m, base_p = (
            _body_poses(table, record.tables["senSenJ"], senB, t + e)[0] for e in (-h, h)
        )
        p_dot = (base_p[:3, 3] - base_m[:3, 3]) / (2 * h)
        S = (base_p[:3, :3] - base_m[:3, :3]) @ base[:3, :3].T / (2 * h)
        omega_world = np.array([S[2, 1], S[0, 2], S[1, 0]])
        power = (
            record.tau[k] @ record.qd[k]
            + record.base_wrench[k, :3] @ p_dot
            + record.base_wrench[k, 3:] @ omega_world
        )
        assert power == pytest.approx(rate_of_energy, rel=1e-4, abs=1e-3)


@pytest.mark.parametrize("name", ["aaria-fig2", "aaria-fig3"])
def test_base_wrench_by_newton_euler_on_every_body(name: str) -> None:
    """F = Σ m(a_c - g); M about the base origin = Σ (c - p_b) × m(a_c - g) + dH/dt."""
    table = get_preset(name).table
    senB = np.array([[0.05, 0.0, 1.5, 0.0], [0.1, 0.05, 1.1, 0.4]])
    record = simulate_run(table, base_table=senB, duration=2.0, rate=2, noise=False)
    model = build_dh_robot(table).model(moving_base=True).model
    inertias = list(model.inertias)[1:]
    gravity = np.array([0.0, 0.0, -g])
    h, dt = 1e-5, 1e-3

    def poses(t: float) -> list[np.ndarray]:
        return _body_poses(table, record.tables["senSenJ"], senB, t)

    def com(t: float) -> list[np.ndarray]:
        return [
            T[:3, :3] @ inertia.lever + T[:3, 3]
            for T, inertia in zip(poses(t), inertias, strict=True)
        ]

    def momentum(t: float) -> list[np.ndarray]:
        before, now, after = poses(t - h), poses(t), poses(t + h)
        out = []
        for Tm, T0, Tp, inertia in zip(before, now, after, inertias, strict=True):
            S = T0[:3, :3].T @ (Tp[:3, :3] - Tm[:3, :3]) / (2 * h)
            omega_body = np.array([S[2, 1], S[0, 2], S[1, 0]])
            out.append(T0[:3, :3] @ inertia.inertia @ omega_body)
        return out

    for k in range(1, record.time.size):
        t = record.time[k]
        c_m, c_0, c_p = com(t - dt), com(t), com(t + dt)
        h_m, h_p = momentum(t - dt), momentum(t + dt)
        p_base = poses(t)[0][:3, 3]
        force, moment = np.zeros(3), np.zeros(3)
        for i, inertia in enumerate(inertias):
            accel = (c_p[i] - 2 * c_0[i] + c_m[i]) / dt**2
            f = inertia.mass * (accel - gravity)
            force += f
            moment += np.cross(c_0[i] - p_base, f) + (h_p[i] - h_m[i]) / (2 * dt)
        np.testing.assert_allclose(record.base_wrench[k, :3], force, rtol=1e-4, atol=1e-2)
        np.testing.assert_allclose(record.base_wrench[k, 3:], moment, rtol=1e-4, atol=1e-2)
