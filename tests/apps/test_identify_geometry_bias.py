"""The bias splines of the kinematic fit (issue 26): knot spacing, basis, projection; noisy arms."""

from __future__ import annotations

import numpy as np

from aaria_pin.apps.identify import identify_kinematics
from aaria_pin.apps.identify.geometry_bias import BiasModel, bias_basis, knot_spacing
from aaria_pin.core.imu_noise import ADIS16485, noise_attributes
from tests.apps.test_identify_geometry import _random_record, _tool_tip_error


def test_knot_spacing_where_the_walk_meets_the_averaged_noise() -> None:
    # by hand, ADIS16485 at 200 Hz: accelerometer white level 0.067 mg/√Hz·√100 and the
    # quantisation 0.25 mg/√12 in quadrature; walk 32 µg·√(2/100 s) per √s
    g = 9.80665
    level = np.hypot(0.067e-3 * g * 10.0, 0.25e-3 * g / np.sqrt(12.0))
    walk = 32e-6 * g * np.sqrt(2.0 / 100.0)
    gyro, accel = knot_spacing(noise_attributes(ADIS16485), 200.0)
    assert abs(accel - level / (walk * np.sqrt(200.0))) < 1e-9 * accel
    assert 10.0 < accel < 11.0 and 15.0 < gyro < 25.0
    # a model without in-run bias: one constant per channel
    flat = {**noise_attributes(ADIS16485), "accel_bias_stability_m_s2": 0.0}
    assert knot_spacing(flat, 200.0)[1] == np.inf
    assert bias_basis(np.linspace(0.0, 30.0, 7), 0.0, 30.0, np.inf).shape == (7, 1)


def test_basis_is_a_partition_of_unity_and_projects_a_spline_bias_off() -> None:
    time = np.linspace(0.0, 30.0, 3001)
    basis = bias_basis(time, 0.0, 30.0, 10.5)
    assert basis.shape == (3001, 2 + 3)  # two knot intervals, cubic
    assert np.allclose(basis.sum(axis=1), 1.0)
    model = BiasModel.at(time, (0.0, 30.0), (20.0, 10.5))
    rng = np.random.default_rng(1)
    # a drifting bias (a cubic over 30 s) on every channel of two IMUs goes entirely
    drift = np.polynomial.polynomial.polyval(time / 30.0, rng.standard_normal((2, 6, 4)))
    residual = np.moveaxis(drift, -1, 0)
    assert np.max(np.abs(model.project(residual, None))) < 1e-10
    # a 1 Hz signal keeps 99.7 % of its energy (a sine over 30 s projects little on cubics)
    wave = np.sin(2 * np.pi * time)[:, None, None] * np.ones((1, 2, 6))
    kept = model.project(wave, None)
    assert float(kept @ kept) > 0.997 * float(np.sum(wave**2))


def test_noisy_arms_within_a_centimetre_and_sigmas_covering() -> None:
    # random arms 4 (prismatic modules 1, 2, 6) and 6 (prismatic 3, revolute 4 and 5) with
    # ADIS16485 noise, 30 s at 200 Hz: 3.3 and 7.2 mm at the tool tip; 12 of their 15
    # determined DH parameters within 2σ of the truth
    inside = total = 0
    for k in (4, 6):
        table, record = _random_record(k, noise=True)
        result = identify_kinematics(record)
        assert result.link_types == tuple(int(t) for t in table[:6, 4])
        assert _tool_tip_error(result.table, record) < 0.01
        assert result.truth is not None
        inside += sum(v[0] for v in result.truth.coverage.values())
        total += sum(v[1] for v in result.truth.coverage.values())
    assert total >= 10 and inside >= 0.75 * total
