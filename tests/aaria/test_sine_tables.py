from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.aaria.dh import chain_from_table
from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.sine_tables import (
    base_motion,
    default_joint_table,
    joint_trajectory,
    validate_base_table,
    validate_joint_table,
)
from aaria_pin.errors import TableError

CHAIN = chain_from_table(get_preset("aaria-fig2").table)


def test_default_tables_stay_in_range() -> None:
    for name in ("aaria-fig2", "aaria-fig3"):
        chain = chain_from_table(get_preset(name).table)
        validate_joint_table(default_joint_table(chain), chain)


def test_revolute_uses_amplitude_and_prismatic_uses_prismatic_amplitude() -> None:
    table = np.zeros((8, 5))
    table[0] = [5.0, 0.05, 0.01, 2.0, 0.0]  # prismatic module 1: 0.05 m
    table[1] = [0.3, 9.0, 0.1, 1.0, 0.5]  # revolute module 2: 0.3 rad
    time = np.array([0.0, 0.25, 1.0])
    trajectory = joint_trajectory(table, CHAIN, time)
    np.testing.assert_allclose(trajectory.q[:, 0], 0.05 * np.sin(2.0 * time) + 0.01)
    np.testing.assert_allclose(trajectory.q[:, 1], 0.3 * np.sin(time + 0.5) + 0.1)
    np.testing.assert_allclose(trajectory.qdd[:, 1], -0.3 * np.sin(time + 0.5))


@pytest.mark.parametrize(
    ("row", "values", "pattern"),
    [
        (
            0,
            [0, 0.08, 0, 1, 0],
            r"row 1 \(prismatic module 1\) moves over \[-0.08, 0.08\] m; allowed",
        ),
        (0, [0, 0.05, 0.03, 1, 0], r"\[-0.02, 0.08\] m"),
        (1, [7.0, 0, 0, 1, 0], r"revolute module 2.*rad"),
        (2, [0.1, 0, 0, -1, 0], r"row 3, column 4 \(frequency\) is -1"),
        (3, [np.nan, 0, 0, 1, 0], r"row 4, column 1 \(amplitude\) is nan"),
    ],
)
def test_bad_joint_tables(row: int, values, pattern: str) -> None:
    table = default_joint_table(CHAIN)
    table[row] = values
    with pytest.raises(TableError, match=pattern):
        validate_joint_table(table, CHAIN)


def test_bad_joint_table_shape() -> None:
    with pytest.raises(TableError, match=r"shape \(6, 5\)"):
        validate_joint_table(np.zeros((6, 5)), CHAIN)


@pytest.mark.parametrize(
    ("table", "pattern"),
    [
        (np.zeros((3, 4)), r"shape \(3, 4\).*2 × 4 or 6 × 4"),
        (np.array([[0, 0, -1.0, 0], [0, 0, 1, 0]]), r"row 1, column 3 \(frequency\) is -1"),
        (np.array([[0, 0, 1.0, 0], [np.inf, 0, 1, 0]]), r"row 2, column 1 \(amplitude\) is inf"),
    ],
)
def test_bad_base_tables(table: np.ndarray, pattern: str) -> None:
    with pytest.raises(TableError, match=pattern):
        validate_base_table(table)


def test_2x4_base_table_equals_its_6x4_expansion() -> None:
    time = np.linspace(0, 2, 9)
    short = np.array([[0.1, 0.2, 1.0, 0.3], [0.2, -0.1, 0.7, 0.0]])
    a, b = base_motion(short, time), base_motion(np.repeat(short, 3, axis=0), time)
    for name in ("position", "velocity", "acceleration", "rotation", "omega", "omega_dot"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    np.testing.assert_allclose(a.position[:, 0], 0.1 * np.sin(time + 0.3) + 0.2)
