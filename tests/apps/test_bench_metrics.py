"""The benchmark metrics against numbers worked out by hand on tiny arrays."""

from __future__ import annotations

import math

import numpy as np
import pytest

from aaria_pin.apps.bench_tasks.metrics import (
    relative_rms,
    relative_rms_summary,
    rms_per_joint,
    share_summary,
)


def test_relative_rms_is_the_error_rms_over_the_truth_rms() -> None:
    truth = np.array([[3.0, 4.0]])  # RMS sqrt(12.5)
    assert relative_rms(truth, truth + 1.0) == pytest.approx(1.0 / math.sqrt(12.5))
    assert relative_rms(truth, truth) == 0.0
    assert relative_rms(truth, np.zeros_like(truth)) == pytest.approx(1.0)


def test_relative_rms_of_a_zero_truth() -> None:
    zeros = np.zeros((2, 3))
    assert relative_rms(zeros, zeros) == 0.0
    assert relative_rms(zeros, zeros + 1.0) == math.inf


def test_relative_rms_summary() -> None:
    summary = relative_rms_summary([0.1, 0.2, 0.6])
    assert summary["relative_rms_median"] == pytest.approx(0.2)
    assert summary["relative_rms_mean"] == pytest.approx(0.3)
    assert summary["relative_rms_max"] == pytest.approx(0.6)
    assert relative_rms_summary([math.inf])["relative_rms_max"] is None  # JSON: not finite


def test_rms_per_joint_counts_each_kind_apart() -> None:
    truths = [np.zeros((2, 2)), np.zeros((2, 2))]
    predictions = [np.array([[1.0, 2.0], [1.0, 2.0]]), np.array([[3.0, 0.0], [3.0, 0.0]])]
    kinds = [np.array([1, 2]), np.array([1, 1])]
    by_kind = rms_per_joint(truths, predictions, kinds)
    # column 0, kind 1 in both runs: (1 + 1 + 9 + 9) / 4 = 5; column 1: kind 2 in run 0 (4),
    # kind 1 in run 1 (0)
    assert by_kind[1] == pytest.approx([math.sqrt(5.0), 0.0])
    assert by_kind[2][0] is None
    assert by_kind[2][1] == pytest.approx(2.0)


def test_share_summary() -> None:
    assert share_summary([True, False, True, True]) == 0.75
    assert share_summary([]) == 0.0
