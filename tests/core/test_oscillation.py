"""The span a joint table row moves its joint over (``aaria_pin.core.oscillation.row_span``)."""

from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.core.oscillation import RANGE_TOLERANCE, row_span


@pytest.mark.parametrize(
    ("kind", "expected"),
    [
        ("revolute", (0.5, -0.3, 0.7, "rad")),
        ("continuous", (0.5, -0.3, 0.7, "rad")),
        ("prismatic", (0.25, -0.05, 0.45, "m")),
    ],
)
def test_the_amplitude_of_the_joints_kind_moves_it_about_the_bias(
    kind: str, expected: tuple[float, float, float, str]
) -> None:
    span = row_span(np.array([-0.5, 0.25, 0.2, 1.0, 0.0]), kind)
    assert span.unit == expected[3]
    np.testing.assert_allclose(span[:3], expected[:3], rtol=0, atol=1e-15)


def test_a_span_leaves_a_range_only_past_the_tolerance() -> None:
    span = row_span(np.array([0.5, 0.0, 0.0, 1.0, 0.0]), "revolute")
    assert not span.leaves(-0.5, 0.5)
    assert not span.leaves(-0.5 + RANGE_TOLERANCE / 2, 0.5)
    assert span.leaves(-0.4, 0.5)
    assert span.leaves(-0.5, 0.4)
