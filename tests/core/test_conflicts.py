"""An option that another makes meaningless: one error naming both, for Python and the CLI."""

from __future__ import annotations

import pytest

from aaria_pin.core.conflicts import OptionConflictError
from aaria_pin.errors import ParameterError

FLAGS = {"holdout": "--holdout", "dynamics": "--dynamics", "harmonics": "--harmonics"}


def test_without_and_with_in_library_names_and_in_flags() -> None:
    needs = OptionConflictError(parameter="holdout", other="dynamics", given_with=False, value=0.3)
    assert str(needs) == "holdout is given without dynamics; allowed: holdout with dynamics"
    assert needs.for_flag(FLAGS) == (
        "--holdout is given without --dynamics; allowed: --holdout with --dynamics"
    )
    refused = OptionConflictError(parameter="holdout", other="dynamics", given_with=True)
    assert str(refused) == "holdout is given with dynamics; allowed: holdout without dynamics"
    assert refused.for_flag(FLAGS).startswith("--holdout is given with --dynamics; ")


def test_the_value_the_rule_is_about_and_names_without_a_flag() -> None:
    error = OptionConflictError(
        parameter="harmonics", other="motion", given_with=False, value=3, other_value="fourier"
    )
    assert str(error) == (
        "harmonics is given without motion='fourier'; allowed: harmonics with motion='fourier'"
    )
    # "motion" has no flag in this mapping: its name stays, as a Python keyword would
    assert error.for_flag(FLAGS) == (
        "--harmonics is given without motion='fourier'; allowed: --harmonics with motion='fourier'"
    )
    assert error.for_flag({**FLAGS, "motion": "--motion"}) == (
        "--harmonics is given without --motion fourier; allowed: --harmonics with --motion fourier"
    )


def test_its_fields_are_a_parameter_errors() -> None:
    error = OptionConflictError(parameter="holdout", other="dynamics", given_with=False, value=0.3)
    assert isinstance(error, ParameterError) and isinstance(error, ValueError)
    assert (error.parameter, error.value, error.allowed) == (
        "holdout",
        0.3,
        "holdout with dynamics",
    )
    assert (error.other, error.given_with, error.other_value) == ("dynamics", False, "")
    with pytest.raises(ParameterError, match=r"^holdout is given without dynamics; allowed: "):
        raise error
