"""The ``-o/--output`` option of ``aaria render``, ``plot`` and ``view``: a file of one type."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import click

__all__ = ["output_option"]

F = TypeVar("F", bound=Callable[..., Any])


def output_option(what: str, suffixes: tuple[str, ...]) -> Callable[[F], F]:
    """Add a required ``-o/--output FILE`` whose suffix must be one of ``suffixes``.

    A wrong suffix is an :class:`~aaria_pin.errors.OutputFileError` (one line, exit 2), raised
    while the options are read, before anything is computed or written.

    Args:
        what: what the file is, for the help and the error (``"PNG"``, ``"HTML page"``)
        suffixes: allowed suffixes, lower case with the dot, the first one named in the error
    """

    def check(_ctx: click.Context, _param: click.Parameter, value: Path) -> Path:
        from aaria_pin.errors import OutputFileError

        if value.suffix.lower() not in suffixes:
            raise OutputFileError(
                f"{value}: suffix {value.suffix!r} is not one of a {what};"
                f" allowed: {', '.join(suffixes)}"
            )
        return value

    return click.option(
        "-o",
        "--output",
        type=click.Path(path_type=Path, dir_okay=False),
        required=True,
        callback=check,
        help=f"{what} file to write ({', '.join(suffixes)}).",
    )
