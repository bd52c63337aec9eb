"""Planar two-link IK of the pick-place arm and its no-swing-through-the-pillar rule."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from aaria_pin.apps.arm.ik import elbow_move, plan_planar_move, planar_fk, planar_ik, wrap
from aaria_pin.errors import ParameterError

A, B = 0.40, 0.30


def _targets(n: int = 4000, seed: int = 1) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    r = np.concatenate([rng.uniform(A - B, A + B, n), [A - B, A + B]])  # rims included
    phi = rng.uniform(-np.pi, np.pi, r.size)
    return r * np.cos(phi), r * np.sin(phi)


def test_both_branches_reach_every_target_of_the_annulus() -> None:
    x, y = _targets()
    left, right = planar_ik(x, y, A, B)
    for branch in (left, right):
        np.testing.assert_allclose(planar_fk(branch.alpha, branch.beta, A, B)[..., 0], x, atol=1e-7)
        np.testing.assert_allclose(planar_fk(branch.alpha, branch.beta, A, B)[..., 1], y, atol=1e-7)
    assert np.all(left.beta >= 0) and np.all(right.beta <= 0)
    assert np.all(np.abs(left.beta) <= np.pi) and np.all(np.abs(right.beta) <= np.pi)
    # mirrored about the target direction: the upper arms lie symmetric about x
    heading = np.arctan2(y, x)
    inside = (np.hypot(x, y) > A - B + 1e-6) & (np.hypot(x, y) < A + B - 1e-6)
    np.testing.assert_allclose(
        wrap(left.alpha - heading)[inside], -wrap(right.alpha - heading)[inside], atol=1e-7
    )


def test_rims_give_straight_and_folded_arms() -> None:
    left, right = planar_ik(A + B, 0.0, A, B)
    assert abs(float(left.beta)) < 1e-6 and abs(float(right.beta)) < 1e-6
    left, right = planar_ik(0.0, A - B, A, B)
    assert float(left.beta) == pytest.approx(np.pi) and float(right.beta) == pytest.approx(-np.pi)
    np.testing.assert_allclose(planar_fk(left.alpha, left.beta, A, B), [0.0, A - B], atol=1e-12)


@pytest.mark.parametrize("r", [A - B - 1e-6, A + B + 1e-6, 2.0, 0.0])
def test_targets_outside_the_annulus_are_refused_naming_it(r: float) -> None:
    with pytest.raises(
        ParameterError, match=r"outside the reachable annulus 0\.1 m <= r <= 0\.7 m"
    ):
        planar_ik(r, 0.0, A, B)


@settings(max_examples=300, deadline=None)
@given(
    st.floats(-1e-10, 1e-10),
    st.sampled_from([A - B, A + B]),
    st.floats(-np.pi, np.pi),
)
def test_round_trip_at_the_annulus_rims(dr: float, r: float, phi: float) -> None:
    x, y = (r + dr) * np.cos(phi), (r + dr) * np.sin(phi)
    for branch in planar_ik(x, y, A, B):
        np.testing.assert_allclose(planar_fk(branch.alpha, branch.beta, A, B), [x, y], atol=2e-5)


def report_rule(current_deg: float, goal_deg: float) -> float:
    """The report's MATLAB (section 4.2.9), line by line, with its β0 > 0 typo fixed."""
    d = np.fmod(goal_deg - current_deg, 360.0)  # MATLAB rem
    if current_deg <= 0:
        if d > 0 and abs(d) > abs(180 - current_deg):
            d -= 360
        elif d < 0 and abs(d) > abs(180 + current_deg):
            d += 360
    else:
        if d > 0 and abs(d) > abs(180 - current_deg):
            d -= 360
        elif d < 0 and abs(d) > abs(180 + current_deg):
            d += 360
    return float(d)


def _never_crosses(beta0: float, turn: float) -> bool:
    path = beta0 + np.linspace(0.0, 1.0, 2001) * turn
    return bool(np.all(np.abs(path) <= np.pi + 1e-12))


def test_forearm_never_swings_through_the_pillar_over_a_sweep() -> None:
    grid = np.radians(np.concatenate([np.arange(-180.0, 181.0, 7.5), [-179.999, 179.999]]))
    for b0 in grid:
        for b1 in grid:
            turn = float(elbow_move(b0, b1))
            assert _never_crosses(b0, turn)
            assert float(wrap(b0 + turn - b1)) == pytest.approx(0.0, abs=1e-12)
            if abs(b1) < np.pi:  # (a goal of exactly ±180°: the report turns the long way)
                report = report_rule(np.degrees(b0), np.degrees(b1))
                assert np.degrees(turn) == pytest.approx(report)


def test_planned_moves_keep_the_forearm_on_its_side() -> None:
    rng = np.random.default_rng(5)
    alpha, beta = 0.0, np.pi / 2
    for _ in range(500):
        r, phi = rng.uniform(A - B, A + B), rng.uniform(-np.pi, np.pi)
        branch = str(rng.choice(["left", "right", "nearest"]))
        goal = plan_planar_move(alpha, beta, r * np.cos(phi), r * np.sin(phi), A, B, branch)  # type: ignore[arg-type]
        assert _never_crosses(beta, float(goal.beta) - beta)
        np.testing.assert_allclose(
            planar_fk(goal.alpha, goal.beta, A, B), [r * np.cos(phi), r * np.sin(phi)], atol=1e-7
        )
        assert abs(float(goal.alpha) - alpha) <= np.pi + 1e-12  # the shoulder goes the short way
        alpha, beta = float(goal.alpha), float(goal.beta)


@settings(max_examples=500, deadline=None)
@given(st.floats(np.pi - 1e-3, np.pi), st.floats(np.pi - 1e-3, np.pi), st.booleans(), st.booleans())
def test_no_swing_through_near_180_degrees(b0: float, b1: float, neg0: bool, neg1: bool) -> None:
    b0, b1 = (-b0 if neg0 else b0), (-b1 if neg1 else b1)
    turn = float(elbow_move(b0, b1))
    assert _never_crosses(b0, turn)
    assert float(wrap(b0 + turn - b1)) == pytest.approx(0.0, abs=1e-12)
    if neg0 != neg1 and max(abs(b0), abs(b1)) < np.pi:  # across the pillar: the long way round
        assert abs(turn) >= 2 * np.pi - 2e-3


def test_an_elbow_already_past_the_pillar_is_refused() -> None:
    with pytest.raises(ParameterError, match=r"allowed: \[-pi, pi\]") as error:
        elbow_move(3.5, 0.0)
    assert error.value.parameter == "beta0"
    with pytest.raises(ParameterError, match="goal elbow angle") as error:
        elbow_move(0.0, -4.0)
    assert error.value.parameter == "beta1"
