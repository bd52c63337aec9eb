"""The exception family of aaria_pin: errors that carry their data.

Every error the toolkit raises on bad input derives from :class:`AariaError`. Its message is one
line, "X is Y; allowed: Z", so the CLI prints it as it is (exit status 2), and the pieces are
fields a Python caller can read without parsing text:

- ``parameter``: the library parameter at fault (``"duration"``, ``"joint_table"``), named as in
  the function's signature; the CLI names its flag instead (:meth:`AariaError.for_flag`);
- ``value``: the value given;
- ``allowed``: what is allowed, as text;
- ``element``: where in the value (``"row 3, column 2"``, a joint or link name, a file path).

Every error the package makes names its ``parameter`` (``tests/test_raise_sites.py`` walks the
package's AST for one that does not). The CLI recomposes the message around its flag when the
error also has ``allowed``; an error whose message must reach the user as written (it names its
file, or the table by its title) leaves ``allowed`` out of the fields.

An :class:`OutputFileError` and an :class:`InputFileError` are also :class:`OSError`, so code that
handles file errors catches them; a :class:`ParameterTypeError` (an argument of the wrong type) is
also a :class:`TypeError`.
"""

from __future__ import annotations

import re
from typing import Any

__all__ = [
    "AariaError",
    "InputFileError",
    "JointLimitError",
    "MeshWarning",
    "ModelError",
    "NoSpaceError",
    "OutputFileError",
    "ParameterError",
    "ParameterTypeError",
    "RunFailedError",
    "TableError",
    "TableTypeError",
    "TrackingError",
    "UrdfError",
    "plain_message",
]


_SHOWN_ITEMS = 8
"""Most numbers of an array or sequence a message shows (then "…" and the shape)."""

_NUMPY_REPR = re.compile(
    r"np\.(?:True_|False_|(?:float|int|uint|complex|bool|str_|bytes_)\w*\((.*?)\))"
)
"""A NumPy scalar as ``repr`` (NumPy 2) writes it: ``np.float64(1.5)``, ``np.True_``."""


def _plain_numpy(match: re.Match[str]) -> str:
    text = match.group(0)
    if text in ("np.True_", "np.False_"):
        return text[3:-1]
    return match.group(1)


def plain_message(text: str) -> str:
    """``text`` with NumPy scalar reprs written as plain values (``np.float64(0.5)`` → ``0.5``).

    Messages composed with ``{value!r}`` or from lists of NumPy numbers would otherwise show
    ``np.float64(…)``; every :class:`AariaError` passes its message through this.
    """
    return _NUMPY_REPR.sub(_plain_numpy, text) if "np." in text else text


def _shown(value: Any) -> str:
    """A value as the message shows it: numbers with %g, text quoted, arrays as plain lists.

    NumPy scalars show as Python numbers (``nan``, ``1.5``), arrays as ``[1, 2.5, nan]`` (at
    most :data:`_SHOWN_ITEMS` values, then ``…`` and the shape), the rest by ``repr`` with
    NumPy scalars in it plain (:func:`plain_message`). NumPy is not imported: its values are
    recognised by their methods.
    """
    if getattr(value, "ndim", None) == 0 and hasattr(value, "item"):
        value = value.item()  # a NumPy scalar or 0-d array: the Python number
    if isinstance(value, bool):
        return str(value)
    if isinstance(value, int):
        return str(value)  # 100000000000, not 1e+11
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, str):
        return repr(value)
    shape = getattr(value, "shape", None)
    if shape is not None and hasattr(value, "ravel") and hasattr(value, "tolist"):
        items = value.ravel()[: _SHOWN_ITEMS + 1].tolist()
        size = 1
        for extent in shape:
            size *= int(extent)
        shown = "[" + ", ".join(_shown(item) for item in items[:_SHOWN_ITEMS])
        if size > _SHOWN_ITEMS or len(shape) > 1:
            more = ", …" if size > _SHOWN_ITEMS else ""
            return f"{shown}{more}] (shape {' × '.join(map(str, shape))})"
        return shown + "]"
    return plain_message(repr(value))  # a list or tuple of NumPy numbers shows them plainly


