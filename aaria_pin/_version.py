"""The package version (a module of its own, so any layer can read it without a cycle)."""

__version__ = "0.3.0"
