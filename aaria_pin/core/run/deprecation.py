"""The producers of earlier releases, made once: a request's record or pieces, with a warning.

Before the engine (0.3.0) each robot kind had its own ``simulate_*`` producers taking the joint
and base tables positionally and keyword options; each is now one line over its request (e.g.
``simulate_run = deprecated_producer("simulate_run", dh_request, "record")``), so the rule "warn,
then run the request" is written here only. They go in the next release.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import Any, Literal

from numpy.typing import ArrayLike

__all__ = ["deprecated_producer", "warn_deprecated"]


def warn_deprecated(name: str, replacement: str) -> None:
    """Warn that the producer ``name`` (the caller) is deprecated, naming its replacement."""
    warnings.warn(
        f"{name} is deprecated; use {replacement} (it goes in the next release)",
        DeprecationWarning,
        stacklevel=3,
    )


def deprecated_producer(
    name: str, request: Callable[..., Any], form: Literal["record", "pieces"]
) -> Callable[..., Any]:
    """A producer of an earlier release: ``request(first, **options).<form>()``, warning first.

    Args:
        name: the producer's name (``simulate_run``), for its warning and ``__name__``
        request: the request it stands for (``dh_request``: its first argument and keyword
            options, returning a :class:`~aaria_pin.core.run.RunRequest`)
        form: ``"record"`` (the run held whole) or ``"pieces"`` (an iterator of pieces)

    Returns:
        ``producer(first, joint_table=None, base_table=None, **options)``: the old signature
        (the tables positionally, as earlier releases took them).
    """
    replacement = f"{request.__module__}.{request.__name__}(..., **options).{form}()"

    def producer(
        first: Any,
        joint_table: ArrayLike | None = None,
        base_table: ArrayLike | None = None,
        **options: Any,
    ) -> Any:
        warn_deprecated(name, replacement)
        tables = {"joint_table": joint_table, "base_table": base_table}
        options.update({key: table for key, table in tables.items() if table is not None})
        run = request(first, **options)
        return run.record() if form == "record" else run.pieces()

    producer.__name__ = producer.__qualname__ = name
    producer.__module__ = request.__module__
    producer.__doc__ = f"Deprecated: ``{replacement}`` (it goes in the next release)."
    return producer
