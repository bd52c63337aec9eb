"""Torque sensors: the noise's variance passes a χ² test at 1 % against the configured σ (with
and without a resolution, Sheppard's Δ²/12), and the stored bias and scale reproduce the mean."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import chi2

import aaria_pin as ap
from aaria_pin.core.joint_sensors import TorqueSensorModel
from aaria_pin.core.record import RunRecord
from aaria_pin.core.run import RunSettings, simulate
from aaria_pin.core.torque_sensor import torque_reading

SIGMA = 0.02
"""The sensors' noise [N·m or N]."""


def _run(resolution: float) -> RunRecord:
    model = TorqueSensorModel(noise=SIGMA, bias=0.5, resolution=resolution, scale_error=0.02)
    settings = RunSettings(2.0, 500.0, noise=False, torque_sensor=model)
    return simulate(ap.preset_arm("aaria-fig2"), settings=settings, seeds=11)


def _residual(record: RunRecord) -> np.ndarray:
    """The reading less the scaled true torque and the stored bias: the noise (quantised)."""
    scale = record.tables["torque_sensor_scale"]
    bias = record.tables["torque_sensor_bias"]
    return record.tables["tau_measured"] - (1 + scale) * record.tau - bias


@pytest.mark.parametrize("resolution", [0.0, SIGMA / 2])
def test_the_noise_variance_passes_a_chi2_test_at_1_percent(resolution: float) -> None:
    residual = _residual(_run(resolution))
    variance = SIGMA**2 + resolution**2 / 12  # Sheppard: rounding adds Δ²/12
    n = residual.shape[0]
    low, high = chi2.ppf([0.005, 0.995], n - 1)
    for column in residual.T:  # each joint on its own
        statistic = (n - 1) * column.var(ddof=1) / variance
        assert low < statistic < high


def test_the_stored_bias_and_scale_reproduce_the_measured_mean() -> None:
    record = _run(0.0)
    bias, scale = record.tables["torque_sensor_bias"], record.tables["torque_sensor_scale"]
    assert (bias != 0).all() and (scale != 0).all() and (np.abs(scale) < 0.1).all()
    n = record.n_samples
    mean = (record.tables["tau_measured"] - (1 + scale) * record.tau).mean(axis=0)
    assert (np.abs(mean - bias) < 4 * SIGMA / np.sqrt(n)).all()
    wrong = (record.tables["tau_measured"] - record.tau).mean(axis=0)  # without the scale
    assert (np.abs(wrong - bias) > 4 * SIGMA / np.sqrt(n)).any()


def test_a_reading_by_hand() -> None:
    tau = np.array([[10.0, -2.0]])
    got = torque_reading(tau, np.array([0.1, 0.0]), np.array([0.04, 0.0]), np.array([0.5, 0.0]))
    np.testing.assert_allclose(got, [[11.0, -2.0]])  # 11.04 → 11.0 on the 0.5 grid
