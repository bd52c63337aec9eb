"""The error family: one line, fields that carry the data, file errors that are OSErrors too."""

from __future__ import annotations

import math

import pytest

from aaria_pin.errors import (
    AariaError,
    InputFileError,
    ModelError,
    OutputFileError,
    ParameterError,
    TableError,
    UrdfError,
)


def test_fields_compose_the_one_line_message() -> None:
    error = TableError(
        parameter="joint_table", element="row 3, column 4", value=math.nan, allowed="finite"
    )
    assert str(error) == "row 3, column 4 of joint_table is nan; allowed: finite"
    assert (error.parameter, error.element, error.allowed) == (
        "joint_table",
        "row 3, column 4",
        "finite",
    )
    assert math.isnan(error.value)


def test_a_given_message_is_kept_and_fields_still_read() -> None:
    error = ParameterError("density -1 kg/m^3; allowed: > 0", parameter="density", value=-1.0)
    assert str(error) == "density -1 kg/m^3; allowed: > 0"
    assert error.value == -1.0


def test_the_cli_names_the_flag_not_the_parameter() -> None:
    error = ParameterError(parameter="joint_table", value="x.csv", allowed="an 8 × 5 table")
    assert error.for_flag({"joint_table": "--joints"}) == (
        "--joints is 'x.csv'; allowed: an 8 × 5 table"
    )
    assert error.for_flag({}) == str(error)


def test_the_cli_names_the_flag_of_a_cell() -> None:
    error = TableError(
        "base table: row 2, column 1 (x) is inf; allowed: finite",
        parameter="base_table",
        value=math.inf,
        allowed="finite",
        element="row 2, column 1 (x)",
    )
    assert str(error) == "base table: row 2, column 1 (x) is inf; allowed: finite"
    assert error.for_flag({"base_table": "--base"}) == (
        "row 2, column 1 (x) of --base is inf; allowed: finite"
    )


def test_a_message_without_allowed_is_printed_as_written() -> None:
    """No ``allowed`` field: the CLI keeps the message (it names its file), flag or not."""
    error = InputFileError(
        "imus.toml: [[imu]] number 2: no name; allowed: a non-empty string",
        parameter="path",
        value="imus.toml",
        element="[[imu]] number 2",
    )
    assert error.for_flag({"path": "-o/--output"}) == str(error)
    assert (error.parameter, error.value, error.allowed) == ("path", "imus.toml", None)


def test_for_flag_is_the_one_mapping_of_parameters_to_flags() -> None:
    """Only the CLI's error handler turns a parameter into a flag, through ``for_flag``."""
    import ast
    from pathlib import Path

    package = Path(__file__).resolve().parent.parent / "aaria_pin"
    callers = []
    for path in sorted(package.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Attribute) and node.attr == "for_flag":
                callers.append(path.relative_to(package).as_posix())
    assert len(callers) == 1 and callers[0].startswith("cli/"), callers  # today cli/_app.py


@pytest.mark.parametrize("kind", [InputFileError, OutputFileError])
def test_file_errors_are_os_errors_and_aaria_errors(kind: type[AariaError]) -> None:
    with pytest.raises(OSError, match="folder") as caught:
        raise kind("out/x.h5: no such folder; allowed: an existing folder")
    assert isinstance(caught.value, AariaError)
    assert isinstance(caught.value, ValueError)
    assert str(caught.value) == "out/x.h5: no such folder; allowed: an existing folder"


def test_one_base_class() -> None:
    for kind in (TableError, ParameterError, InputFileError, OutputFileError, ModelError):
        assert issubclass(kind, AariaError)
    assert issubclass(UrdfError, ModelError)


def test_numpy_values_are_shown_plainly() -> None:
    """Fields holding NumPy scalars or arrays read as the numbers, never ``np.float64(…)``."""
    import numpy as np

    cases = [
        (np.float64(np.nan), "nan"),
        (np.float32(1.5), "1.5"),
        (np.int64(-3), "-3"),
        (np.bool_(True), "True"),
        (np.array(2.25), "2.25"),
        (np.array([1.0, np.inf, -0.5]), "[1, inf, -0.5]"),
        (np.zeros((3, 2)), "[0, 0, 0, 0, 0, 0] (shape 3 × 2)"),
        (np.arange(20.0), "[0, 1, 2, 3, 4, 5, 6, 7, …] (shape 20)"),
        ((np.float64(0.1), 2), "(0.1, 2)"),
    ]
    for value, shown in cases:
        error = ParameterError(parameter="x", value=value, allowed="finite")
        assert str(error) == f"x is {shown}; allowed: finite"
        assert error.for_flag({"x": "--x"}) == f"--x is {shown}; allowed: finite"
        assert error.value is value


def test_numpy_reprs_in_a_given_message_are_made_plain() -> None:
    import numpy as np

    speed, lengths = np.float64(1e-9), [np.float32(0.25), np.int32(2)]
    error = ParameterError(f"speed {speed!r} and lengths {lengths}; allowed: > 0")
    assert str(error) == "speed 1e-09 and lengths [0.25, 2]; allowed: > 0"
    assert str(TableError(f"flag {np.False_!r}; allowed: True")) == "flag False; allowed: True"
    # text that merely mentions NumPy is left alone
    assert str(ModelError("np.linalg failed; allowed: x")) == "np.linalg failed; allowed: x"


def test_a_wrong_type_is_a_parameter_error_and_a_type_error() -> None:
    from aaria_pin.errors import ParameterTypeError, TableTypeError

    error = ParameterTypeError(parameter="duration", value="1", allowed="a number")
    assert isinstance(error, ParameterError) and isinstance(error, TypeError)
    assert isinstance(error, AariaError) and isinstance(error, ValueError)
    assert str(error) == "duration is '1'; allowed: a number"
    assert error.for_flag({"duration": "--duration"}) == "--duration is '1'; allowed: a number"
    table = TableTypeError(parameter="dh_table", value=None, allowed="a numeric array")
    assert isinstance(table, TableError) and isinstance(table, ParameterTypeError)
    with pytest.raises(TypeError):
        raise table
