"""Physically consistent bodies: the pseudo-inertia against a solid box's own moments, the
log-Cholesky map both ways, and the constrained least squares against problems whose answer is
known."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from aaria_pin.apps.identify.inertial_consistent import (
    consistent_fit,
    log_cholesky,
    log_cholesky_of,
    project_consistent,
    pseudo_inertia,
    standard_from_pseudo,
)


def _box(mass: float, sides: tuple[float, float, float], centre: np.ndarray) -> np.ndarray:
    """Standard parameters of a solid box about the origin, from Pinocchio's own box inertia."""
    inertia = pin.Inertia.FromBox(mass, *sides)
    inertia = pin.Inertia(mass, centre, inertia.inertia)
    return np.asarray(inertia.toDynamicParameters())


def test_pseudo_inertia_of_a_box_is_its_second_moment() -> None:
    m, (a, b, c) = 2.0, (0.3, 0.2, 0.1)
    centre = np.array([0.1, -0.05, 0.2])
    J = pseudo_inertia(_box(m, (a, b, c), centre))[0]
    # ∫ x xᵀ dm of a box: m·diag(a², b², c²)/12 about its centre, plus m·c·cᵀ
    second = m * np.diag([a * a, b * b, c * c]) / 12 + m * np.outer(centre, centre)
    assert np.allclose(J[:3, :3], second, atol=1e-12)
    assert np.allclose(J[:3, 3], m * centre)
    assert J[3, 3] == m
    assert np.linalg.eigvalsh(J).min() > 0
    assert np.allclose(standard_from_pseudo(J[None]), _box(m, (a, b, c), centre))


def test_an_impossible_inertia_has_a_negative_pseudo_inertia_eigenvalue() -> None:
    standard = _box(1.0, (0.2, 0.2, 0.2), np.zeros(3))
    standard[9] = standard[4] + standard[6] + 0.01  # Izz > Ixx + Iyy: no body has it
    assert np.linalg.eigvalsh(pseudo_inertia(standard)[0]).min() < 0
    projected = project_consistent(standard[None], 1e-9)
    assert np.linalg.eigvalsh(pseudo_inertia(projected)[0]).min() >= 1e-9 * (1 - 1e-6)


def test_log_cholesky_covers_positive_definite_bodies_both_ways() -> None:
    rng = np.random.default_rng(3)
    theta = rng.normal(size=(5, 10))
    J = log_cholesky(theta)
    assert np.all(np.linalg.eigvalsh(J) > 0)
    assert np.allclose(log_cholesky_of(J), theta, atol=1e-12)
    assert np.allclose(J[:, 3, 3], np.exp(2 * theta[:, 0]))  # the mass is e^(2α)


def test_consistent_fit_recovers_physical_bodies_and_friction() -> None:
    rng = np.random.default_rng(5)
    truth = np.concatenate(
        [
            _box(2.0, (0.3, 0.2, 0.1), np.array([0.1, 0.0, 0.05])),
            _box(0.5, (0.1, 0.1, 0.4), np.array([0.0, 0.02, 0.2])),
            [0.7, 1.5],  # two parameters bounded below by 0
        ]
    )
    W = rng.normal(size=(400, truth.size))
    R = np.linalg.qr(np.column_stack([W, W @ truth]), mode="r")
    fitted = consistent_fit(R, 2, np.zeros(truth.size))
    assert np.allclose(fitted, truth, rtol=1e-5, atol=1e-7)


def test_consistent_fit_keeps_bodies_physical_where_least_squares_does_not() -> None:
    rng = np.random.default_rng(8)
    truth = np.concatenate([_box(1.0, (0.2, 0.2, 0.02), np.zeros(3)), [0.0]])
    W = rng.normal(size=(200, truth.size))
    y = W @ truth + 0.05 * rng.normal(size=200)  # noise on a thin plate and no friction
    least, *_ = np.linalg.lstsq(W, y, rcond=None)
    assert np.linalg.eigvalsh(pseudo_inertia(least[:10])[0]).min() < 0 or least[10] < 0
    fitted = consistent_fit(np.linalg.qr(np.column_stack([W, y]), mode="r"), 1, least)
    assert np.linalg.eigvalsh(pseudo_inertia(fitted[:10])[0]).min() > 0
    assert fitted[10] >= 0
    # no worse than the least squares restricted to physical bodies can be: close to it
    assert np.linalg.norm(W @ fitted - y) <= 1.05 * np.linalg.norm(W @ least - y) + 1e-9
