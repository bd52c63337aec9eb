"""Options shared by the commands that read runs and write files: ``--run``, the output file.

``--run`` is checked by the one reader (:func:`aaria_pin.files.source.open_record`: required
for a data set, refused for a run file), so every command says the same.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import click

from aaria_pin.viz._formats import PICTURE_SUFFIXES

__all__ = [
    "PICTURE_SUFFIXES",
    "check_output",
    "output_option",
    "run_option",
]

F = TypeVar("F", bound=Callable[..., Any])


def check_output(path: Path, what: str, suffixes: tuple[str, ...]) -> None:
    """Refuse an output of another type (``what``: ``"PNG"``, ``"run file"``) or folder-less.

    The rest (``-``, a name too long, a folder or a socket at the path, an unwritable folder,
    an output another aaria process is writing) is refused by
    :func:`aaria_pin.files.paths.check_output`.

    Raises:
        OutputFileError: naming the path and what is allowed (one line).
    """
    from aaria_pin.errors import OutputFileError
    from aaria_pin.files.paths import check_name_lengths
    from aaria_pin.files.paths import check_output as check_output_path

    if str(path) in ("-", ""):
        check_output_path(path)  # refused: this command does not write to standard output
    check_name_lengths(path)  # before the folder is looked at (ENAMETOOLONG)
    if path.suffix.lower() not in suffixes:
        is_not = f"suffix {path.suffix!r} is not one of a {what}"
        raise OutputFileError(f"{path}: {is_not}; allowed: {', '.join(suffixes)}", parameter="path")
    if not path.parent.is_dir():
        no_folder = f"no folder {path.parent} (it does not exist)"
        allowed = "a file in an existing folder"
        raise OutputFileError(f"{path}: {no_folder}; allowed: {allowed}", parameter="path")
    check_output_path(path, suffixes=suffixes)


def output_option(
    what: str, suffixes: tuple[str, ...], *flags: str, required: bool = True, help: str = ""
) -> Callable[[F], F]:
    """An output file option (``-o/--output FILE`` unless ``flags`` are given), checked.

    A wrong suffix, a missing folder (:func:`check_output`) or a folder given as the file is
    an error of one line (exit 2) while the options are read, before anything is computed.

    Args:
        what: what the file is, for the help and the error (``"PNG"``, ``"HTML page"``)
        suffixes: allowed suffixes, lower case with the dot
        flags: the option's names (default ``-o``, ``--output``)
        required: whether the option must be given (else it defaults to None)
        help: the option's help (default: what it is and its suffixes)
    """

    def check(_ctx: click.Context, _param: click.Parameter, value: Path | None) -> Path | None:
        if value is not None:
            check_output(value, what, suffixes)
        return value

    help = help or f"{what} file to write ({', '.join(suffixes)})."
    path = click.Path(path_type=Path, dir_okay=False)
    declared = flags or ("-o", "--output")
    return click.option(*declared, type=path, required=required, callback=check, help=help)


def run_option(help: str = "One run of a data set (default 0).") -> Callable[[F], F]:
    """``--run K`` (the parameter ``run_index``): one run of a data set."""
    return click.option("--run", "run_index", type=click.IntRange(0), help=help)
