"""``apps.pool.completed``: every task's result once, with its index, in a pool or not."""

from __future__ import annotations

import math

import pytest

from aaria_pin.apps.pool import completed


@pytest.mark.parametrize("workers", [1, 2])
def test_every_task_once_with_its_index(workers: int) -> None:
    tasks = [0.1 * k for k in range(7)]
    found = dict(completed(math.sin, tasks, workers))
    assert sorted(found) == list(range(7))
    assert all(found[k] == math.sin(0.1 * k) for k in range(7))
