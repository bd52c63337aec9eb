"""Trajectories from samples: through the samples, derivatives against the analytic ones,
bad input refused in one line naming its parameter."""

from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.core.sampled_motion import trajectory_from_samples
from aaria_pin.errors import ParameterError


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


def test_fit_samples_matches_named_columns_and_fills_a_mimic_joint_from_its_leader():
    from aaria_pin.core.sampled_motion import GivenSamples, JointColumns, fit_samples

    joints = JointColumns(("a", "b", "finger"), (0, 1), {2: (1, -0.5, 0.01)})
    time = np.arange(21) / 10.0
    q = np.column_stack([0.1 * time, np.sin(time)])  # named b, a: the file's order
    given = GivenSamples("motion.csv", time, q[:, ::-1].copy(), names=("b", "a"))
    trajectory, duration, rate = fit_samples(given, joints)
    assert (duration, rate) == (2.0, 10.0)  # the samples' own span and steps
    np.testing.assert_array_equal(trajectory.q[:, 0], 0.1 * time)
    np.testing.assert_array_equal(trajectory.q[:, 1], np.sin(time))
    np.testing.assert_allclose(trajectory.q[:, 2], -0.5 * np.sin(time) + 0.01, rtol=0, atol=1e-15)
    np.testing.assert_allclose(trajectory.qd[:, 2], -0.5 * trajectory.qd[:, 1], rtol=0, atol=0)
    shorter, duration, _ = fit_samples(given, joints, duration=1.0)
    assert duration == 1.0 and shorter.q.shape == (11, 3)


def test_fit_samples_refuses_columns_that_do_not_fit_the_robot_in_one_line():
    from aaria_pin.core.sampled_motion import GivenSamples, JointColumns, fit_samples
    from aaria_pin.errors import InputFileError

    joints = JointColumns(("a", "b", "c"), (0, 2))
    time = np.arange(11) / 10.0
    cases = [
        (GivenSamples("f", time, np.zeros((11, 4))), "has 4 joint columns; allowed: 2 or 3"),
        (GivenSamples("f", time, np.zeros((11, 1)), names=("z",)), "joint 'z' is not"),
        (GivenSamples("f", time, np.zeros((11, 1)), names=("a",)), "no column for joint c"),
    ]
    for given, message in cases:
        with pytest.raises(InputFileError) as error:
            fit_samples(given, joints)
        assert message in str(error.value) and "\n" not in str(error.value)
        assert error.value.parameter == "given"
    with pytest.raises(ParameterError) as error:
        fit_samples(GivenSamples("f", time, np.zeros((11, 3))), joints, duration=5.0)
    assert error.value.parameter == "duration"
