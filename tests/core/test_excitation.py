"""Fourier excitation within its limits, with exact derivatives (complex step, finite
differences), periodic over the run; trajectories from samples through the samples."""

from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.core.excitation import fourier_motion, fourier_series, trajectory_from_samples
from aaria_pin.errors import ParameterError

LIMITS = [(-1.0, 1.0), (-0.5, 1.5), (-2.0, 0.0), (-0.1, 0.1)]  # the last a prismatic rail [m]


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_fourier_motion_stays_within_its_limits_and_reaches_them(seed):
    qd_max = np.array([1.5, 1.0, 2.0, 0.2])
    qdd_max = np.array([5.0, 3.0, 4.0, 0.5])
    motion = fourier_motion(
        4, 20.0, 200.0, q_limits=LIMITS, qd_limits=qd_max, qdd_limits=qdd_max, seed=seed
    )
    lower, upper = np.array(LIMITS).T
    assert motion.q.shape == motion.qd.shape == motion.qdd.shape == (4001, 4)
    assert np.all(motion.q >= lower) and np.all(motion.q <= upper)
    assert np.all(np.abs(motion.qd) <= qd_max) and np.all(np.abs(motion.qdd) <= qdd_max)
    # each joint reaches 95 % of its tightest limit (the default fill)
    ratios = np.stack(
        [
            np.max(np.abs(motion.q - (lower + upper) / 2), axis=0) / ((upper - lower) / 2),
            np.max(np.abs(motion.qd), axis=0) / qd_max,
            np.max(np.abs(motion.qdd), axis=0) / qdd_max,
        ]
    ).max(axis=0)
    assert np.allclose(ratios, 0.95, rtol=1e-12)


def test_fourier_motion_is_periodic_over_the_run_and_reproducible():
    motion = fourier_motion(3, 30.0, 100.0, seed=7)  # default base frequency 0.1 Hz: 3 periods
    for x in (motion.q, motion.qd, motion.qdd):
        assert np.allclose(x[0], x[-1], rtol=0, atol=1e-12)
    assert np.array_equal(motion.q, fourier_motion(3, 30.0, 100.0, seed=7).q)
    assert not np.allclose(motion.q, fourier_motion(3, 30.0, 100.0, seed=8).q)
    short = fourier_motion(1, 7.0, 100.0, seed=0)  # 0.1 Hz does not fit 7 s: 1/7 Hz does
    assert np.allclose(short.q[0], short.q[-1], rtol=0, atol=1e-12)


def test_fourier_series_derivatives_by_complex_step():
    rng = np.random.default_rng(3)
    a, b = rng.standard_normal((2, 2, 5))
    offset = np.array([0.2, -0.3])
    time = np.linspace(0.0, 12.0, 97)
    h = 1e-20
    _, qd, qdd = fourier_series(a, b, offset, 0.13, time)
    q_step, qd_step, _ = fourier_series(a, b, offset, 0.13, time + 1j * h)
    assert np.allclose(q_step.imag / h, qd, rtol=1e-13, atol=1e-13)
    assert np.allclose(qd_step.imag / h, qdd, rtol=1e-13, atol=1e-13)
    # and the values against the formula written out for one joint and one harmonic
    w = 2 * np.pi * 0.13
    one = offset[0] + a[0, 0] / w * np.sin(w * time) - b[0, 0] / w * np.cos(w * time)
    q1, _, _ = fourier_series(a[:1, :1], b[:1, :1], offset[:1], 0.13, time)
    assert np.allclose(q1[:, 0], one, rtol=1e-14, atol=1e-14)


def test_fourier_motion_derivatives_are_those_of_q():
    motion = fourier_motion(2, 10.0, 2000.0, harmonics=4, seed=5)
    dt = 1 / 2000.0
    central = (motion.q[2:] - motion.q[:-2]) / (2 * dt)
    assert np.allclose(central, motion.qd[1:-1], rtol=0, atol=1e-5)
    central = (motion.qd[2:] - motion.qd[:-2]) / (2 * dt)
    assert np.allclose(central, motion.qdd[1:-1], rtol=0, atol=1e-4)


