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
