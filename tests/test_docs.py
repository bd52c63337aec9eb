"""The documentation: ``mkdocs build --strict`` passes, and every code example in it runs.

Each page's ```` ```bash ```` and ```` ```python ```` blocks run in order in one temporary folder
(so a page's later blocks read the files its earlier ones wrote): ``aaria ...`` commands run
in-process through click (``> FILE`` writes their stdout to FILE), any other shell command runs
in bash, Python blocks are exec'd in one namespace per page. Every command must exit 0. Blocks
that should not run are written as ```` ```console ```` or ```` ```text ````. The README's blocks
run the same way.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
PAGES = [*sorted(DOCS.rglob("*.md")), ROOT / "README.md"]
FENCE = re.compile(r"^```(\w+)[^\n]*\n(.*?)^```$", re.MULTILINE | re.DOTALL)
RUN = ("bash", "python")


def code_blocks(text: str) -> list[tuple[str, str]]:
    """The fenced code blocks of a Markdown text, in order: (language, code)."""
    return [(match[1], match[2]) for match in FENCE.finditer(text)]


def shell_commands(code: str) -> list[list[str]]:
    """A bash block as commands (argument lists), comments dropped, ``&&`` chains split."""
    commands: list[list[str]] = []
    for line in code.replace("\\\n", " ").splitlines():
        words = shlex.split(line, comments=True)
        command: list[str] = []
        for word in [*words, "&&"]:
            if word == "&&":
                if command:
                    commands.append(command)
                command = []
            else:
                command.append(word)
    return commands


def run_shell(argv: list[str], where: Path) -> None:
    """One command: ``aaria`` in-process (stdout to a file after ``>``), anything else in bash."""
    out = None
    if ">" in argv:
        at = argv.index(">")
        argv, out = argv[:at], argv[at + 1]
    if argv[0] != "aaria":
        line = shlex.join(argv) + (f" > {shlex.quote(out)}" if out else "")
        done = subprocess.run(["bash", "-c", line], cwd=where, capture_output=True, text=True)
        assert done.returncode == 0, f"{line}: {done.stderr}"
        return
    from aaria_pin.cli import main

    result = CliRunner().invoke(main, argv[1:])
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise AssertionError(shlex.join(argv)) from result.exception
    assert result.exit_code == 0, f"{shlex.join(argv)}: exit {result.exit_code}: {result.stderr}"
    if out is not None:
        (where / out).write_text(result.stdout)


def page_id(page: Path) -> str:
    return str(page.relative_to(ROOT))


def pages_with_examples() -> list[Path]:
    return [page for page in PAGES if any(lang in RUN for lang, _ in code_blocks(page.read_text()))]


@pytest.fixture
def registries_restored() -> Iterator[None]:
    """The engine's registries of sensors and motions as they were before the test.

    The "Extending aaria_pin" page registers a toy sensor and a toy motion; other tests in the
    same process must not see them.
    """
    from aaria_pin.core.run.motion import MOTIONS
    from aaria_pin.core.run.sensor import _SENSORS

    registries: list[dict[str, Any]] = [MOTIONS, _SENSORS]
    saved = [dict(registry) for registry in registries]
    yield
    for registry, before in zip(registries, saved, strict=True):
        registry.clear()
        registry.update(before)


@pytest.mark.slow
@pytest.mark.parametrize("page", pages_with_examples(), ids=page_id)
@pytest.mark.usefixtures("registries_restored")
def test_every_example_on_the_page_runs(
    page: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    namespace: dict[str, object] = {"__name__": "__docs__"}
    ran = 0
    for language, code in code_blocks(page.read_text()):
        if language == "bash":
            for argv in shell_commands(code):
                run_shell(argv, tmp_path)
                ran += 1
        elif language == "python":
            exec(
                compile(code, str(page), "exec", dont_inherit=True), namespace
            )  # as a user runs it
            ran += 1
    assert ran > 0


def test_code_blocks_are_found_with_their_language() -> None:
    text = "a\n```bash\naaria info x.h5  # note\nls && aaria robots\n```\n```console\n$ no\n```\n"
    assert code_blocks(text) == [
        ("bash", "aaria info x.h5  # note\nls && aaria robots\n"),
        ("console", "$ no\n"),
    ]
    assert shell_commands(code_blocks(text)[0][1]) == [
        ["aaria", "info", "x.h5"],
        ["ls"],
        ["aaria", "robots"],
    ]


def test_a_failing_example_fails_and_stdout_goes_to_its_file(tmp_path: Path) -> None:
    with pytest.raises(AssertionError, match="exit 2"):
        run_shell(["aaria", "info", str(tmp_path / "missing.h5")], tmp_path)
    with pytest.raises(AssertionError, match="false"):
        run_shell(["false"], tmp_path)
    run_shell(["aaria", "template", "dh", ">", "table.csv"], tmp_path)
    lines = (tmp_path / "table.csv").read_text().splitlines()
    header, *rows = [line for line in lines if line.strip() and not line.startswith("#")]
    assert header.split(",")[0] == "alpha [rad]"
    assert np.array([row.split(",") for row in rows], dtype=float).shape == (8, 5)  # Aaria's table


def fence_openings(text: str) -> list[str]:
    """The info string of every opening code fence (``""`` for a fence without a language)."""
    openings, inside = [], False
    for line in text.splitlines():
        if line.startswith("```"):
            if not inside:
                openings.append(line[3:].strip())
            inside = not inside
    assert not inside, "a code fence is not closed"
    return openings


def test_every_block_has_a_language() -> None:
    assert fence_openings("```bash\nx\n```\ntext\n```\ny\n```\n") == ["bash", ""]
    for page in PAGES:
        assert "" not in fence_openings(page.read_text()), (
            f"{page_id(page)}: a block without a language"
        )


def test_the_command_pages_cover_every_command() -> None:
    import click

    from aaria_pin.cli import main

    context = click.Context(main, info_name="aaria")
    marked = {
        name
        for page in (DOCS / "commands").glob("*.md")
        for name in re.findall(r"<!-- aaria-help: ([\w-]+) -->", page.read_text())
    }
    assert marked == set(main.list_commands(context))


def test_readme_is_short_and_links_into_the_docs() -> None:
    text = (ROOT / "README.md").read_text()
    assert len(text.splitlines()) <= 300
    for link in re.findall(r"\]\((docs/[^)#]+)", text):
        assert (ROOT / link).is_file(), link


@pytest.mark.slow
def test_mkdocs_build_strict(tmp_path: Path) -> None:
    env = {**os.environ, "PYTHONPATH": str(ROOT), "NO_MKDOCS_2_WARNING": "1"}
    site = tmp_path / "site"
    done = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(site)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        env=env,
    )
    assert done.returncode == 0, done.stderr[-4000:]
    # the generated pages are there: a command's options and a module's API
    simulate = (site / "commands" / "simulate" / "index.html").read_text()
    assert "--duration" in simulate
    api = (site / "api" / "aaria_pin" / "index.html").read_text()
    assert "simulate_run" in api


def named_in_text(text: str) -> set[str]:
    """The package's modules and objects a text names (``aaria_pin.x.y``, ``aaria_pin/x/y.py``)."""
    dotted = {name for name in re.findall(r"\baaria_pin(?:\.\w+)+", text) if name[-3:] != ".md"}
    paths = re.findall(r"\baaria_pin/[\w/]*\w(?:\.py)?", text)
    return dotted | {path.removesuffix(".py").replace("/", ".") for path in paths}


