"""examples/baseline_state.py: the link types from the IMUs alone, q per joint kind."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("torch")

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture(autouse=True)
def _examples_on_path(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.syspath_prepend(str(EXAMPLES))


def test_invariants_tell_the_link_types_of_a_simulated_arm() -> None:
    """Flags where a module is present; the rate norm kept across prismatic joints only."""
    from baseline_state import invariants

    from aaria_pin.ml import OnlineRuns

    seen: set[int] = set()
    for seed in (1, 2, 3):
        run = OnlineRuns.defaults(1, seed=seed, duration=2.0)[0]
        types = np.rint(run["senSenDH"][:6, 4]).astype(int)
        out = invariants(run["imu"][None])[0]  # (T, 12)
        assert out.shape == (len(run["imu"]), 12)
        assert np.array_equal(out[0, :6] > 0, types > 0)
        spread = np.sqrt((out[:, 6:] ** 2).mean(axis=0))
        assert (spread[types == 0] == 0).all()
        assert (spread[types == 2] < 0.005).all()  # the gyros' noise [rad/s]
        assert (spread[types == 1] > 0.01).all()
        seen |= set(types.tolist())
    assert seen == {0, 1, 2}  # the seeds give every kind (the checks above are not empty)


def test_a_prediction_takes_the_value_of_the_predicted_type() -> None:
    from baseline_state import predicted_q

    stats = np.array([[0.1, 0.5], [0.0, 0.05]])  # mean, std: revolute [rad], prismatic [m]
    values = np.stack([np.full((6, 4), 2.0), np.full((6, 4), -1.0)])  # (kind, joint, T)
    logits = np.zeros((6, 3))
    logits[[0, 3], 1] = 1.0  # revolute
    logits[[1, 4], 2] = 1.0  # prismatic
    logits[[2, 5], 0] = 1.0  # empty
    q = predicted_q({"q": values, "type": logits}, stats)
    assert q.shape == (4, 6)
    assert np.allclose(q[:, [0, 3]], 2.0 * 0.5 + 0.1)
    assert np.allclose(q[:, [1, 4]], -0.05)
    assert (q[:, [2, 5]] == 0).all()
