"""Every error of the family the package makes names its parameter (a walk over the AST).

An :class:`~aaria_pin.errors.AariaError` carries the library parameter at fault
(``parameter=``), so the CLI can name its flag (:meth:`~aaria_pin.errors.AariaError.for_flag`)
and a Python caller can read it without parsing the message. This test reads every module of
``aaria_pin`` and fails on a construction of an error of the family (``raise X(...)``, or
``X(...)`` made in a helper that returns it) that passes no ``parameter=``, naming file:line.
"""

from __future__ import annotations

import ast
import inspect
from pathlib import Path

import aaria_pin.errors as errors_module
from aaria_pin.errors import AariaError

PACKAGE = Path(__file__).resolve().parent.parent / "aaria_pin"


def _family(trees: dict[Path, ast.Module]) -> set[str]:
    """Names of the error classes of the family: those of ``errors.py`` and their subclasses
    defined anywhere in the package (found by their bases' names, to a fixed point)."""
    names = {
        name
        for name, value in inspect.getmembers(errors_module, inspect.isclass)
        if issubclass(value, AariaError)
    }
    grown = True
    while grown:
        grown = False
        for tree in trees.values():
            for node in ast.walk(tree):
                if isinstance(node, ast.ClassDef) and node.name not in names:
                    bases = {_called_name(base) for base in node.bases}
                    if bases & names:
                        names.add(node.name)
                        grown = True
    return names


def _called_name(node: ast.expr) -> str | None:
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        return node.attr
    return None


def _names_its_parameter(call: ast.Call) -> bool:
    for keyword in call.keywords:
        if keyword.arg is None:  # **fields: cannot be read here, so it is not enough
            continue
        if keyword.arg == "parameter":
            return not (isinstance(keyword.value, ast.Constant) and keyword.value.value is None)
    return False


def message_only_sites(trees: dict[Path, ast.Module], family: set[str]) -> list[str]:
    """``file:line Name`` of every construction (or bare raise) of a family error without a
    ``parameter``.

    Args:
        trees: parsed modules by path (relative to the package, as they are reported)
        family: the error classes' names

    Returns:
        The sites, sorted by file and line.
    """
    found: list[tuple[str, int, str]] = []
    for path, tree in trees.items():
        for node in ast.walk(tree):
            if isinstance(node, ast.Call):
                name = _called_name(node.func)
                if name in family and not _names_its_parameter(node):
                    found.append((str(path), node.lineno, name))
            elif isinstance(node, ast.Raise) and node.exc is not None:
                name = _called_name(node.exc)
                if name in family and not isinstance(node.exc, ast.Call):
                    found.append((str(path), node.lineno, name))
    return [f"{path}:{line} {name}" for path, line, name in sorted(found)]


def _package_trees() -> dict[Path, ast.Module]:
    return {
        path.relative_to(PACKAGE.parent): ast.parse(path.read_text(encoding="utf-8"), str(path))
        for path in sorted(PACKAGE.rglob("*.py"))
    }


def test_every_error_of_the_family_names_its_parameter() -> None:
    trees = _package_trees()
    family = _family(trees)
    assert {"ParameterError", "TableError", "InputFileError", "NoSpaceError"} <= family
    sites = message_only_sites(trees, family)
    assert not sites, "raises without parameter=:\n" + "\n".join(sites)


def test_the_walk_finds_a_message_only_raise() -> None:
    source = (
        "from aaria_pin import errors\n"
        "from aaria_pin.errors import ParameterError, TableError\n"
        "class MineError(errors.ModelError): ...\n"
        "def f(x):\n"
        "    if x < 0:\n"
        "        raise ParameterError(f'x is {x}; allowed: >= 0')\n"  # line 6: no parameter
        "    if x > 9:\n"
        "        raise ParameterError(parameter='x', value=x, allowed='<= 9')\n"
        "    if x == 3:\n"
        "        raise MineError('three', parameter=None)\n"  # line 10: None names nothing
        "    if x == 4:\n"
        "        raise errors.TableError\n"  # line 12: a bare class
        "    return TableError('made here, raised by the caller')\n"  # line 13
        "def g(x):\n"
        "    raise ValueError('not of the family')\n"
    )
    trees = {Path("sample.py"): ast.parse(source)}
    family = _family(trees)
    assert "MineError" in family
    assert message_only_sites(trees, family) == [
        "sample.py:6 ParameterError",
        "sample.py:10 MineError",
        "sample.py:12 TableError",
        "sample.py:13 TableError",
    ]
