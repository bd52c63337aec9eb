"""Each joint's torque per ampere checked against the base wrench: the corrected least squares
recovers a known scale (also where the joint's torque is mostly its own friction), and the one
line names the joints that are off."""

from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.apps.identify.inertial_scale import scale_line, scale_off, torque_scale

N = 4000  # samples
SIGMA = 0.05  # the currents' noise, in torque


def _problem(rng: np.random.Generator, scales: tuple[float, float]) -> tuple[np.ndarray, float]:
    """R of ``[W | T | y]``: a load cell seeing three body parameters, two joints seeing them and
    their own friction column, measured through ``k_t·N`` given wrong by ``1/scale``.

    Joint 2's torque is mostly its friction (a wrist): its body part is a tenth of joint 1's.
    """
    body = np.array([2.0, -1.0, 0.5])
    friction = np.array([0.3, 3.0])
    wrench = rng.standard_normal((N, 3))
    rows = [np.hstack([wrench, np.zeros((N, 4)), (wrench @ body)[:, None]])]
    for j, (share, scale) in enumerate(zip((1.0, 0.1), scales, strict=True)):
        Y = share * rng.standard_normal((N, 3))
        F = np.sign(rng.standard_normal(N)) * rng.uniform(0.5, 1.0, N)
        measured = (Y @ body + friction[j] * F) / scale + SIGMA * rng.standard_normal(N)
        block = np.zeros((N, 8))
        block[:, :3], block[:, 3 + j], block[:, 5 + j], block[:, 7] = Y, F, measured, measured
        rows.append(block)
    R = np.linalg.qr(np.vstack(rows), mode="r")
    return R, SIGMA * np.sqrt(N)


@pytest.mark.parametrize("scales", [(1.0, 1.0), (0.5, 0.5), (1.2, 0.9)])
def test_the_scale_is_recovered_within_its_sigma(scales: tuple[float, float]) -> None:
    rng = np.random.default_rng(7)
    R, noise = _problem(rng, scales)
    independent = [0, 1, 2, 3, 4]
    c, std = torque_scale(R, independent, [5, 6], np.full(2, noise), dof=3 * N - 7)
    assert np.all(np.abs(c - np.array(scales)) < 4 * std)
    assert std[0] < 0.01 and std[1] > std[0]  # the wrist's own friction leaves it looser
    # without the correction the joint that is mostly friction would fit its own noise
    plain, _ = torque_scale(R, independent, [5, 6], np.zeros(2), dof=3 * N - 7)
    assert abs(plain[1] - scales[1]) > 4 * std[1]


def test_parameters_the_data_do_not_separate_determine_nothing() -> None:
    rng = np.random.default_rng(3)
    R, noise = _problem(rng, (1.0, 1.0))
    R[:, 1] = R[:, 0]  # two body columns the same: no unique fit, no scale reported
    c, std = torque_scale(R, [0, 1, 2, 3, 4], [5, 6], np.full(2, noise), dof=3 * N - 7)
    assert np.isnan(c).all() and np.isnan(std).all()


def test_the_line_names_the_joints_that_are_off() -> None:
    rows = [
        {"joint": "j1", "scale": 0.5, "std": 0.001},  # off
        {"joint": "j2", "scale": 1.004, "std": 0.001},  # 4σ but within 1 %: a data sheet's
        {"joint": "j3", "scale": 0.9, "std": 0.05},  # within 3σ
        {"joint": "j4", "scale": 2.0, "std": None},  # not determined
    ]
    assert [row["joint"] for row in scale_off(rows)] == ["j1"]
    line = scale_line(rows)
    assert "\n" not in line and "j1 0.5 ± 0.001" in line and "j2" not in line
    assert "allowed: within 1 %" in line
    agree = scale_line(rows[1:])
    assert "agrees" in agree and "largest σ 5 %" in agree
    assert "not determined" in scale_line(rows[3:])
