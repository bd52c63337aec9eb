from __future__ import annotations

import numpy as np
import pytest
from gimbal_oracle import gimbal_xyz_motion
from hypothesis import given, settings
from hypothesis import strategies as st

from aaria_pin.core.trajectory import (
    MAX_SAMPLES,
    MAX_STREAMED_SAMPLES,
    piece_times,
    sample_count,
    sample_times,
    sine_motion,
)
from aaria_pin.errors import ParameterError


def test_sample_grid_is_simulink_like() -> None:
    t = sample_times(1.0, 100)
    assert t.size == 101 and t[0] == 0.0 and t[-1] == pytest.approx(1.0)
    np.testing.assert_allclose(np.diff(t), 0.01)


@pytest.mark.parametrize(
    ("duration", "rate", "pattern"),
    [
        (0.0, 100, "duration is 0; allowed"),
        (-1, 100, "duration is -1; allowed"),
        (np.nan, 100, "duration is nan; allowed"),
        (1e9, 100, "duration is 1e"),
        (1.0, 0.0, "rate is 0; allowed"),
        (1.0, -5, "rate is -5; allowed"),
        (86_400, 100_000, "samples"),
        (0.001, 10, "1 sample"),
    ],
)
def test_bad_grids(duration: float, rate: float, pattern: str) -> None:
    with pytest.raises(ParameterError, match=pattern) as caught:
        sample_times(duration, rate)
    assert caught.value.parameter in {"duration", "rate"}
    assert caught.value.allowed
    assert caught.value.value in (duration, rate) or np.isnan(caught.value.value)


def test_a_run_held_whole_and_a_run_in_pieces_have_their_own_bounds() -> None:
    """The issue's run, 20 s at 100 kHz (2,000,001 samples): too long to hold, fine in pieces."""
    with pytest.raises(ParameterError, match="2000001 samples; allowed: at most 2000000 per run "
                       "held in memory") as caught:  # fmt: skip
        sample_count(20.0, 100_000.0)
    assert (caught.value.parameter, caught.value.value) == ("duration", 20.0)
    assert sample_count(20.0, 100_000.0, MAX_STREAMED_SAMPLES) == 2_000_001
    assert sample_count(19.99999, 100_000.0) == MAX_SAMPLES
    with pytest.raises(ParameterError, match="written in pieces") as caught:
        sample_count(86_400.0, 100_000.0, MAX_STREAMED_SAMPLES)  # 8.64e9 samples
    assert caught.value.allowed == (
        f"at most {MAX_STREAMED_SAMPLES} samples per run written in pieces (duration × rate)"
    )
    assert sample_count(86_400.0, 100_000.0, None) == 8_640_000_001  # an existing run's length


def test_piece_times_are_the_grid_s_samples() -> None:
    grid = sample_times(1.23, 977.0)
    assert grid.size == 1202  # 1.23 s at 977 Hz, both ends: floor(1.23 × 977) + 1
    for start, stop in [(0, 5), (17, 400), (1100, grid.size)]:
        by_hand = np.array([k / 977.0 for k in range(start, stop)])  # sample k at k / rate
        assert np.array_equal(piece_times(start, stop, 977.0), by_hand)
        assert np.array_equal(grid[start:stop], by_hand)
    np.testing.assert_allclose(piece_times(1000, 1001, 977.0), [1000 / 977.0], rtol=1e-15)


def test_error_fields_name_the_flag_in_the_cli() -> None:
    with pytest.raises(ParameterError) as caught:
        sample_times(1.0, -5.0)
    error = caught.value
    assert (error.parameter, error.value) == ("rate", -5.0)
    assert error.for_flag({"rate": "--rate"}).startswith("--rate is -5; allowed: 0 < rate")
    assert isinstance(error, ValueError)


def test_sine_derivatives_are_exact() -> None:
    t = np.linspace(0, 3, 7)
    h = 1e-5
    q, qd, qdd = sine_motion([0.4, 0.1], [0.2, 0.0], [1.3, 2.0], [0.5, 0.0], t)
    qp, _, _ = sine_motion([0.4, 0.1], [0.2, 0.0], [1.3, 2.0], [0.5, 0.0], t + h)
    qm, _, _ = sine_motion([0.4, 0.1], [0.2, 0.0], [1.3, 2.0], [0.5, 0.0], t - h)
    np.testing.assert_allclose(qd, (qp - qm) / (2 * h), atol=1e-8)
    np.testing.assert_allclose(qdd, (qp - 2 * q + qm) / h**2, atol=1e-4)


@settings(max_examples=50, deadline=None)
@given(
    angles=st.tuples(*[st.floats(-3.2, 3.2)] * 3) | st.just((0.3, np.pi / 2, -1.0)),
    rates=st.tuples(*[st.floats(-2, 2)] * 3),
    accels=st.tuples(*[st.floats(-2, 2)] * 3),
)
def test_gimbal_angular_velocity_and_acceleration_by_differences(angles, rates, accels) -> None:
    h = 1e-5
    a0, r0, c0 = (np.array(x, dtype=float) for x in (angles, rates, accels))

    def at(s: float):
        return gimbal_xyz_motion(
            (a0 + r0 * s + 0.5 * c0 * s * s)[None], (r0 + c0 * s)[None], c0[None]
        )

    (R, w, wd), (Rp, wp, _), (Rm, wm, _) = at(0.0), at(h), at(-h)
    S = R[0].T @ (Rp[0] - Rm[0]) / (2 * h)
    np.testing.assert_allclose(w[0], [S[2, 1], S[0, 2], S[1, 0]], atol=1e-6)
    np.testing.assert_allclose(wd[0], (wp[0] - wm[0]) / (2 * h), atol=1e-5)
    cx, sx = np.cos(a0[0]), np.sin(a0[0])
    np.testing.assert_allclose(
        R[0][:, 0],
        [
            np.cos(a0[1]) * np.cos(a0[2]),
            cx * np.sin(a0[2]) + sx * np.sin(a0[1]) * np.cos(a0[2]),
            sx * np.sin(a0[2]) - cx * np.sin(a0[1]) * np.cos(a0[2]),
        ],
        atol=1e-12,
    )
