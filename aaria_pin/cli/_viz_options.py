"""Options shared by the commands that read runs and write files: ``--run``, the output file."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import click

from aaria_pin.viz._formats import PICTURE_SUFFIXES

__all__ = ["PICTURE_SUFFIXES", "check_output", "check_run_option", "output_option"]

F = TypeVar("F", bound=Callable[..., Any])


def check_output(path: Path, what: str, suffixes: tuple[str, ...]) -> None:
    """Refuse an output of another type, in a folder that does not exist, or not writable.

    The type and the folder are told here; the rest (``-``, a name too long for the file
    system, a folder or a socket at the path, an unwritable folder, an output another aaria
    process is writing) by :func:`aaria_pin.files.paths.check_output`.

    Args:
        path: the file to write
        what: what the file is, for the error (``"PNG"``, ``"run file"``)
        suffixes: allowed suffixes, lower case with the dot

    Raises:
        OutputFileError: naming the path and what is allowed (one line).
    """
    from aaria_pin.errors import OutputFileError
    from aaria_pin.files.paths import check_output as check_output_path

    if str(path) in ("-", ""):
        check_output_path(path)  # refused: this command does not write to standard output
    if path.suffix.lower() not in suffixes:
        raise OutputFileError(
            f"{path}: suffix {path.suffix!r} is not one of a {what}; allowed: {', '.join(suffixes)}"
        )
    folder = path.parent
    if not folder.is_dir():
        raise OutputFileError(
            f"{path}: no folder {folder} (it does not exist); allowed: a file in an existing folder"
        )
    check_output_path(path, suffixes=suffixes)


def output_option(
    what: str,
    suffixes: tuple[str, ...],
    *flags: str,
    required: bool = True,
    help: str | None = None,
) -> Callable[[F], F]:
    """Add an output file option (``-o/--output FILE`` unless ``flags`` are given), checked.

    A wrong suffix or a missing folder (:func:`check_output`), or a folder given as the file, is
    an error of one line (exit 2), raised while the options are read, before anything is
    computed or written.

    Args:
        what: what the file is, for the help and the error (``"PNG"``, ``"HTML page"``)
        suffixes: allowed suffixes, lower case with the dot, the first one named in the error
        flags: the option's names (default ``-o``, ``--output``)
        required: whether the option must be given (else it defaults to None)
        help: the option's help (default: what it is and its suffixes)
    """

    def check(_ctx: click.Context, _param: click.Parameter, value: Path | None) -> Path | None:
        if value is not None:
            check_output(value, what, suffixes)
        return value

    return click.option(
        *(flags or ("-o", "--output")),
        type=click.Path(path_type=Path, dir_okay=False),
        required=required,
        default=None,
        callback=check,
        help=help or f"{what} file to write ({', '.join(suffixes)}).",
    )


def check_run_option(path: Path, run_index: int | None) -> None:
    """Refuse ``--run`` for a file that is not a data set (a missing file is told later).

    Raises:
        click.UsageError: ``--run`` given with a run file.
    """
    if run_index is None or not path.is_file():
        return
    from aaria_pin.files.detection import is_dataset_file

    if not is_dataset_file(path):
        raise click.UsageError("--run is for a data set; this is a run file")
