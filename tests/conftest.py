"""Shared test helpers: independent homogeneous matrices written straight from the papers."""

from __future__ import annotations

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


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(12345)
