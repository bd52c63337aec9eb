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
