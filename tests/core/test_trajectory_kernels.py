"""The compiled trajectory and noise passes give the numbers of the array code they replaced.

Each reference below is the numpy array code of the 0.1 line (the code the fixtures in
``tests/fixtures/v0_1_0`` were made with), written out here; the compiled passes must equal it
bit for bit, on random inputs and angles far from zero.
"""

from __future__ import annotations

import numpy as np
import pytest
from gimbal_oracle import gimbal_xyz_motion

from aaria_pin.core.imu_noise import (
    ADIS16485,
    ImuNoiseModel,
    _bias_knots,
    _bias_step,
    _measure,
    _per_axis,
)
from aaria_pin.core.oscillation import base_motion
from aaria_pin.core.trajectory import sine_motion

NOISE_BLOCK = 4096
"""Rows per block of the array code of the noise."""


def reference_sine_motion(
    A: np.ndarray, bias: np.ndarray, w: np.ndarray, phase: np.ndarray, time: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """sine_motion as the numpy array expressions the compiled sine_columns replaced."""
    angle = np.multiply.outer(time, w)
    angle += phase
    s = np.sin(angle)
    c = np.cos(angle, out=angle)
    value = A * s
    value += bias
    velocity = c
    velocity *= A * w
    s *= -A * w * w
    return value, velocity, s


def _measure_arrays(
    measured: np.ndarray,
    exact: np.ndarray,
    bias: np.ndarray,
    start: int,
    rate: float,
    model: ImuNoiseModel,
) -> None:
    """_measure as the numpy array code the compiled pass replaced, rows in blocks."""
    n, columns = measured.shape
    n_imu = columns // 6
    flat = exact.reshape(n, -1)
    white = np.tile(_per_axis(model, "noise_density"), n_imu) * np.sqrt(rate / 2.0)
    full_scale = np.tile(_per_axis(model, "range"), n_imu)
    lsb = np.tile(_per_axis(model, "lsb"), n_imu)
    step = _bias_step(rate, model)
    change = bias[1:] - bias[:-1]
    for first in range(0, n, NOISE_BLOCK):
        block = measured[first : first + NOISE_BLOCK]
        block *= white
        block += flat[first : first + NOISE_BLOCK]
        # sample i = k·step + r: b[k] + (b[k+1] - b[k])·(r/step)
        index = np.arange(start + first, start + first + block.shape[0])
        knot = index // step
        between = np.take(change, knot, axis=0)
        between *= ((index - knot * step) / step)[:, None]
        between += np.take(bias, knot, axis=0)  # b[k] + Δ·r (a sum is the same either way)
        block += between
        np.minimum(block, full_scale, out=block)
        np.maximum(block, -full_scale, out=block)
        block /= lsb
        np.round(block, out=block)
        block *= lsb


def numpy_gimbal(angles, rates, accelerations):  # type: ignore[no-untyped-def]
    (cx, cy, cz), (sx, sy, sz) = np.cos(angles.T), np.sin(angles.T)
    (xd, yd, zd), (xdd, ydd, zdd) = rates.T, accelerations.T
    R = np.empty((3, 3, angles.shape[0]))
    R[0, 0], R[0, 1], R[0, 2] = cy * cz, -cy * sz, sy
    row1 = (sz, cz, 0.0)
    row2 = (-sy * cz, sy * sz, cy)
    for col in range(3):
        R[1, col] = cx * row1[col] - sx * row2[col]
        R[2, col] = sx * row1[col] + cx * row2[col]
    omega = np.empty((3, angles.shape[0]))
    omega[0] = cy * cz * xd + sz * yd
    omega[1] = -cy * sz * xd + cz * yd
    omega[2] = sy * xd + zd
    omega_dot = np.empty_like(omega)
    omega_dot[0] = cy * cz * xdd + sz * ydd - (sy * cz * yd + cy * sz * zd) * xd + cz * zd * yd
    omega_dot[1] = -cy * sz * xdd + cz * ydd + (sy * sz * yd - cy * cz * zd) * xd - sz * zd * yd
    omega_dot[2] = sy * xdd + zdd + cy * yd * xd
    return R.transpose(2, 0, 1), omega.T, omega_dot.T


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    return (
        a.shape == b.shape
        and np.ascontiguousarray(a).tobytes() == np.ascontiguousarray(b).tobytes()
    )


@pytest.mark.parametrize("seed", range(4))
def test_sine_motion_is_the_array_code_bit_for_bit(seed: int) -> None:
    rng = np.random.default_rng(seed)
    A, bias, phase = rng.normal(size=(3, 7)) * [[0.8], [0.3], [3.0]]
    w = np.abs(rng.normal(size=7)) * 20.0
    A[0], w[1] = 0.0, 0.0  # a still column and a constant one
    time = np.arange(40_001) / 97.3  # angles up to about 10⁴ rad
    for got, want in zip(
        sine_motion(A, bias, w, phase, time),
        reference_sine_motion(A, bias, w, phase, time),
        strict=True,
    ):
        assert same_bits(got, want)


def test_one_scalar_motion_is_a_column_less_series_as_before() -> None:
    time = np.linspace(0.0, 2.0, 11)
    got = sine_motion(0.5, 0.1, 2.0, 0.3, time)
    want = reference_sine_motion(0.5, 0.1, 2.0, 0.3, time)
    for g, w in zip(got, want, strict=True):
        assert same_bits(g, w)


@pytest.mark.parametrize("seed", range(4))
def test_gimbal_is_the_array_code_bit_for_bit(seed: int) -> None:
    rng = np.random.default_rng(10 + seed)
    angles = rng.normal(size=(5000, 3)) * 4.0
    angles[:7] = [[0, 0, 0], [np.pi / 2, 0, 0], [0, -np.pi / 2, 0], [0, 0, np.pi], [-0.0] * 3,
                  [1e-300, -1e-300, 0.0], [50.0, -80.0, 120.0]]  # fmt: skip
    rates, accelerations = rng.normal(size=(2, 5000, 3))
    got = gimbal_xyz_motion(angles, rates, accelerations)
    for g, w in zip(got, numpy_gimbal(angles, rates, accelerations), strict=True):
        assert same_bits(g, w)


def test_gimbal_rotation_is_the_product_of_axis_rotations() -> None:
    angles = np.array([[0.3, -0.7, 1.9]])
    R = gimbal_xyz_motion(angles, np.zeros((1, 3)), np.zeros((1, 3)))[0][0]
    ax, ay, az = angles[0]
    Rx = np.array([[1, 0, 0], [0, np.cos(ax), -np.sin(ax)], [0, np.sin(ax), np.cos(ax)]])
    Ry = np.array([[np.cos(ay), 0, np.sin(ay)], [0, 1, 0], [-np.sin(ay), 0, np.cos(ay)]])
    Rz = np.array([[np.cos(az), -np.sin(az), 0], [np.sin(az), np.cos(az), 0], [0, 0, 1]])
    np.testing.assert_allclose(R, Rx @ Ry @ Rz, atol=1e-15)


@pytest.mark.parametrize(
    "table",
    [
        np.array([[0.05, 0.0, 1.0, 0.0], [0.05, 0.0, 0.7, 0.3]]),
        np.array(
            [
                [0.1, 0.2, 3.0, 0.1],
                [0.2, -0.1, 2.0, 0.3],
                [0.0, 0.1, 1.0, 0.0],
                [0.4, 0.1, 0.5, 1.0],
                [1.3, -0.1, 2.0, 0.4],
                [2.2, 0.2, 0.0, 0.2],
            ]
        ),
    ],
)
def test_base_motion_is_sine_then_gimbal_of_the_array_code(table: np.ndarray) -> None:
    time = np.arange(30_001) / 1000.0
    per_axis = np.repeat(table, 3, axis=0) if table.shape[0] == 2 else table
    x, xd, xdd = reference_sine_motion(*per_axis.T, time)
    R, omega, omega_dot = numpy_gimbal(x[:, 3:], xd[:, 3:], xdd[:, 3:])
    base = base_motion(table, time)
    for got, want in (
        (base.position, x[:, :3]),
        (base.velocity, xd[:, :3]),
        (base.acceleration, xdd[:, :3]),
        (base.rotation, R),
        (base.omega, omega),
        (base.omega_dot, omega_dot),
    ):
        assert same_bits(got, want)
        assert got.flags.c_contiguous


@pytest.mark.parametrize(("rate", "start"), [(1000.0, 0), (1000.0, 12_345), (50.0, 7), (3.0, 0)])
def test_compiled_noise_pass_is_the_array_code_bit_for_bit(rate: float, start: int) -> None:
    rng = np.random.default_rng(int(rate) + start)
    n, n_imu = 9000, 5
    exact = rng.normal(size=(n, n_imu, 6)) * np.tile([3.0, 3.0, 3.0, 20.0, 20.0, 20.0], (1, 1))
    exact[::97] *= 100.0  # saturated samples
    bias = _bias_knots(rng, start + n, n_imu, rate, ADIS16485)
    normals = rng.standard_normal((n, n_imu * 6))
    got, want = normals.copy(), normals.copy()
    _measure(got, exact, bias, start, rate, ADIS16485)
    _measure_arrays(want, exact, bias, start, rate, ADIS16485)
    assert same_bits(got, want)
