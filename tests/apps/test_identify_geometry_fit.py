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
