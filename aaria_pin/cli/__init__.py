"""The ``aaria`` command line: thin click commands over the library.

Each command parses its options, calls one library function and prints. Heavy imports
(Pinocchio, h5py, scipy) happen inside the commands that need them, so ``aaria --help`` stays
fast. Any :class:`~aaria_pin.errors.AariaError` becomes a one-line message on stderr and exit
status 2.
"""

from __future__ import annotations

from aaria_pin.cli._app import main

__all__ = ["main"]
