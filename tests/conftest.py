"""Shared test helpers: independent homogeneous matrices written straight from the papers."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest


def Rx(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def Rz(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def Tx(dist: float) -> np.ndarray:
    T = np.eye(4)
    T[0, 3] = dist
    return T


def Tz(dist: float) -> np.ndarray:
    T = np.eye(4)
    T[2, 3] = dist
    return T


W_T_DH = np.array([[0, -1, 0, 0], [0, 0, -1, 0], [1, 0, 0, 0], [0, 0, 0, 1.0]])


def paper_tool_pose(table: np.ndarray, q: np.ndarray) -> np.ndarray:
    """T_world_tool, resting base, from the issue's module formulas (q per non-empty module)."""
    T = W_T_DH.copy()
    values = iter(q)
    for alpha, a, theta, d, link_type in table[:6]:
        if link_type == 1:
            T = T @ Rx(alpha) @ Tz(d) @ Rz(next(values)) @ Tx(a)
        elif link_type == 2:
            T = T @ Rx(alpha) @ Rz(theta) @ Tz(next(values)) @ Tx(a)
    return T @ Tx(table[6, 1])


GRAVITY = np.array([0.0, 0.0, -9.81])
"""Gravity in the world [m/s²], written here for the tests' own computations."""


def vee(S: np.ndarray) -> np.ndarray:
    """The vector of the skew-symmetric part of a 3 × 3 matrix (exact for a skew matrix)."""
    return 0.5 * np.array([S[2, 1] - S[1, 2], S[0, 2] - S[2, 0], S[1, 0] - S[0, 1]])


def _paper_base_at(rows: np.ndarray, t: complex) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Base position, rotation Rx(ax)·Ry(ay)·Rz(az) and body angular velocity at time t, from
    the sines (complex t allowed, for complex-step derivatives)."""
    A, bias, w, phase = rows.T
    x = A * np.sin(w * t + phase) + bias
    xd = A * w * np.cos(w * t + phase)
    ax, ay, az = x[3:]

    def rot(axis: int, angle: complex) -> np.ndarray:
        c, s = np.cos(angle), np.sin(angle)
        i, j = [(1, 2), (2, 0), (0, 1)][axis]
        R = np.eye(3, dtype=complex)
        R[i, i], R[i, j], R[j, i], R[j, j] = c, -s, s, c
        return R

    Rx_, Ry_, Rz_ = rot(0, ax), rot(1, ay), rot(2, az)
    e = np.eye(3)
    # ω_body = Rzᵀ·Ryᵀ·e_x·ȧx + Rzᵀ·e_y·ȧy + e_z·ȧz (moving-axis gimbal rates)
    omega = Rz_.T @ Ry_.T @ e[0] * xd[3] + Rz_.T @ e[1] * xd[4] + e[2] * xd[5]
    return x[:3], Rx_ @ Ry_ @ Rz_, omega


def paper_base_state(
    senB: np.ndarray, t: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The base's motion written out from the paper's sines, independently of the library.

    Returns:
        Position, velocity, acceleration (world), rotation, body angular velocity and its
        derivative, each with a leading time axis. Derivatives are exact: sine derivatives for
        the position, a complex step (h = 1e-30) for the angular acceleration.
    """
    rows = np.repeat(senB, 3, axis=0) if senB.shape[0] == 2 else np.asarray(senB, dtype=float)
    A, _, w, phase = rows[:3].T
    out: list[list[np.ndarray]] = [[] for _ in range(6)]
    for time in np.atleast_1d(t):
        position, R, omega = _paper_base_at(rows, time)
        h = 1e-30
        omega_dot = _paper_base_at(rows, time + 1j * h)[2].imag / h
        velocity = A * w * np.cos(w * time + phase)
        acceleration = -A * w**2 * np.sin(w * time + phase)
        for store, value in zip(
            out, (position, velocity, acceleration, R, omega, omega_dot), strict=True
        ):
            store.append(np.real(value))
    return tuple(np.array(values) for values in out)  # type: ignore[return-value]


def paper_frames(
    table: np.ndarray, senJ: np.ndarray, senB: np.ndarray, t: float
) -> tuple[np.ndarray, list[np.ndarray | None], np.ndarray]:
    """World poses at time t from the paper's matrices and sines: the base, each module's
    post-joint frame (None for an empty module), and the tool tip."""
    rows = np.repeat(senB, 3, axis=0) if senB.shape[0] == 2 else senB
    x, y, z, ax, ay, az = (r[0] * np.sin(r[2] * t + r[3]) + r[1] for r in rows)
    cy, sy = np.cos(ay), np.sin(ay)
    Ry = np.array([[cy, 0, sy, 0], [0, 1, 0, 0], [-sy, 0, cy, 0], [0, 0, 0, 1.0]])
    T_base = Rx(ax) @ Ry @ Rz(az)
    T_base[:3, 3] = (x, y, z)
    T = T_base @ W_T_DH
    modules: list[np.ndarray | None] = []
    for i, (alpha, a, theta, d, link_type) in enumerate(table[:6]):
        A, Ap, bias, w, phase = senJ[i]
        if link_type == 0:
            modules.append(None)
            continue
        if link_type == 1:
            T = T @ Rx(alpha) @ Tz(d) @ Rz(A * np.sin(w * t + phase) + bias)
        else:
            T = T @ Rx(alpha) @ Rz(theta) @ Tz(Ap * np.sin(w * t + phase) + bias)
        modules.append(T.copy())
        T = T @ Tx(a)
    return T_base, modules, T @ Tx(table[6, 1])


def wrist_equation_9(t1: float, t2: float, t3: float, d: float) -> np.ndarray:
    """Equation (9) of the spherical-wrist report: the tool pose of its standard DH table."""
    c1, s1, c2, s2, c3, s3 = (
        np.cos(t1),
        np.sin(t1),
        np.cos(t2),
        np.sin(t2),
        np.cos(t3),
        np.sin(t3),
    )
    return np.array(
        [
            [c1 * c2 * c3 - s1 * s3, -c1 * c2 * s3 - s1 * c3, c1 * s2, c1 * s2 * d],
            [s1 * c2 * c3 + c1 * s3, -s1 * c2 * s3 + c1 * c3, s1 * s2, s1 * s2 * d],
            [-s2 * c3, s2 * s3, c2, c2 * d],
            [0, 0, 0, 1],
        ]
    )


def run_cli(*args: str) -> tuple[int, str, str]:
    """Run the ``aaria`` command line in-process: exit status, stdout, stderr."""
    from click.testing import CliRunner

    from aaria_pin.cli import main

    result = CliRunner().invoke(main, list(args))
    return result.exit_code, result.stdout, result.stderr


def simulated_with_hardware(folder: Path, robot: str, hardware: str, duration: float) -> Path:
    """A Fourier run at 200 Hz without IMU noise of ``robot`` (``ur5`` or a preset) with the
    hardware TOML text ``hardware``, made by ``aaria simulate`` in ``folder``."""
    (folder / "hardware.toml").write_text(hardware)
    chosen = ["--robot", robot] if robot == "ur5" else ["--preset", robot]
    code, _, err = run_cli(
        "simulate", *chosen, "--motion", "fourier", "--duration", str(duration), "--rate", "200",
        "--no-noise", "--hardware", str(folder / "hardware.toml"), "-o", str(folder / "run.h5"),
    )  # fmt: skip
    assert code == 0, err
    return folder / "run.h5"


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(12345)