@pytest.mark.parametrize(
    ("kwargs", "parameter"),
    [
        ({"harmonics": 0}, "harmonics"),
        ({"harmonics": 60, "base_frequency": 1.0}, None),  # 60 Hz at 100 Hz: two parameters
        ({"q_limits": (1.0, -1.0)}, "q_limits"),
        ({"q_limits": [(0, 1)] * 3}, "q_limits"),
        ({"qd_limits": 0.0}, "qd_limits"),
        ({"qdd_limits": [1.0, np.nan]}, "qdd_limits"),
        ({"base_frequency": -1.0}, "base_frequency"),
        ({"fill": 1.5}, "fill"),
    ],
)
def test_fourier_motion_refuses_bad_input_in_one_line(kwargs, parameter):
    with pytest.raises(ParameterError) as error:
        fourier_motion(2, 10.0, 100.0, **kwargs)
    assert error.value.parameter == parameter
    assert "\n" not in str(error.value) and "allowed" in str(error.value)


def test_trajectory_from_samples_on_a_grid_keeps_q_and_differentiates():
    time = np.arange(801) / 200.0
    q = np.column_stack([np.sin(1.3 * time), 0.1 * np.cos(2.1 * time) + time**2 / 10])
    trajectory = trajectory_from_samples(time, q, rate=200.0)
    assert np.array_equal(trajectory.time, time) and np.array_equal(trajectory.q, q)
    qd = np.column_stack([1.3 * np.cos(1.3 * time), -0.21 * np.sin(2.1 * time) + time / 5])
    qdd = np.column_stack([-1.69 * np.sin(1.3 * time), -0.441 * np.cos(2.1 * time) + 0.2])
    assert np.allclose(trajectory.qd, qd, rtol=0, atol=1e-8)
    assert np.allclose(trajectory.qdd, qdd, rtol=0, atol=1e-5)


def test_trajectory_from_samples_resampled_passes_through_the_samples():
    rng = np.random.default_rng(0)
    given = 2.0 + np.sort(rng.choice(np.arange(1, 1000), 300, replace=False)) / 100.0
    given = np.concatenate([[2.0], given])  # 2 s … 12 s on a 100 Hz lattice, irregular
    q = np.sin(given) + 0.5 * given
    trajectory = trajectory_from_samples(given, q, rate=100.0)
    assert trajectory.time[0] == 0 and trajectory.time[1] == pytest.approx(0.01)
    at_samples = np.rint((given - given[0]) * 100).astype(int)
    assert np.allclose(trajectory.q[at_samples, 0], q, rtol=0, atol=1e-12)
    truth = np.sin(2.0 + trajectory.time) + 0.5 * (2.0 + trajectory.time)
    assert np.allclose(trajectory.q[:, 0], truth, rtol=0, atol=1e-6)


def test_trajectory_from_samples_with_smoothing_stays_within_the_noise():
    time = np.arange(1001) / 100.0
    noise = np.random.default_rng(1).normal(0.0, 1e-3, time.size)
    q = np.sin(time) + noise
    trajectory = trajectory_from_samples(time, q, rate=100.0, smoothing=1e-3)
    residual = trajectory.q[:, 0] - q
    assert np.sqrt(np.mean(residual**2)) <= 1e-3 * np.sqrt(1.001)  # FITPACK: s within 0.1 %
    assert np.sqrt(np.mean((trajectory.q[:, 0] - np.sin(time)) ** 2)) < 1e-3  # nearer the truth
    inner = slice(100, -100)
    assert np.max(np.abs(trajectory.qd[inner, 0] - np.cos(time[inner]))) < 0.02


def test_trajectory_from_samples_takes_given_derivatives_and_refuses_bad_input():
    time = np.arange(11) / 10.0
    q, qd, qdd = time**2, 2 * time, np.full(11, 2.0)
    trajectory = trajectory_from_samples(time, q, qd, qdd, rate=10.0)
    assert np.array_equal(trajectory.qd[:, 0], qd) and np.array_equal(trajectory.qdd[:, 0], qdd)
    bad_cases = [
        ((time[::-1], q), {}, "time"),
        ((time[:5], q[:5]), {}, "time"),
        ((time, np.where(time > 0.5, np.nan, q)), {}, "q"),
        ((time, q, qd[:5]), {}, "qd"),
        ((time, q), {"smoothing": -1.0}, "smoothing"),
        ((time, q), {"rate": 0.0}, "rate"),
    ]
    for args, extra, parameter in bad_cases:
        with pytest.raises(ParameterError) as error:
            trajectory_from_samples(*args, **{"rate": 10.0, **extra})
        assert error.value.parameter == parameter and "\n" not in str(error.value)
