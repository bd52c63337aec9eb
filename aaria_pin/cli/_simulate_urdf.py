"""``aaria simulate --robot/--urdf`` (or ``--from`` a URDF robot's run file): a URDF robot's run."""

from __future__ import annotations

from typing import Any

import click

from aaria_pin.cli._options import drive_overrides, given, sampling_overrides
from aaria_pin.core.record import RunRecord

_DH_ONLY = ("preset", "dh_file", "mount_file", "density", "convention")
"""Options of ``aaria simulate`` for DH arms only."""


def _refuse_options_without_effect(params: dict[str, Any]) -> None:
    """Options of ``aaria simulate`` that would do nothing for a URDF robot: usage errors."""
    from aaria_pin.core.conflicts import OptionConflictError

    refused = [(key, "from_run") for key in ("robot", "urdf_file") if params["from_run"]]
    source = next(key for key in ("from_run", "robot", "urdf_file") if params[key] is not None)
    refused += [(key, source) for key in _DH_ONLY] + [("base_file", "fixed_base")]
    for key, other in refused:  # the run file has its URDF; --base moves the base
        if given(key) and given(other):
            raise OptionConflictError(parameter=key, other=other, given_with=True)
    if params["from_run"] is not None and params["tool_frame"] is not None:
        raise click.UsageError(
            "--tool with --from: the run file's IMU layout was made for its tool; re-simulate "
            "with --robot/--urdf instead"
        )


def simulate_urdf_command(params: dict[str, Any], stored: RunRecord | None = None) -> None:
    """Run ``aaria simulate`` for a URDF robot from the command's option values.

    Args:
        params: the option values of ``aaria simulate`` by parameter name
        stored: the record of ``--from`` (read by the caller), if given
    """
    import warnings

    from aaria_pin.aaria.run_motion import MotionChoice
    from aaria_pin.aaria.run_source import effort_warnings, urdf_file_overrides, urdf_run_request
    from aaria_pin.apps.run_summary import run_summary as summary
    from aaria_pin.files.runfile import write_run_pieces

    _refuse_options_without_effect(params)
    overrides = sampling_overrides(params, stored)
    overrides.update(urdf_file_overrides(params))
    overrides.update(drive_overrides(params))
    output = params["output"]
    compress = params["compress"]

    def announce(record: RunRecord) -> None:
        for line in [str(warning.message) for warning in caught] + effort_warnings(record):
            click.echo(f"aaria: warning: {line}", err=True)

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot, moving = (params["robot"], params["urdf_file"]), not params["fixed_base"]
        choice = MotionChoice.from_options(params)
        chunks = urdf_run_request(choice, overrides, robot, stored, moving).pieces()
        record, samples, peak = write_run_pieces(
            output, chunks, None if compress == "none" else compress, announce
        )
    click.echo(summary(output, record, samples, peak, robot=True))
