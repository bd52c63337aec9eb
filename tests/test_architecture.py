"""The package's architecture as a contract: layers and no import cycle (import-linter), the README.

The layers are ``cli > viz > ml > apps > aaria > files > core`` (a layer imports only those below);
``lint-imports`` checks the contracts written in ``pyproject.toml``. "No import cycle" is the
``acyclic_siblings`` contract over the whole package: at every depth, the children of a package
(its modules and sub-packages, each taken whole) import one another without a cycle. The one
cycle that contract cannot see, a package's ``__init__`` importing a module of the package that
imports the ``__init__`` back, is checked here over grimp's graph (the one import-linter builds).
Together they leave no cycle: a cycle's modules lie in some smallest package; either they span
two of its children (the contract) or the cycle passes through its ``__init__`` (this test).
Both checks are shown able to fail on small packages made with a cycle.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
LAYERS = ("cli", "viz", "ml", "apps", "aaria", "files", "core")
CONFIG = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]


def _lint_imports(*arguments: str, cwd: Path = ROOT, path: Path | None = None) -> str:
    """``lint-imports`` run in ``cwd`` (``path`` first on the import path); its output."""
    environment = dict(os.environ)
    if path is not None:
        environment["PYTHONPATH"] = os.pathsep.join([str(path), environment.get("PYTHONPATH", "")])
    result = subprocess.run(
        [str(Path(sys.executable).with_name("lint-imports")), "--no-logo", *arguments],
        cwd=cwd,
        capture_output=True,
        text=True,
        env=environment,
    )
    assert result.returncode in (0, 1), result.stdout + result.stderr
    return result.stdout + result.stderr


def cycles_through_a_front(package: str) -> list[tuple[str, str]]:
    """(front, module) pairs: a package's ``__init__`` reaches a module of it that imports it.

    Args:
        package: the root package to build the graph of

    Returns:
        Every ``(front, module)`` where ``module`` is inside the package ``front``, imports
        ``front`` directly and is imported by ``front`` (directly or through other modules).
    """
    import grimp

    graph = grimp.build_graph(package, cache_dir=None)
    found = []
    for front in sorted(m for m in graph.modules if graph.find_children(m)):
        inside = graph.find_descendants(front)
        for module in sorted(graph.find_modules_that_directly_import(front) & inside):
            if graph.chain_exists(importer=front, imported=module):
                found.append((front, module))
    return found


def _package(folder: Path, name: str, modules: dict[str, str]) -> None:
    """Write package ``name`` into ``folder``: module path → source (``__init__`` for fronts)."""
    for module, source in {"__init__": "", **modules}.items():
        path = folder / name / (module.replace(".", "/") + ".py")
        path.parent.mkdir(parents=True, exist_ok=True)
        for parent in path.relative_to(folder).parents[:-1]:
            (folder / parent / "__init__.py").touch()
        path.write_text(source)


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
    acyclic = next(c for c in CONFIG["contracts"] if c["type"] == "acyclic_siblings")
    assert acyclic["ancestors"] == ["aaria_pin"] and acyclic.get("depth", 10) >= 10
    assert "Contracts: 1 kept, 0 broken." in _lint_imports("--contract", "acyclic")
    assert cycles_through_a_front("aaria_pin") == []


def _acyclic_config(folder: Path, package: str) -> Path:
    """Our acyclic contract, as ``pyproject.toml`` writes it, for another root package."""
    acyclic = next(c for c in CONFIG["contracts"] if c["type"] == "acyclic_siblings")
    config = folder / "importlinter.toml"
    ancestors = ", ".join(f'"{a.replace("aaria_pin", package)}"' for a in acyclic["ancestors"])
    config.write_text(
        f'[tool.importlinter]\nroot_package = "{package}"\n\n'
        f'[[tool.importlinter.contracts]]\nid = "acyclic"\nname = "{acyclic["name"]}"\n'
        f'type = "{acyclic["type"]}"\nancestors = [{ancestors}]\n'
    )
    return config


@pytest.mark.parametrize("inner", ["", "deep.er."])
def test_the_acyclic_contract_finds_a_cycle(tmp_path: Path, inner: str) -> None:
    """a → b → c → a, at the top or two packages down: the contract names the package."""
    package = "cyclic_pkg." + inner if inner else "cyclic_pkg."
    modules = {
        "a": f"from {package[:-1]} import b\n",
        "b": f"from {package}c import x\n",
        "c": f"import {package}a\nx = 1\n",
        "d": f"import {package}a\n",
    }
    _package(tmp_path, "cyclic_pkg", {inner + name: source for name, source in modules.items()})
    config = _acyclic_config(tmp_path, "cyclic_pkg")
    output = _lint_imports(str(config), "--no-cache", cwd=tmp_path, path=tmp_path)
    assert "Contracts: 0 kept, 1 broken." in output, output
    assert f"No cycles are allowed in {package[:-1]}." in output
    _package(tmp_path, "cyclic_pkg", {inner + "c": "x = 1\n"})  # the cycle cut
    output = _lint_imports(str(config), "--no-cache", cwd=tmp_path, path=tmp_path)
    assert "Contracts: 1 kept, 0 broken." in output, output


def test_a_cycle_through_a_package_front_is_found(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The front re-exports its module, which imports the front: the contract cannot see it."""
    _package(
        tmp_path,
        "front_pkg",
        {
            "sub.__init__": "from front_pkg.sub.m import f\n",
            "sub.m": "import front_pkg.sub\ndef f() -> None: ...\n",
            "sub.n": "import front_pkg.sub\n",  # imports the front, but the front does not reach it
            "main": "import front_pkg\n",  # the root's front imports nothing: no cycle
        },
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    output = _lint_imports(
        str(_acyclic_config(tmp_path, "front_pkg")), "--no-cache", cwd=tmp_path, path=tmp_path
    )
    assert "Contracts: 1 kept, 0 broken." in output, output  # why this test exists
    assert cycles_through_a_front("front_pkg") == [("front_pkg.sub", "front_pkg.sub.m")]


def test_readme_architecture_section_matches_the_tree() -> None:
    text = (ROOT / "README.md").read_text()
    section = text.split("## Architecture", 1)[1].split("\n## ", 1)[0]
    named = re.findall(r"^\| `aaria_pin/(\w+)/` \|", section, flags=re.MULTILINE)
    assert tuple(named) == LAYERS
