"""The front door's argument checks: what each annotation allows, and our one-line errors."""

from __future__ import annotations

import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, Protocol, TypedDict, Unpack

import numpy as np
import pytest
from numpy.typing import ArrayLike

from aaria_pin.core.arguments import checked
from aaria_pin.errors import ParameterError, ParameterTypeError, TableTypeError

if TYPE_CHECKING:
    from aaria_pin.core.record import ImuMount


class Named(Protocol):
    """Anything with a name."""

    @property
    def name(self) -> str:
        """The name."""
        ...


class Options(TypedDict, total=False):
    """Keyword options."""

    rate: float
    label: str


@checked
def call(
    table: ArrayLike,
    duration: float = 1.0,
    *,
    count: int = 1,
    flag: bool = False,
    path: str | os.PathLike[str] | None = None,
    folder: Path | None = None,
    names: Sequence[str] = (),
    weights: Mapping[str, float] | None = None,
    mode: bool | Literal["auto"] = False,
    named: Named | None = None,
    mount: ImuMount | None = None,
    anything: Any = None,
    **options: Unpack[Options],
) -> str:
    """A function with one parameter of each kind."""
    return "ran"


@checked
@dataclass(frozen=True)
class Settings:
    """An input class."""

    rate: float = 100.0
    labels: tuple[str, ...] = ()


@dataclass(frozen=True)
class Thing:
    """A Named by a field."""

    name: str


GOOD: list[dict[str, Any]] = [
    {"table": [[1, 2], [3, 4]]},
    {"table": np.zeros((2, 3), dtype=np.float32), "duration": np.float64(2.5)},
    {"table": [1.0], "duration": 3, "count": np.int64(4), "flag": np.bool_(True)},
    {"table": [1.0], "path": "x.h5", "folder": Path("out"), "names": ["a", "b"]},
    {"table": [1.0], "path": Path("x.h5"), "folder": "out", "weights": {"a": 1.0}},
    {"table": [1.0], "mode": "auto", "named": Thing("n"), "anything": object()},
    {"table": [1.0], "rate": 5.0, "label": "x", "mode": True},
]


@pytest.mark.parametrize("arguments", GOOD)
def test_good_arguments_pass_as_given(arguments: dict[str, Any]) -> None:
    assert call(**arguments) == "ran"


@pytest.mark.parametrize(
    ("arguments", "parameter", "message"),
    [
        ({"table": "1"}, "table", "table is '1' (str); allowed: a numeric array"),
        ({"table": None}, "table", "table is None; allowed: a numeric array"),
        ({"table": [True, False]}, "table", "table is a list; allowed: a numeric array"),
        ({"table": [1], "duration": "1"}, "duration", "duration is '1' (str); allowed: a number"),
        ({"table": [1], "duration": True}, "duration", "duration is True; allowed: a number"),
        ({"table": [1], "count": 2.0}, "count", "count is 2.0 (float); allowed: an integer"),
        ({"table": [1], "flag": 1}, "flag", "flag is 1 (int); allowed: True or False"),
        ({"table": [1], "path": 3}, "path", "allowed: text (str) or a path or None"),
        ({"table": [1], "names": "ab"}, "names", "names is 'ab' (str); allowed: a sequence"),
        ({"table": [1], "names": ["a", 2]}, "names", "item 1 of names is 2 (int)"),
        ({"table": [1], "weights": {"a": "x"}}, "weights", "item 'a' of weights is 'x'"),
        ({"table": [1], "mode": "x"}, None, None),  # a value: the function's to refuse
        ({"table": [1], "mode": 2}, "mode", "allowed: True or False or one of 'auto'"),
        ({"table": [1], "named": object()}, "named", "named is an object; allowed: a Named"),
        ({"table": [1], "mount": "m"}, "mount", "allowed: an ImuMount or None"),
        ({"table": [1], "rate": "5"}, "rate", "rate is '5' (str); allowed: a number"),
        ({"table": [1], "speed": 5}, "speed", "call got an unexpected keyword argument 'speed'"),
        ({"duration": 1.0}, "table", "table is missing; allowed: a value (it is required)"),
        ({"table": [1], "label": 3}, "label", "label is 3 (int); allowed: text (str)"),
    ],
)
def test_a_wrong_type_is_our_type_error(
    arguments: dict[str, Any], parameter: str | None, message: str | None
) -> None:
    if parameter is None:
        assert call(**arguments) == "ran"
        return
    with pytest.raises(ParameterTypeError, match=re.escape(str(message))) as caught:
        call(**arguments)
    assert caught.value.parameter == parameter
    assert isinstance(caught.value, TypeError) and "\n" not in str(caught.value)


def test_an_array_of_the_wrong_type_is_a_table_error_too() -> None:
    with pytest.raises(TableTypeError):
        call([["a", "b"]])
    with pytest.raises(TypeError, match="positional"):
        call([1.0], 1.0, 2)


@pytest.mark.parametrize(
    ("arguments", "parameter", "message"),
    [
        ({"table": [1], "duration": float("nan")}, "duration", "duration is nan; allowed: a fin"),
        ({"table": [1], "rate": np.inf}, "rate", "rate is inf; allowed: a finite number"),
        ({"table": [[1, 2], [3]]}, "table", "table is a ragged nesting of sequences"),
    ],
)
def test_a_bad_value_of_the_right_type_is_a_value_error(
    arguments: dict[str, Any], parameter: str, message: str
) -> None:
    with pytest.raises(ParameterError, match=message) as caught:
        call(**arguments)
    assert caught.value.parameter == parameter and not isinstance(caught.value, TypeError)


def test_a_class_checks_its_fields() -> None:
    assert Settings(rate=5, labels=("a",)).rate == 5
    with pytest.raises(ParameterTypeError, match=r"rate is '5' \(str\); allowed: a number"):
        Settings(rate="5")  # type: ignore[arg-type]
    with pytest.raises(ParameterTypeError, match="item 0 of labels is 1"):
        Settings(labels=(1,))  # type: ignore[arg-type]
