"""One matplotlib figure drawn and saved (PNG, PDF or SVG by the suffix), closed whatever happens.

Pictures for papers: a PNG has exactly the asked pixel size; a PDF or an SVG (vector, fonts as
paths) is cropped to what is drawn (``bbox_inches="tight"``, 0.02 in of margin) and carries no
creation date, so the same figure gives the same file.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from aaria_pin.core.se3 import Array
from aaria_pin.errors import OutputFileError
from aaria_pin.files.io import atomic_output
from aaria_pin.viz._formats import PICTURE_SUFFIXES
from aaria_pin.viz._plotting import pyplot

__all__ = ["DPI", "PICTURE_SUFFIXES", "equal_axes_3d", "figure_file", "picture_format"]

DPI = 100
"""Dots per inch of every picture: a figure of w × h inches is 100 w × 100 h pixels."""


def picture_format(path: str | os.PathLike[str]) -> str:
    """The format of a picture file by its suffix: ``"png"``, ``"pdf"`` or ``"svg"``.

    Raises:
        OutputFileError: another suffix (one line, naming the allowed ones).
    """
    suffix = Path(path).suffix.lower()
    if suffix not in PICTURE_SUFFIXES:
        raise OutputFileError(
            f"{path}: suffix {suffix!r} is not one of a picture;"
            f" allowed: {', '.join(PICTURE_SUFFIXES)}",
            parameter="path",
            value=suffix,
        )
    return suffix[1:]


@contextmanager
def figure_file(
    path: str | os.PathLike[str], width: int, height: int, **options: Any
) -> Iterator[Any]:
    """A figure of ``width`` × ``height`` pixels, saved to ``path`` when the block ends.

    The file is written beside ``path`` and renamed when complete; nothing is written if the
    block raises. The figure is closed either way.

    Args:
        path: the picture to write: ``.png`` (exactly ``width`` × ``height`` px), ``.pdf`` or
            ``.svg`` (cropped to what is drawn)
        width: picture width [px] (1/100 in)
        height: picture height [px]
        **options: more arguments of ``pyplot.figure`` (e.g. ``layout="constrained"``)

    Yields:
        The matplotlib figure to draw on.

    Raises:
        OutputFileError: a suffix that is not a picture's (before anything is drawn).
        ParameterError: matplotlib is not installed.
    """
    kind = picture_format(path)
    plt = pyplot()
    figure = plt.figure(figsize=(width / DPI, height / DPI), dpi=DPI, **options)
    try:
        yield figure
        with atomic_output(Path(path)) as temporary:
            if kind == "png":
                figure.savefig(temporary, format="png", dpi=DPI)
            else:
                metadata = {"CreationDate": None} if kind == "pdf" else {"Date": None}
                # A fixed salt: SVG clip-path ids are hashes salted at random otherwise, so two
                # writes of one figure differed.
                with plt.rc_context({"svg.hashsalt": "aaria_pin"}):
                    figure.savefig(
                        temporary,
                        format=kind,
                        bbox_inches="tight",
                        pad_inches=0.02,
                        metadata=metadata,
                    )
    finally:
        plt.close(figure)


def equal_axes_3d(
    axes: Any, low: Array, high: Array, margin: float = 1.05, min_half: float = 1e-3
) -> None:
    """Give 3D axes equal scales: a cube about the middle of ``low``–``high`` [m], tight.

    Args:
        axes: matplotlib 3D axes
        low: lowest corner to show (3,)
        high: highest corner to show (3,)
        margin: the cube's half side over half the largest extent
        min_half: the smallest half side [m]
    """
    low, high = np.asarray(low, dtype=float), np.asarray(high, dtype=float)
    centre, half = (low + high) / 2.0, max(float(np.max(high - low)) / 2.0, min_half) * margin
    axes.set_xlim(centre[0] - half, centre[0] + half)
    axes.set_ylim(centre[1] - half, centre[1] + half)
    axes.set_zlim(centre[2] - half, centre[2] + half)
    axes.set_box_aspect((1.0, 1.0, 1.0))
