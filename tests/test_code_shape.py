"""The package's shape as the issue of the run engine set it: modules of one concept (under 500
lines), a thin command line (at most 2,000 lines), no public function with more than 8 parameters,
and one file name per module across the layers."""

from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "aaria_pin"
MAX_MODULE_LINES = 500
MAX_CLI_LINES = 2000
MAX_PARAMETERS = 8


def modules() -> list[Path]:
    return sorted(p for p in PACKAGE.rglob("*.py") if "vendor" not in p.parts)


def lines(path: Path) -> int:
    return path.read_text(encoding="utf-8").count("\n")


def public_functions(path: Path, root: Path = PACKAGE.parent) -> list[tuple[str, int]]:
    """(name, parameter count) of the public functions and methods of a public module.

    Functions of private modules (``_kernel.py``: numba kernels over flat arrays) are not public.
    ``self``/``cls`` and ``*args``/``**kwargs`` are not counted (keyword options arrive typed, as
    ``**options: Unpack[...]``).
    """
    if any(part.startswith("_") and part != "__init__.py" for part in path.parts[-2:]):
        return []
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and not node.name.startswith(
            "_"
        ):
            args = node.args
            names = [a.arg for a in (*args.posonlyargs, *args.args, *args.kwonlyargs)]
            count = len([n for n in names if n not in ("self", "cls")])
            found.append((f"{path.relative_to(root)}:{node.lineno} {node.name}", count))
    return found


def test_no_module_over_500_lines() -> None:
    big = {str(p.relative_to(PACKAGE.parent)): lines(p) for p in modules()}
    assert {k: v for k, v in big.items() if v >= MAX_MODULE_LINES} == {}


def test_the_command_line_is_thin() -> None:
    total = sum(lines(p) for p in (PACKAGE / "cli").glob("*.py"))
    assert total <= MAX_CLI_LINES, total


def test_no_public_function_takes_more_than_8_parameters() -> None:
    wide = [(name, n) for p in modules() for name, n in public_functions(p) if n > MAX_PARAMETERS]
    assert wide == []


def test_the_parameter_count_sees_a_wide_function(tmp_path: Path) -> None:
    (tmp_path / "wide.py").write_text(
        "class A:\n    def m(self, a, *, b=0, **rest):\n        pass\n"
        "def f(a, b, c, d, e, f, g, h, *, i=0, **rest):\n    pass\n"
        "def _private(a, b, c, d, e, f, g, h, i):\n    pass\n"
    )
    (tmp_path / "_kernel.py").write_text("def k(a, b, c, d, e, f, g, h, i):\n    pass\n")
    counts = sorted(n for _, n in public_functions(tmp_path / "wide.py", tmp_path))
    assert counts == [2, 9]
    assert public_functions(tmp_path / "_kernel.py", tmp_path) == []


def test_module_names_are_distinct_across_layers() -> None:
    by_name: dict[str, set[str]] = defaultdict(set)
    for path in modules():
        if path.name != "__init__.py":
            layer = path.relative_to(PACKAGE).parts[0]
            by_name[path.name].add(layer)
    assert {name: sorted(layers) for name, layers in by_name.items() if len(layers) > 1} == {}
