"""One matplotlib figure drawn and saved as a PNG (atomically), closed whatever happens."""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from aaria_pin.files.io import atomic_output
from aaria_pin.viz._plotting import pyplot

__all__ = ["DPI", "png_figure"]

DPI = 100
"""Dots per inch of every picture: a figure of w × h inches is 100 w × 100 h pixels."""


@contextmanager
def png_figure(
    path: str | os.PathLike[str], width: int, height: int, **options: Any
) -> Iterator[Any]:
    """A figure of ``width`` × ``height`` pixels, saved to ``path`` when the block ends.

    The PNG is written beside ``path`` and renamed when complete; nothing is written if the
    block raises. The figure is closed either way.

    Args:
        path: the PNG to write
        width: picture width [px]
        height: picture height [px]
        **options: more arguments of ``pyplot.figure`` (e.g. ``layout="constrained"``)

    Yields:
        The matplotlib figure to draw on.

    Raises:
        ParameterError: matplotlib is not installed.
    """
    plt = pyplot()
    figure = plt.figure(figsize=(width / DPI, height / DPI), dpi=DPI, **options)
    try:
        yield figure
        with atomic_output(Path(path)) as temporary:
            figure.savefig(temporary, format="png", dpi=DPI)
    finally:
        plt.close(figure)