def resolves(name: str) -> bool:
    """Whether ``name`` is a module of the tree, or a module and a name it defines or exports.

    A name is defined by a top-level ``def``, ``class`` or assignment, and exported by an entry of
    the module's ``__all__`` (a package re-exporting a name of its modules) or of a lazy-import
    table (``"name": "module"``, as the front door's).
    """
    parts = name.split(".")
    for cut in range(len(parts), 0, -1):
        base = ROOT.joinpath(*parts[:cut])
        source = base / "__init__.py" if base.is_dir() else base.with_suffix(".py")
        if base.is_dir() or source.is_file():
            rest = parts[cut:]
            if not rest:
                return True
            text = source.read_text() if source.is_file() else ""
            defined = rf"^(?:def|class) {rest[0]}\b|^{rest[0]}\b\s*[:=]|^\s+\"{rest[0]}\"(?::|,$)"
            return len(rest) <= 2 and re.search(defined, text, re.MULTILINE) is not None
    return False


def test_named_modules_and_objects_exist() -> None:
    assert named_in_text("see `aaria_pin.core.rotations` and aaria_pin/viz/vendor") == {
        "aaria_pin.core.rotations",
        "aaria_pin.viz.vendor",
    }
    assert resolves("aaria_pin.errors.AariaError") and not resolves("aaria_pin.errors.Nope")
    assert resolves("aaria_pin.core.run.RunSettings")  # exported by the package's __all__
    assert resolves("aaria_pin.wrist_fk")  # the front door's lazy table
    missing = {
        f"{page_id(page)}: {name}"
        for page in PAGES
        for name in named_in_text(page.read_text())
        if not resolves(name)
    }
    assert not missing, sorted(missing)
