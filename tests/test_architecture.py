"""The package's architecture as a contract: layers (import-linter), no import cycle, the README.

The layers are ``cli > viz > apps > aaria > files > core`` (a layer imports only those below);
``lint-imports`` checks the contract written in ``pyproject.toml``. The cycle check is our own,
over grimp's import graph (the library import-linter is built on), and is shown able to fail on
a package made with a cycle.
"""

from __future__ import annotations

import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
LAYERS = ("cli", "viz", "apps", "aaria", "files", "core")


def import_cycles(package: str) -> list[list[str]]:
    """Strongly connected groups of more than one module in a package's import graph (Tarjan)."""
    import grimp

    graph = grimp.build_graph(package, cache_dir=None)
    edges = {m: sorted(graph.find_modules_directly_imported_by(m)) for m in graph.modules}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    groups: list[list[str]] = []
    counter = 0

    def visit(root: str) -> None:
        nonlocal counter
        work = [(root, 0)]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            node, i = work[-1]
            targets = edges.get(node, [])
            if i < len(targets):
                work[-1] = (node, i + 1)
                target = targets[i]
                if target not in index:
                    index[target] = low[target] = counter
                    counter += 1
                    stack.append(target)
                    on_stack.add(target)
                    work.append((target, 0))
                elif target in on_stack:
                    low[node] = min(low[node], index[target])
                continue
            work.pop()
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[node])
            if low[node] == index[node]:
                group = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    group.append(member)
                    if member == node:
                        break
                if len(group) > 1:
                    groups.append(sorted(group))

    for module in sorted(edges):
        if module not in index:
            visit(module)
    return groups


def test_layers_contract_holds() -> None:
    result = subprocess.run(
        [str(Path(sys.executable).with_name("lint-imports"))],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )
    assert result.returncode == 0, result.stdout + result.stderr
    assert "BROKEN" not in result.stdout


def test_layers_contract_names_every_layer_folder() -> None:
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]
    layers = next(c for c in config["contracts"] if c["type"] == "layers")["layers"]
    assert layers == [f"aaria_pin.{name}" for name in LAYERS]
    for name in LAYERS:
        assert (ROOT / "aaria_pin" / name / "__init__.py").is_file()
    loose = {p.stem for p in (ROOT / "aaria_pin").glob("*.py")} - {"__init__", "errors", "_version"}
    assert not loose, f"modules outside the layer folders: {sorted(loose)}"


def test_no_import_cycle_in_the_package() -> None:
    assert import_cycles("aaria_pin") == []


def test_the_cycle_check_finds_a_cycle(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    package = tmp_path / "cyclic_pkg"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "a.py").write_text("from cyclic_pkg import b\n")
    (package / "b.py").write_text("from cyclic_pkg.c import x\n")
    (package / "c.py").write_text("import cyclic_pkg.a\nx = 1\n")
    (package / "d.py").write_text("import cyclic_pkg.a\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    assert import_cycles("cyclic_pkg") == [["cyclic_pkg.a", "cyclic_pkg.b", "cyclic_pkg.c"]]


def test_readme_architecture_section_matches_the_tree() -> None:
    text = (ROOT / "README.md").read_text()
    section = text.split("## Architecture", 1)[1].split("\n## ", 1)[0]
    named = re.findall(r"^\| `aaria_pin/(\w+)/` \|", section, flags=re.MULTILINE)
    assert tuple(named) == LAYERS
