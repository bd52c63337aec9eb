"""A warm start of the kinematic identification (issue 27): a start table, its checks, its fallback.

On a noise-free run of the ``aaria-fig2`` preset: the true table as the start ends at the truth
from that start alone (the closed-form start is not built); a wrong one
(link types swapped, lengths 0.5 m longer, angles a quarter turn off) ends above the noise floor
and the cold path gives the result, the very table of a cold start. Where the detection of the
link types is made unsure, the data decide between its kinds and the table's, whichever is
wrong.
"""

from __future__ import annotations

import importlib

import numpy as np
import pytest

from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.apps.identify import geometry_warm, identify_kinematics
from aaria_pin.apps.identify.geometry_input import ArmSignals
from aaria_pin.apps.identify.geometry_model import ArmLayout
from aaria_pin.apps.identify.geometry_result import KinematicIdentification
from aaria_pin.apps.identify.geometry_warm import checked_start, start_kinds
from aaria_pin.core.record import RunRecord
from aaria_pin.errors import ParameterError

TRUTH = np.asarray(get_preset("aaria-fig2").table, dtype=float)
_SWAP = {"revolute": "prismatic", "prismatic": "revolute"}


@pytest.fixture(scope="module")
def record() -> RunRecord:
    preset = get_preset("aaria-fig2")
    return simulate_run(
        preset.table, preset.joint_table, preset.base_table, duration=4.0, rate=50.0, noise=False
    )


@pytest.fixture(scope="module")
def cold(record: RunRecord) -> KinematicIdentification:
    return identify_kinematics(record)


def test_a_start_at_the_truth_ends_at_the_truth_from_that_start_alone(
    record: RunRecord, cold: KinematicIdentification
) -> None:
    warm = identify_kinematics(record, start=TRUTH)
    assert warm.link_types == tuple(int(t) for t in TRUTH[:6, 4])
    assert warm.truth is not None and warm.truth.tool_tip_max < 1e-4
    assert (warm.fit["start"], warm.fit["starts"], warm.fit["closed_form"]) == (
        "start table",
        1,
        False,
    )
    assert cold.fit["start"] == "closed form" and cold.fit["closed_form"] is True
    # the table's fit needs no more Levenberg–Marquardt iterations than the cold one
    steps = warm.fit["iterations"] + warm.fit["walk_iterations"]
    assert steps <= cold.fit["iterations"] + cold.fit["walk_iterations"]


def test_a_wrong_start_falls_back_to_the_cold_table(
    record: RunRecord, cold: KinematicIdentification
) -> None:
    wrong = TRUTH.copy()
    used = wrong[:6, 4] > 0
    wrong[:6, 4][used] = 3 - wrong[:6, 4][used]  # revolute <-> prismatic
    wrong[:7, 1] += 0.5
    wrong[:6, 3] += 0.5
    wrong[:6, 0] += np.pi / 2
    warm = identify_kinematics(record, start=wrong)
    assert warm.fit["start"] == "closed form" and warm.fit["starts"] == 2
    assert warm.fit["link_types_from_start"] == []  # the detection was sure of every module
    np.testing.assert_array_equal(warm.table, cold.table)


def test_the_table_decides_a_link_type_only_where_the_detection_is_unsure() -> None:
    table = np.zeros((8, 5))
    table[:3, 4] = [2, 2, 1]
    detected = (("revolute", 0.6), ("revolute", 0.97), ("prismatic", 0.3))
    kinds, decided = start_kinds((1, 2, 3), detected, table)
    assert kinds == ("prismatic", "revolute", "revolute")
    assert decided == (1, 3)
    table[0, 4] = 0  # an empty row for a moving module is not obeyed
    assert start_kinds((1,), detected[:1], table) == (("revolute",), ())


def test_an_unsure_wrong_detection_yields_to_the_table_the_data_prefer(
    record: RunRecord, monkeypatch: pytest.MonkeyPatch
) -> None:
    # the detection made wrong and unsure on every module (statistic 0.5): the true table's
    # link types differ from it everywhere, and their closed form fits the signals better
    geometry = importlib.import_module("aaria_pin.apps.identify.geometry")
    real = geometry.joint_kinds

    def unsure(
        signals: ArmSignals, layout: ArmLayout, base: int, qd: np.ndarray
    ) -> tuple[tuple[str, float], ...]:
        return tuple((_SWAP[kind], 0.5) for kind, _ in real(signals, layout, base, qd))

    monkeypatch.setattr(geometry, "joint_kinds", unsure)
    warm = identify_kinematics(record, start=TRUTH)
    assert warm.link_types == tuple(int(t) for t in TRUTH[:6, 4])
    moving = [module for module in range(1, 7) if TRUTH[module - 1, 4] > 0]
    assert warm.fit["link_types_from_start"] == moving
    assert warm.truth is not None and warm.truth.tool_tip_max < 1e-4


def test_an_unsure_right_detection_stays_against_a_wrong_table(
    record: RunRecord, cold: KinematicIdentification, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(geometry_warm, "UNSURE", 0.6)  # every statistic is unsure
    wrong = TRUTH.copy()
    used = wrong[:6, 4] > 0
    wrong[:6, 4][used] = 3 - wrong[:6, 4][used]  # revolute <-> prismatic
    warm = identify_kinematics(record, start=wrong)
    assert warm.link_types == tuple(int(t) for t in TRUTH[:6, 4])
    assert warm.fit["link_types_from_start"] == []
    assert warm.truth is not None and cold.truth is not None
    assert warm.truth.tool_tip_max < max(1e-4, 2 * cold.truth.tool_tip_max)


@pytest.mark.parametrize(
    ("change", "wanted"),
    [
        (lambda t: t[:7], "start is a table of shape (7, 5); allowed: 8 × 5"),
        (lambda t: np.where(np.arange(5) == 1, np.nan, t), "start row 1, column 2 is nan"),
        (lambda t: np.where(np.arange(5) == 4, 3.0, t), "start row 1, column 5 (link type) is 3"),
        (lambda t: "a table", "start is str; allowed: an 8 × 5 table of real numbers"),
    ],
)
def test_bad_start_tables_are_refused_in_one_line(change: object, wanted: str) -> None:
    with pytest.raises(ParameterError) as caught:
        checked_start(change(TRUTH.copy()))  # type: ignore[operator]
    assert caught.value.parameter == "start"
    assert str(caught.value).startswith(wanted) and "\n" not in str(caught.value)
    np.testing.assert_array_equal(checked_start(TRUTH), TRUTH)
