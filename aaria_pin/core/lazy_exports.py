"""Names a package exports but imports on first use (PEP 562), so importing it stays light.

The front door (``aaria_pin``) and the packages that export a few names of their modules
(``aaria_pin.apps.dataset``, ``aaria_pin.apps.wrist``) map each exported name to the module that
defines it and set their module ``__getattr__`` to :func:`lazy_exports` of that map: a name is
imported when first read, then kept in the package's namespace. Type checkers see the real
objects through the package's ``TYPE_CHECKING`` imports.
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Mapping
from importlib import import_module
from typing import Any

__all__ = ["lazy_exports"]


def lazy_exports(package: str, modules: Mapping[str, str]) -> Callable[[str], Any]:
    """A module ``__getattr__`` that imports each exported name from its module on first use.

    Args:
        package: the exporting package's ``__name__``
        modules: each exported name → the dotted name of the module that defines it

    Returns:
        ``__getattr__(name)``: the object, kept in the package's namespace after the first read.
        Any other name raises ``AttributeError``, as a module does.
    """

    def lazy_attribute(name: str) -> Any:
        if name not in modules:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(import_module(modules[name]), name)
        setattr(sys.modules[package], name, value)
        return value

    return lazy_attribute
