"""Tests of the kinematic fit's moves along its null directions (geometry_fit)."""

from __future__ import annotations

import numpy as np

from aaria_pin.apps.identify.geometry_fit import non_negative_lengths, shortest_lengths


def test_shortest_lengths_stops_at_the_first_length_reaching_zero() -> None:
    # lengths 3 and 4 m move together (one null direction, with an angle along): the sum of
    # squares (3 + s)² + (4 + s)² is smallest at s = -3.5, where the first length is negative;
    # the smallest with both non-negative is at s = -3: lengths 0 and 1
    x = np.array([3.0, 0.2, 4.0])
    basis = np.array([[1.0, 0.5, 1.0]])
    moved = shortest_lengths(x, basis, [0, 2])
    np.testing.assert_allclose(moved, [0.0, 0.2 - 1.5, 1.0], atol=1e-7)


def test_shortest_lengths_of_an_unconstrained_minimum() -> None:
    # two lengths trading off (a + b fixed at 2): both 1
    moved = shortest_lengths(np.array([5.0, -3.0]), np.array([[1.0, -1.0]]), [0, 1])
    np.testing.assert_allclose(moved, [1.0, 1.0], atol=1e-7)


def test_no_null_direction_keeps_the_parameters() -> None:
    x = np.array([5.0, 6.0])
    assert shortest_lengths(x, np.zeros((0, 2)), [0, 1]) is x
    np.testing.assert_array_equal(non_negative_lengths(x, np.zeros((0, 2)), [0, 1]), x)


def test_shorten_walks_equivalent_tables_to_short_lengths() -> None:
    # two prismatic modules and the tool: the lengths a1, a2, a7 and the link IMUs' positions
    # trade off along null directions; from a table 3 m longer along them (same signals) the
    # walk comes back to lengths no longer than the truth's with the signals still fitted
    from aaria_pin.apps.identify.geometry_fit import WeightedFit, deficiencies
    from aaria_pin.apps.identify.geometry_model import ArmLayout, KinematicData, predict_signals

    rng = np.random.default_rng(5)
    time = np.linspace(0.0, 6.0, 240)
    waves = [np.sin(f * time + p) for f, p in rng.uniform(0.5, 3.0, (6, 2))]
    omega = 0.5 * np.column_stack(waves[:3])
    omega_dot = np.gradient(omega, time, axis=0)
    force = np.column_stack([0.1 * waves[3], 0.2 * waves[4], 9.81 + 0.1 * waves[5]])
    q = 0.2 * np.column_stack([np.sin(1.3 * time), np.cos(0.7 * time)])
    qd, qdd = np.gradient(q, time, axis=0), np.gradient(np.gradient(q, time, axis=0), time, axis=0)
    data = KinematicData(omega, omega_dot, force, q, qd, qdd)
    layout = ArmLayout((1, 2), ("prismatic", "prismatic"), ((1,), (2,)), 3)
    # module 2 turned half a turn: its x axis against module 1's (a1 - a2 is what shows)
    truth = np.array([0.4, 0.3, 0.5, 0.0, np.pi, 0.4, 0.3, 0.1, 0.2, -0.3, 0.05, 0.0, 0.02])
    truth = np.concatenate([truth, [0.2, 0.1, -0.1, 0.0, 0.03, 0.01]])
    measured, _ = predict_signals(truth, layout, data)
    lengths = [2, 5, 6]
    fit = WeightedFit(layout, data, measured, np.ones(6), lengths)
    names = [f"p{i}" for i in range(layout.n_params)]
    index = np.arange(time.size)
    _, _, jac, _ = fit.fit(truth, truth, index, 0, biases=False)
    basis = deficiencies(jac, names, layout.n_dh)[2]
    assert basis.shape[0] >= 1
    far = truth.copy()
    for _ in range(12):  # 3 m along the first null direction, kept on the equivalent tables
        direction = (
            basis[0] * np.sign(np.sum(basis[0][lengths])) / np.max(np.abs(basis[0][lengths]))
        )
        step = far + 0.25 * direction
        far, _, jac, _ = fit.fit(step, step, index, 20, biases=False)
        basis = deficiencies(jac, names, layout.n_dh)[2]
    assert np.max(far[lengths]) > 2.0 and fit.cost(far, index) < 1e-12
    short = fit.shorten(far, basis, names, index)
    assert np.all(short[lengths] >= -1e-9)
    assert np.sum(short[lengths] ** 2) <= np.sum(truth[lengths] ** 2) + 1e-6
    assert fit.cost(short, index) < 1e-10