class AariaError(ValueError):
    """Base class of every input error raised by aaria_pin.

    Args:
        message: the whole one-line message; left out, it is composed from the fields as
            ``"<element> of <parameter> is <value>; allowed: <allowed>"``
        parameter: the parameter at fault, as the library names it
        value: the value given
        allowed: what is allowed, as text
        element: where in the value (a row and column, a joint, a file)

    Attributes:
        parameter: as given (None when the error is not about one parameter)
        value: as given
        allowed: as given
        element: as given
    """

    def __init__(
        self,
        message: str | None = None,
        *,
        parameter: str | None = None,
        value: Any = None,
        allowed: str | None = None,
        element: str | None = None,
    ) -> None:
        self.parameter = parameter
        self.value = value
        self.allowed = allowed
        self.element = element
        super().__init__(
            plain_message(message) if message is not None else self._compose(parameter)
        )

    def _compose(self, name: str | None) -> str:
        subject = " of ".join(part for part in (self.element, name) if part) or "input"
        text = f"{subject} is {_shown(self.value)}"
        whole = f"{text}; allowed: {self.allowed}" if self.allowed is not None else text
        return plain_message(whole)

    def for_flag(self, flags: dict[str, str]) -> str:
        """The message with the parameter named by its command-line flag.

        Args:
            flags: parameter name → flag (``{"duration": "--duration"}``)

        Returns:
            The composed message naming the flag when the error has a ``parameter`` that
            ``flags`` maps and a ``value`` and ``allowed`` to compose from; else the message.
        """
        if self.parameter in flags and self.allowed is not None:
            return self._compose(flags[self.parameter])
        return str(self)


class TableError(AariaError):
    """A DH or oscillation table has the wrong shape or a value outside its allowed set."""


class ParameterError(AariaError):
    """A scalar parameter (density, cross-section, rate, duration, ...) is out of range."""


class ParameterTypeError(ParameterError, TypeError):
    """An argument of the wrong type (None, text for a number, an object for a path, ...).

    Also a :class:`TypeError`, as Python's own error for a wrong type is, so a caller catches it
    either way; as every :class:`AariaError` it names its ``parameter`` and is one line.
    """


class TableTypeError(TableError, ParameterTypeError):
    """An array or table argument of the wrong type (text, booleans, objects, None).

    A :class:`TableError` (as a table's bad values are) and a :class:`ParameterTypeError`.
    """


class InputFileError(AariaError, OSError):
    """An input file is missing, unreadable or does not hold what was asked for."""


class OutputFileError(AariaError, OSError):
    """An output file cannot be written (an :class:`OSError` too)."""


class NoSpaceError(OutputFileError):
    """No room left on the device while writing an output.

    The CLI exits with status 1, not 2: the input was fine, the machine was not.
    """


class RunFailedError(AariaError):
    """A run whose inputs were fine failed as it went (its motion left what it may do).

    The CLI exits with status 1, not 2: the input was fine, the run was not.
    """


class JointLimitError(RunFailedError):
    """A torque-driven run left its joints' limits under the policy ``stop`` (``limits``).

    The CLI exits with status 1, not 2: the input was fine, the motion left the range.
    """


class TrackingError(RunFailedError):
    """A closed-loop run lost its reference (an unstable loop, or motors too weak for it).

    The CLI exits with status 1: the message names the joint, the time and the gains.
    """


class ModelError(AariaError):
    """A robot description cannot be turned into a model (bad URDF, unknown frame, ...)."""


class UrdfError(ModelError):
    """A URDF document is malformed or describes no physical robot (names the link or joint)."""


class MeshWarning(UserWarning):
    """A mesh a URDF refers to is missing (it still simulates: inertias come from the URDF)."""
