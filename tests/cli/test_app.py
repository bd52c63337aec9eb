"""The one mapping of a library error to a flag: an input file's error is not the output's."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import click
import numpy as np
import pytest
from click.testing import CliRunner

from aaria_pin.cli._app import flag_message
from aaria_pin.errors import AariaError, InputFileError, OutputFileError
from aaria_pin.files.io import read_table
from aaria_pin.files.paths import check_output


@click.command("demo")
@click.option("-o", "--output", type=click.Path())
@click.option("--dh", "dh_file", type=click.Path())
def demo(output: str, dh_file: str) -> None:
    """A command with an output and an input file."""


def test_an_output_error_names_the_output_flag() -> None:
    error = OutputFileError(parameter="path", value="x.txt", allowed=".h5, .mat")
    assert flag_message(error, demo) == "-o/--output is 'x.txt'; allowed: .h5, .mat"


def test_an_input_error_never_names_the_output_flag() -> None:
    error = InputFileError(parameter="file", value="t.csv", allowed="a numeric table")
    assert flag_message(error, demo) == "file is 't.csv'; allowed: a numeric table"
    named = InputFileError(parameter="dh_file", value="t.csv", allowed="a numeric table")
    assert flag_message(named, demo) == "--dh is 't.csv'; allowed: a numeric table"


def _raised(call: Callable[[], object]) -> AariaError:
    with pytest.raises(AariaError) as caught:
        call()
    return caught.value


def test_the_readers_and_writers_name_input_and_output_apart(tmp_path: Path) -> None:
    bad = tmp_path / "bad.csv"
    bad.write_text("1, 2\n3, x\n")
    np.save(tmp_path / "cube.npy", np.zeros((2, 2, 2)))
    inputs = [
        _raised(lambda: read_table(tmp_path / "missing.csv")),
        _raised(lambda: read_table(bad)),
        _raised(lambda: read_table(tmp_path / "cube.npy")),
        _raised(lambda: read_table(tmp_path / "t.xyz")),
    ]
    assert [type(e) for e in inputs] == [InputFileError] * 4
    assert [e.parameter for e in inputs] == ["file"] * 4
    assert "-o/--output" not in " ".join(flag_message(e, demo) for e in inputs)
    output = _raised(lambda: check_output(tmp_path / "no folder" / "run.h5"))
    assert isinstance(output, OutputFileError) and output.parameter == "path"


@pytest.mark.parametrize(
    ("argv", "line"),
    [
        (["--frob"], "aaria: error: No such option '--frob'."),
        (["--version", "--frob"], "aaria: error: No such option '--frob'."),
        (["urdf", "--preset", "aaria-fig2"], "aaria: error: Missing option '-o' / '--output'."),
        (["mjcf", "--preset", "aaria-fig2"], "aaria: error: Missing option '-o' / '--output'."),
    ],
)
def test_usage_errors_are_one_line_at_every_level(argv: list[str], line: str) -> None:
    from aaria_pin.cli import main

    result = CliRunner().invoke(main, argv)
    assert result.exit_code == 2
    assert result.stderr.splitlines() == [line]
    assert result.stdout == ""


def test_aaria_alone_still_prints_its_help() -> None:
    from aaria_pin.cli import main

    result = CliRunner().invoke(main, [], prog_name="aaria")
    assert "Usage: aaria [OPTIONS] COMMAND [ARGS]..." in result.output
    assert "Commands:" in result.output and "aaria: error" not in result.output


def test_a_full_device_exits_1(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The input was fine, the machine was not: exit 1, the NoSpaceError's line as it is."""
    from aaria_pin.cli import main
    from aaria_pin.files import io, paths

    def full(*_: object, **__: object) -> None:
        raise paths.no_space_error(tmp_path / "dh.csv")

    monkeypatch.setattr(io, "write_text_atomic", full)
    result = CliRunner().invoke(main, ["template", "dh", "-o", str(tmp_path / "dh.csv")])
    assert result.exit_code == 1
    assert result.stderr.splitlines() == [
        f"aaria: error: no space left on device writing {tmp_path / 'dh.csv'}; nothing was replaced"
    ]


def test_a_warning_is_one_line_on_stderr() -> None:
    """Python's two-line warning (file:line, source line) becomes ``aaria: warning: …``."""
    import subprocess
    import sys

    old = Path(__file__).parents[1] / "fixtures" / "v0_3_0" / "dh_run.h5"
    done = subprocess.run(
        [sys.executable, "-m", "aaria_pin.cli", "torques", str(old)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0
    lines = done.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("aaria: warning: ")
    assert "cannot be verified" in lines[0]
