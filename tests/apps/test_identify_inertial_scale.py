"""Each joint's torque per ampere checked against the base wrench: the corrected least squares
recovers a known scale (also where the joint's torque is mostly its own friction), and the one
line names the joints that are off."""

from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.apps.identify.inertial_scale import scale_line, scale_off, torque_scale

N = 2000  # samples per signal
SIGMA = 0.05  # the currents' noise, in torque
WRENCH_SIGMA = 0.02  # the load cell's (another noise: the σ must not assume one for all)
INDEPENDENT = [0, 1, 2, 3, 4]


def _problem(
    rng: np.random.Generator,
    scales: tuple[float, float],
    offsets: tuple[float, float] = (0.0, 0.0),
) -> list[np.ndarray]:
    """Each signal's R of ``[W | 1 1 | y]``: a load cell seeing three body parameters (three
    signals), two joints seeing them and their own friction column, measured through ``k_t·N``
    given wrong by ``1/scale`` and with a constant current offset.

    Joint 2's torque is mostly its friction (a wrist): its body part is a tenth of joint 1's.
    """
    body = np.array([2.0, -1.0, 0.5])
    friction = np.array([0.3, 3.0])
    wrench = rng.standard_normal((N, 3))
    signals = []
    for _ in range(3):
        block = np.zeros((N, 8))
        block[:, :3] = wrench
        block[:, 7] = wrench @ body + WRENCH_SIGMA * rng.standard_normal(N)
        signals.append(block)
    for j, (share, scale) in enumerate(zip((1.0, 0.1), scales, strict=True)):
        Y = share * rng.standard_normal((N, 3))
        F = np.sign(rng.standard_normal(N)) * rng.uniform(0.5, 1.0, N)
        noise = SIGMA * rng.standard_normal(N)
        block = np.zeros((N, 8))
        block[:, :3], block[:, 3 + j], block[:, 5 + j] = Y, F, 1.0
        block[:, 7] = (Y @ body + friction[j] * F) / scale + offsets[j] + noise
        signals.append(block)
    return [np.linalg.qr(block, mode="r") for block in signals]


@pytest.mark.parametrize(
    ("scales", "offsets"),
    [((1.0, 1.0), (0.0, 0.0)), ((0.5, 0.5), (0.0, 0.0)), ((1.2, 0.9), (0.3, -0.2))],
)
def test_the_scale_is_recovered_within_its_sigma(
    scales: tuple[float, float], offsets: tuple[float, float]
) -> None:
    factors = _problem(np.random.default_rng(7), scales, offsets)
    c, std = torque_scale(factors, 3, INDEPENDENT, N)
    assert np.all(np.abs(c - np.array(scales)) < 4 * std)
    assert std[0] < 0.01 and std[1] > std[0]  # the wrist's own friction leaves it looser


def test_a_current_offset_is_not_read_as_a_scale() -> None:
    # an offset of a tenth of joint 1's torque: the constant column takes it, c stays right
    rng = np.random.default_rng(11)
    offset = torque_scale(_problem(rng, (1.0, 1.0), (0.3, 0.3)), 3, INDEPENDENT, N)
    rng = np.random.default_rng(11)
    plain = torque_scale(_problem(rng, (1.0, 1.0)), 3, INDEPENDENT, N)
    assert np.allclose(offset[0], plain[0], rtol=1e-9) and np.allclose(offset[1], plain[1])


def test_the_sigma_is_honest_over_many_runs() -> None:
    # the right k_t on both joints: (c − 1)/σ is a unit normal, so a 3σ test is a 0.3 % alarm
    z = []
    for seed in range(200):
        c, std = torque_scale(_problem(np.random.default_rng(seed), (1.0, 1.0)), 3, INDEPENDENT, N)
        z.append((c - 1.0) / std)
    z = np.array(z)
    assert np.all((0.85 < z.std(axis=0)) & (z.std(axis=0) < 1.15)), z.std(axis=0)
    assert np.all(np.abs(z.mean(axis=0)) < 0.25)
    assert np.mean(np.abs(z) > 3) < 0.01


def test_parameters_the_data_do_not_separate_determine_nothing() -> None:
    factors = _problem(np.random.default_rng(3), (1.0, 1.0))
    for f in factors:
        f[:, 1] = f[:, 0]  # two body columns the same: no unique fit, no scale reported
    c, std = torque_scale(factors, 3, INDEPENDENT, N)
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
    # off: set k_t and N first (the friction was fitted with them), not a faster motion
    assert "set torque_constant and gear_ratio first" in line
    agree = scale_line(rows[1:])
    # a σ above 1 % cannot tell a data sheet's error: named "not checked", not "agrees"
    assert "agrees with the one given on j2 (largest σ 0.1 %)" in agree
    assert agree.endswith("not checked (σ above 1 %): j3, j4")
    assert "not checked, the base wrench does not determine it" in scale_line(rows[2:])
