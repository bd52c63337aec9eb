"""The exception family of aaria_pin.

Every error the toolkit raises on bad input derives from :class:`AariaError`. Messages are
one line and name the offending value and what is allowed, so the CLI can print them as they
are (exit status 2) and a Python caller can catch the whole family at once.
"""

from __future__ import annotations

__all__ = [
    "AariaError",
    "InputFileError",
    "MeshWarning",
    "ModelError",
    "OutputFileError",
    "ParameterError",
    "TableError",
    "UrdfError",
]


class AariaError(ValueError):
    """Base class of every input error raised by aaria_pin."""


class TableError(AariaError):
    """A DH or oscillation table has the wrong shape or a value outside its allowed set."""


class ParameterError(AariaError):
    """A scalar parameter (density, cross-section, rate, duration, ...) is out of range."""


class InputFileError(AariaError):
    """An input file is missing, unreadable or does not hold what was asked for."""


class OutputFileError(AariaError):
    """An output file cannot be written."""


class ModelError(AariaError):
    """A robot description cannot be turned into a model (bad URDF, unknown frame, ...)."""


class UrdfError(ModelError):
    """A URDF document is malformed or describes no physical robot (names the link or joint)."""


class MeshWarning(UserWarning):
    """A mesh a URDF refers to is missing (it still simulates: inertias come from the URDF)."""
