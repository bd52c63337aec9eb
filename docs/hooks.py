"""MkDocs hooks: the pages that are made from the code at build time.

- ``<!-- aaria-help: simulate -->`` in a page becomes ``aaria simulate --help`` (from click, so a
  command's options in the docs are always its options); a group (``wrist``, ``arm``) also gets
  each subcommand's help. An unknown command fails the build.
- ``api/<module>.md``: one page per public module of ``aaria_pin`` (no ``_`` in its path; the
  command line is left to the command pages), rendered from its docstrings by mkdocstrings, and
  listed in the nav under "API reference", one section per layer.
  The pages are found by walking the package tree, so moved or renamed modules need no edit here.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "aaria_pin"
HELP = re.compile(r"<!-- aaria-help: ([\w-]+) -->")


def public_modules() -> list[str]:
    """The dotted names of ``aaria_pin``'s public modules and packages, sorted."""
    names = []
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = list(path.relative_to(ROOT).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        if any(part.startswith("_") for part in parts) or parts[1:2] == ["cli"]:
            continue  # private, or the command line (its pages are under Commands)
        names.append(".".join(parts))
    return names


def _api_path(module: str) -> str:
    return "api/" + module.replace(".", "/") + ".md"


def on_config(config: Any) -> Any:
    """Fill the nav's "API reference" section with one page per module, by layer."""
    pages: list[dict[str, Any]] = [{"Overview": "api/index.md"}]
    layers: dict[str, list[dict[str, str]]] = {}
    for module in public_modules():
        parts = module.split(".")
        if len(parts) <= 2 and not (PACKAGE / parts[-1]).is_dir():
            pages.append({module: _api_path(module)})  # the front door, errors
        else:
            layers.setdefault(parts[1], []).append({module: _api_path(module)})
    order = ("core", "files", "aaria", "apps", "ml", "viz")  # bottom up, as the architecture page
    ranked = sorted(layers, key=lambda name: (order.index(name) if name in order else 99, name))
    pages += [{f"aaria_pin.{layer}": layers[layer]} for layer in ranked]
    for index, entry in enumerate(config["nav"]):
        if isinstance(entry, dict) and "API reference" in entry:
            config["nav"][index] = {"API reference": pages}
    return config


def on_files(files: Any, config: Any) -> Any:
    """Add the generated API pages (not on disk) to the site's files."""
    from mkdocs.structure.files import File

    for module in public_modules():
        content = f"# `{module}`\n\n::: {module}\n"
        files.append(File.generated(config, _api_path(module), content=content))
    return files


def command_help(name: str) -> str:
    """``aaria NAME --help`` (and each subcommand's help for a group), as Markdown."""
    import click

    from aaria_pin.cli import main

    context = click.Context(main, info_name="aaria")
    command = main.get_command(context, name)
    if command is None:
        raise ValueError(f"docs: aaria has no command {name!r} (an aaria-help marker)")
    blocks = [_help_block(command, f"aaria {name}")]
    if isinstance(command, click.Group):
        sub_context = click.Context(command, info_name=f"aaria {name}", parent=context)
        for sub in command.list_commands(sub_context):
            sub_command = command.get_command(sub_context, sub)
            assert sub_command is not None
            blocks.append(
                f"### `aaria {name} {sub}`\n\n" + _help_block(sub_command, f"aaria {name} {sub}")
            )
    return "\n\n".join(blocks)


def _help_block(command: Any, info_name: str) -> str:
    import click

    with click.Context(command, info_name=info_name, terminal_width=100) as context:
        text = command.get_help(context)
    return "```text\n" + text.rstrip() + "\n```"


def on_page_markdown(markdown: str, page: Any, config: Any, files: Any) -> str:
    """Replace each ``<!-- aaria-help: NAME -->`` marker with that command's help."""
    return HELP.sub(lambda match: command_help(match[1]), markdown)
