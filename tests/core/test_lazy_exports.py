"""Lazy exports: a name is imported from its module when first read, then kept."""

from __future__ import annotations

import math
import sys
import types

import pytest

from aaria_pin.core.lazy_exports import lazy_exports


def test_a_name_is_imported_on_first_read_and_kept(monkeypatch: pytest.MonkeyPatch) -> None:
    package = types.ModuleType("lazy_pkg")
    monkeypatch.setitem(sys.modules, "lazy_pkg", package)
    lookup = lazy_exports("lazy_pkg", {"sqrt": "math"})
    package.__getattr__ = lookup  # type: ignore[method-assign]
    assert "sqrt" not in vars(package)
    assert package.sqrt is math.sqrt  # through __getattr__ (PEP 562)
    assert vars(package)["sqrt"] is math.sqrt  # kept: the next read is a plain attribute
    with pytest.raises(AttributeError, match="module 'lazy_pkg' has no attribute 'cos'"):
        lookup("cos")  # math has it, but the package does not export it
