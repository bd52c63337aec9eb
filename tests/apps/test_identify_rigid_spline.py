"""Uniform B-spline design matrices of the rigid-pair fit: cubics reproduced, derivatives exact."""

from __future__ import annotations

import numpy as np
from scipy.sparse.linalg import lsqr

from aaria_pin.apps.identify.rigid_spline import coefficient_count, fit_spline, spline_basis


def test_a_cubic_is_reproduced_with_its_derivatives() -> None:
    start, interval = 0.3, 0.1
    count = coefficient_count(2.0, interval, 3)
    samples = np.linspace(start, start + 2.0, 301)
    cubic = np.polynomial.Polynomial([0.5, -1.0, 2.0, 0.7])
    basis = spline_basis(samples, start, interval, count, 3)
    coefficients = lsqr(basis, cubic(samples - start), atol=1e-14, btol=1e-14)[0]
    at = np.linspace(start + 0.01, start + 1.99, 57)
    for derivative in range(3):
        values = spline_basis(at, start, interval, count, 3, derivative) @ coefficients
        expected = cubic.deriv(derivative)(at - start)
        np.testing.assert_allclose(values, expected, atol=1e-8)


def test_rows_are_a_partition_of_unity() -> None:
    basis = spline_basis(np.linspace(0.0, 1.0, 41), 0.0, 0.25, 7, 3)
    np.testing.assert_allclose(np.asarray(basis.sum(axis=1)).ravel(), 1.0)
    assert basis.getnnz(axis=1).max() == 4
    slope = spline_basis(np.linspace(0.0, 1.0, 41), 0.0, 0.25, 7, 3, 1)
    np.testing.assert_allclose(np.asarray(slope.sum(axis=1)).ravel(), 0.0, atol=1e-12)


def test_linear_and_constant_bases() -> None:
    assert coefficient_count(20.0, np.inf, 1) == 1
    assert coefficient_count(20.0, 5.0, 1) == 5
    constant = spline_basis(np.linspace(0.0, 20.0, 9), 0.0, np.inf, 1, 1)
    np.testing.assert_array_equal(constant.toarray(), np.ones((9, 1)))
    hats = spline_basis(np.array([0.0, 2.5, 5.0, 20.0]), 0.0, 5.0, 5, 1).toarray()
    np.testing.assert_allclose(hats[1, :2], [0.5, 0.5])
    np.testing.assert_allclose(hats[:, 0], [1.0, 0.5, 0.0, 0.0])
    np.testing.assert_allclose(hats[3, 4], 1.0)


def test_fit_spline_recovers_a_cubic_per_column() -> None:  # to its vanishing ridge
    times = np.linspace(0.0, 3.0, 301)
    values = np.column_stack([times**3 - 2 * times, np.sin(0.0 * times) + 4.0])
    count = coefficient_count(3.0, 0.05, 3)
    coefficients = fit_spline(times, values, 0.0, 0.05, count)
    assert coefficients.shape == (count, 2)
    at = np.linspace(0.1, 2.9, 29)
    np.testing.assert_allclose(
        spline_basis(at, 0.0, 0.05, count, 3) @ coefficients[:, 0], at**3 - 2 * at, atol=1e-5
    )
    np.testing.assert_allclose(
        spline_basis(at, 0.0, 0.05, count, 3, 1) @ coefficients[:, 1], 0.0, atol=1e-5
    )
