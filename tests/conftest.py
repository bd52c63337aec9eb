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


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(12345)
