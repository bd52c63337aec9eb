"""Fourier excitation within its limits, with exact derivatives (complex step, finite
differences), periodic over the run."""

from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.core.excitation import (
    FourierExcitation,
    check_joint_range,
    fourier_motion,
    fourier_series,
)
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
        ({"harmonics": 60, "base_frequency": 1.0}, "harmonics"),  # 60 Hz at 100 Hz: both named
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


def test_check_joint_range_names_the_first_sample_outside_its_joint_and_limit() -> None:
    time = np.array([0.0, 0.1, 0.2, 0.3])
    q = np.array([[0.0, 0.5], [0.2, 0.9], [-0.5, 1.2], [-1.5, 1.4]])
    limits = (np.array([-1.0, -2.0]), np.array([1.0, 1.0]))
    check_joint_range(time, np.clip(q, -1.0, 1.0), limits, ("a", "b"))  # at the limits: kept
    with pytest.raises(ParameterError) as caught:
        check_joint_range(time, q, limits, ("a", "b"))
    assert str(caught.value) == (
        "motion takes joint b to 1.2 at t = 0.2 s; allowed: within its limits [-2, 1] "
        "(beyond its upper limit 1)"
    )
    assert caught.value.parameter == "motion" and caught.value.element == "b"
    with pytest.raises(ParameterError, match=r"joint a to -1.5 at t = 0.3 s.*lower limit -1\)"):
        check_joint_range(time, q[:, :1], (limits[0][:1], limits[1][:1]), ("a",))


def test_a_fourier_excitation_s_range_is_checked_on_the_run_s_samples() -> None:
    # q = (1 / w) sin(w t), w = 2π: its peak 1/(2π) = 0.159 at t = 0.25 s, a sample at 100 Hz
    excitation = FourierExcitation(np.ones((1, 1)), np.zeros((1, 1)), np.zeros(1), 1.0)
    excitation.check_range(101, 100.0, (np.array([-0.16]), np.array([0.16])), ("j",))
    with pytest.raises(ParameterError, match=r"^motion takes joint j to 0.15\d* at t = 0.2\d* s"):
        excitation.check_range(101, 100.0, (np.array([-0.15]), np.array([0.15])), ("j",))
    with pytest.raises(ParameterError, match=r"to -0.15\d* at t = 0.7\d* s"):
        excitation.check_range(101, 100.0, (np.array([-0.15]), np.array([1.0])), ("j",))
