"""The click group, and the one mapping of a library error to the command line's words."""

from __future__ import annotations

import warnings
from typing import Any

import click

from aaria_pin.apps.run_progress import end_progress_line
from aaria_pin.errors import AariaError, NoSpaceError, RunFailedError

EXIT_BAD_INPUT = 2

PARAMETER_FLAGS = {"joint_table": "--joints", "base_table": "--base", "path": "-o/--output"}
PARAMETER_FLAGS.update(table="--dh", dh_table="--dh")
"""Library parameters whose flag is not named after them, in every command (``path`` is an
output's: an input file's error names ``file`` or its caller's parameter, never ``path``)."""

COMMAND_FLAGS: dict[str, dict[str, str]] = {}
"""A command's own exceptions (command name → parameter → flag), over the rules above."""

_FAILED = "aaria_pin.failed"
"""The key of ``ctx.meta`` set when a command ended in an error (its warnings are not shown)."""

_COMMAND = "aaria_pin.command"
"""The key of ``ctx.meta`` (shared by the nested contexts) naming the command that runs."""


def flag_names(command: click.Command | None) -> dict[str, str]:
    """Library parameter name → the flag that sets it, for one command.

    A parameter maps to the option of the same name (``run_index`` → ``--run``) or spelled
    after it (``imu_layout`` → ``--imu-layout``), else by :data:`PARAMETER_FLAGS`; the
    command's entry in :data:`COMMAND_FLAGS` goes over both.
    """
    flags = dict(PARAMETER_FLAGS)
    params = command.params if command is not None else []
    for param in params:
        if isinstance(param, click.Option) and param.name:
            long = max(param.opts, key=len)
            flags[param.name] = long
            flags[long.lstrip("-").replace("-", "_")] = long
    flags.update(COMMAND_FLAGS.get(command.name or "", {}) if command is not None else {})
    return flags


def flag_message(error: AariaError, command: click.Command | None) -> str:
    """The error's one line, its parameter named by the command's flag."""
    flags = flag_names(command)
    message = error.for_flag(flags)
    name = error.parameter
    if name in flags and message.startswith(f"{name} "):  # "run is …" → "--run is …"
        message = flags[name] + message[len(name) :]
    return " ".join(message.split())


def _show_warnings(caught: list[warnings.WarningMessage]) -> None:
    """A command's warnings, one line each on stderr, once it has run (an error: its line only)."""
    for warning in caught:
        click.echo(f"aaria: warning: {' '.join(str(warning.message).split())}", err=True)


class AariaGroup(click.Group):
    """A group that notes in ``ctx.meta`` which command runs (the innermost group's wins)."""

    def resolve_command(self, ctx: click.Context, args: list[str]) -> Any:
        """As click's, noting the command."""
        name, command, rest = super().resolve_command(ctx, args)
        ctx.meta[_COMMAND] = command
        return name, command, rest


class _Main(AariaGroup):
    """The ``aaria`` group: the toolkit's input errors become one line and exit status 2."""

    def main(self, args: Any = None, *rest: Any, **kwargs: Any) -> Any:
        """Run the command line; as the ``aaria`` process (arguments from ``sys.argv``), end fast.

        When the process ends, Python tears its modules down and runs the garbage collector
        over every object still alive; after a command that ran a compiled kernel that heap
        holds numba's registries and took 0.25–0.35 s of a 1.0 s ``aaria simulate`` (measured
        between the command's end and the process's). ``gc.freeze()`` as the command returns
        moves those objects out of the collector's sight: the exit then takes about 0.04 s.
        Outputs are closed by then (``atomic_output``), exit handlers still run and the
        standard streams are still flushed. A caller that passes ``args`` (tests, scripts
        calling :func:`main` in their own process) keeps its collector as it was.
        """
        if args is None:  # the aaria process: numba loads without its BLAS probe
            from aaria_pin.core._compile import light_start

            light_start()  # 0.23 s of a 1 s `aaria simulate`; callers passing args keep it
        try:
            return super().main(args, *rest, **kwargs)
        finally:
            if args is None and kwargs.get("standalone_mode", True):
                import gc

                gc.freeze()

    def make_context(self, *args: Any, **kwargs: Any) -> click.Context:
        """As click's; a top-level usage error (``aaria --frob``) is one line (exit 2) too."""
        try:
            return super().make_context(*args, **kwargs)
        except click.exceptions.NoArgsIsHelpError:
            raise
        except click.UsageError as exc:
            click.echo(f"aaria: error: {' '.join(exc.format_message().split())}", err=True)
            raise click.exceptions.Exit(EXIT_BAD_INPUT) from None

    def invoke(self, ctx: click.Context) -> Any:
        with warnings.catch_warnings(record=True) as caught:
            try:
                return self._invoke(ctx)
            finally:
                if not ctx.meta.get(_FAILED):
                    _show_warnings(caught)

    def _invoke(self, ctx: click.Context) -> Any:
        try:
            return super().invoke(ctx)
        except (NoSpaceError, RunFailedError) as exc:  # the input was fine: exit 1 (a failure)
            end_progress_line()
            click.echo(f"aaria: error: {' '.join(str(exc).split())}", err=True)
            ctx.meta[_FAILED] = True
            ctx.exit(1)
        except AariaError as exc:
            message = flag_message(exc, ctx.meta.get(_COMMAND))
        except click.UsageError as exc:  # bad options of a command: one line too
            message = " ".join(exc.format_message().split())
        click.echo(f"aaria: error: {message}", err=True)
        ctx.meta[_FAILED] = True
        ctx.exit(EXIT_BAD_INPUT)


@click.group(cls=_Main, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="aaria-pin")
def main() -> None:
    """Aaria on Pinocchio: reconfigurable manipulators, IMU datasets, torques."""


def _register() -> None:
    from importlib import import_module

    names = {"stats": "dataset_stats", "import": "import_"}  # not the module's name
    for module in ("arm bench_task check dataset export identify import info mjcf plot render"
                   " robots simulate stats template torques urdf view wrist").split():  # fmt: skip
        command = getattr(import_module(f"aaria_pin.cli.{module}_cmd"), names.get(module, module))
        main.add_command(command)


_register()
