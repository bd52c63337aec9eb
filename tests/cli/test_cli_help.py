"""Every command's --help ends with examples, and the examples name real commands and flags."""

from __future__ import annotations

import re
import shlex

import click
import pytest
from click.testing import CliRunner

from aaria_pin.cli import main


def _commands() -> list[tuple[str, ...]]:
    """The path of every registered command, groups and their subcommands included."""
    found: list[tuple[str, ...]] = []
    stack: list[tuple[tuple[str, ...], click.Command]] = [
        ((name,), command) for name, command in main.commands.items()
    ]
    while stack:
        path, command = stack.pop()
        found.append(path)
        if isinstance(command, click.Group):
            stack.extend(((*path, name), sub) for name, sub in command.commands.items())
    return sorted(found)


def _cases() -> list[object]:
    return [pytest.param(path, id=" ".join(path)) for path in _commands()]


def _command(path: tuple[str, ...]) -> click.Command:
    command: click.Command = main
    for name in path:
        assert isinstance(command, click.Group), path
        command = command.commands[name]
    return command


def _examples(help_text: str) -> list[str]:
    """The example command lines of a help text (continuations joined, comments dropped)."""
    block = help_text.split("Examples:", 1)[1]
    joined = re.sub(r"\\\n\s*", " ", block)
    lines = [line.split(" #", 1)[0].strip() for line in joined.splitlines()]
    return [part.strip() for line in lines for part in line.split("&&") if part.strip()]


@pytest.mark.parametrize("path", _cases())
def test_help_ends_with_examples_of_real_commands_and_flags(path: tuple[str, ...]) -> None:
    result = CliRunner().invoke(main, [*path, "--help"])
    assert result.exit_code == 0, result.output
    assert "Examples:" in result.output, f"aaria {' '.join(path)} --help has no examples"
    assert "``" not in result.output  # no raw reStructuredText markup
    examples = [line for line in _examples(result.output) if line.startswith("aaria ")]
    assert examples, result.output
    for line in examples:
        words = shlex.split(line)[1:]
        command: click.Command = main
        while isinstance(command, click.Group):
            assert words and words[0] in command.commands, f"{line!r}: no command {words[:1]}"
            command = command.commands[words.pop(0)]
        flags = {opt for param in command.params for opt in param.opts}
        flags |= {"-h", "--help"}
        for word in words:
            if word.startswith("-") and not re.fullmatch(r"-[\d.]+", word):
                assert word.split("=")[0] in flags, f"{line!r}: {word} is not a flag"


def test_every_registered_command_is_covered() -> None:
    """The walk reaches the subcommands of groups (arm urdf, wrist ik)."""
    paths = _commands()
    assert ("arm", "pick-place") in paths and ("wrist", "ik") in paths
    assert ("urdf",) in paths and ("dataset-stats",) in paths
