"""Options that do not go together: one error that names both, for Python and for the CLI.

An option that another option makes meaningless (the dynamics' ``holdout`` in a kinematic
identification, a Fourier ``motion`` of a run driven by ``torques``) is refused, never ignored.
:class:`OptionConflictError` says so in one line naming both options: by their library names
for a Python caller ("parameters is given without dynamics; allowed: parameters with
dynamics"), by their flags on the command line (:meth:`OptionConflictError.for_flag`: "--parameters
is given without --dynamics; allowed: --parameters with --dynamics").

Example::

    from aaria_pin.core.conflicts import OptionConflictError

    if holdout is not None and not dynamics:
        raise OptionConflictError(parameter="holdout", other="dynamics", given_with=False)
"""

from __future__ import annotations

from typing import Any

from aaria_pin.errors import ParameterError

__all__ = ["OptionConflictError"]


class OptionConflictError(ParameterError):
    """An option given with (or without) another option it does not go with.

    Args:
        parameter: the option at fault, as the library names it
        other: the option it conflicts with, as the library names it
        given_with: True: ``parameter`` is given with ``other`` and must not be; False: it is
            given without ``other`` and needs it
        value: the value of ``parameter``
        other_value: the value of ``other`` the rule is about (``"fourier"`` of ``motion``),
            or "" for any

    Attributes:
        other: as given
        given_with: as given
        other_value: as given
    """

    def __init__(
        self,
        *,
        parameter: str,
        other: str,
        given_with: bool,
        value: Any = None,
        other_value: str = "",
    ) -> None:
        self.other = other
        self.given_with = given_with
        self.other_value = other_value
        wanted = f"{parameter} {'without' if given_with else 'with'} {self._other(other)}"
        super().__init__(
            self._text(parameter, other),
            parameter=parameter,
            value=value,
            allowed=wanted,
        )

    def _other(self, name: str) -> str:
        """The other option with the value the rule is about: ``--motion fourier``."""
        if not self.other_value:
            return name
        return (
            f"{name} {self.other_value}" if name.startswith("-") else f"{name}={self.other_value!r}"
        )

    def _text(self, name: str, other: str) -> str:
        given, wanted = ("with", "without") if self.given_with else ("without", "with")
        other_named = self._other(other)
        return f"{name} is given {given} {other_named}; allowed: {name} {wanted} {other_named}"

    def for_flag(self, flags: dict[str, str]) -> str:
        """The message with both options named by their flags (a name without one as it is).

        Args:
            flags: parameter name → flag (``{"holdout": "--holdout"}``)

        Returns:
            The one-line message.
        """
        name = self.parameter or ""
        return self._text(flags.get(name, name), flags.get(self.other, self.other))
