"""One function over many tasks, in this process or a process pool: results as they complete.

Used by the identification benchmark (a progress line per arm as it ends) and the benchmark
tasks' ``identify`` baseline (tables put back in task order by their index).
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterator, Sequence
from typing import TypeVar

__all__ = ["completed"]

Task = TypeVar("Task")
Result = TypeVar("Result")


def completed(
    function: Callable[[Task], Result], tasks: Sequence[Task], workers: int
) -> Iterator[tuple[int, Result]]:
    """``(index, function(tasks[index]))`` in completion order.

    With one worker or one task in this process, in task order; else in a process pool of at
    most ``workers`` processes (fork on Linux: the parent's imports and compiled kernels are
    shared; spawn elsewhere). ``function`` must be picklable (a module-level function).
    """
    if workers <= 1 or len(tasks) <= 1:
        yield from enumerate(map(function, tasks))
        return
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    method = "fork" if sys.platform.startswith("linux") else "spawn"
    context = multiprocessing.get_context(method)
    with ProcessPoolExecutor(max_workers=min(workers, len(tasks)), mp_context=context) as pool:
        futures = {pool.submit(function, task): index for index, task in enumerate(tasks)}
        for future in as_completed(futures):
            yield futures[future], future.result()
