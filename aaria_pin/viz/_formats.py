"""Suffixes of the pictures written (a module of constants only, light to import for the CLI)."""

from __future__ import annotations

__all__ = ["PICTURE_SUFFIXES"]

PICTURE_SUFFIXES = (".png", ".pdf", ".svg")
"""Suffixes of the pictures written, each its format (lower case, with the dot)."""
