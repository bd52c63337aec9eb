"""The click group and its error handling."""

from __future__ import annotations

from typing import Any

import click

from aaria_pin.errors import AariaError, NoSpaceError

EXIT_BAD_INPUT = 2


class _Group(click.Group):
    """A click group that turns the toolkit's input errors into one line and exit status 2."""

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

    def invoke(self, ctx: click.Context) -> Any:
        try:
            return super().invoke(ctx)
        except NoSpaceError as exc:  # the input was fine: exit 1, as any failed job
            click.echo(f"aaria: error: {' '.join(str(exc).split())}", err=True)
            ctx.exit(1)
        except AariaError as exc:
            message = exc.for_flag(_flags(self))
        except click.UsageError as exc:  # bad options of a command: one line too
            message = exc.format_message()
        click.echo(f"aaria: error: {' '.join(message.split())}", err=True)
        ctx.exit(EXIT_BAD_INPUT)


_PARAMETER_FLAGS = {
    "joint_table": "--joints",
    "base_table": "--base",
    "table": "--dh",
    "dh_table": "--dh",
    "torques": "--torques",
    "path": "-o/--output",
    "run": "--run",
}
"""Library parameters whose flag is named otherwise (the rest map by their option's name)."""


def _flags(group: click.Group) -> dict[str, str]:
    """Library parameter name → the flag that sets it, over every command of the group."""
    flags: dict[str, str] = {}
    stack: list[click.Command] = list(group.commands.values())
    while stack:
        command = stack.pop()
        if isinstance(command, click.Group):
            stack.extend(command.commands.values())
        for param in command.params:
            if isinstance(param, click.Option) and param.name:
                flags.setdefault(param.name, max(param.opts, key=len))
    return {**flags, **_PARAMETER_FLAGS}


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="aaria-pin")
def main() -> None:
    """Aaria on Pinocchio: reconfigurable manipulators, IMU datasets, torques."""


def _register() -> None:
    from aaria_pin.cli import (
        arm_cmd,
        dataset_cmd,
        identify_cmd,
        info_cmd,
        mjcf_cmd,
        plot_cmd,
        render_cmd,
        robots_cmd,
        simulate_cmd,
        stats_cmd,
        template_cmd,
        torques_cmd,
        urdf_cmd,
        view_cmd,
        wrist_cmd,
    )

    main.add_command(arm_cmd.arm)
    main.add_command(dataset_cmd.dataset)
    main.add_command(identify_cmd.identify)
    main.add_command(info_cmd.info)
    main.add_command(mjcf_cmd.mjcf)
    main.add_command(plot_cmd.plot)
    main.add_command(render_cmd.render)
    main.add_command(robots_cmd.robots)
    main.add_command(simulate_cmd.simulate)
    main.add_command(stats_cmd.dataset_stats)
    main.add_command(template_cmd.template)
    main.add_command(torques_cmd.torques)
    main.add_command(urdf_cmd.urdf)
    main.add_command(view_cmd.view)
    main.add_command(wrist_cmd.wrist)


_register()
