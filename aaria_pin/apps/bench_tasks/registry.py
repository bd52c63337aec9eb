"""The benchmark tasks by name, and the lookup that refuses an unknown one."""

from __future__ import annotations

from collections.abc import Mapping

from aaria_pin.apps.bench_tasks.inverse_dynamics import InverseDynamicsTask
from aaria_pin.apps.bench_tasks.sensor_to_state import SensorToStateTask
from aaria_pin.apps.bench_tasks.structure import StructureTask
from aaria_pin.apps.bench_tasks.task import BenchTask

__all__ = ["TASKS", "get_task"]

TASKS: Mapping[str, BenchTask] = {
    task.name: task for task in (StructureTask(), InverseDynamicsTask(), SensorToStateTask())
}
"""Every task, by its name, in the issue's order."""


def get_task(name: str) -> BenchTask:
    """The task of a name.

    Raises:
        ParameterError: an unknown name.
    """
    from aaria_pin.errors import ParameterError

    if name not in TASKS:
        raise ParameterError(parameter="task", value=name, allowed=", ".join(TASKS))
    return TASKS[name]
