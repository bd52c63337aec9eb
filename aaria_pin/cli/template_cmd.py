"""``aaria template``: commented, valid input files to start from."""

from __future__ import annotations

from pathlib import Path

import click

KINDS = ("dh", "joints", "base", "imu-layout", "config", "imu-model", "hardware", "recording")
"""The templates (those of :data:`aaria_pin.aaria.templates.TEMPLATE_KINDS`, kept light here)."""


@click.command(
    epilog="""\b
Examples:
  aaria template dh -o my_arm.csv          # edit, then: aaria urdf --dh my_arm.csv -o arm.urdf
  aaria template joints -o joints.csv      # aaria simulate --dh my_arm.csv --joints joints.csv
  aaria template base -o base.csv          # aaria simulate ... --base base.csv
  aaria template imu-layout -o imus.toml   # aaria simulate --robot ur5 --imu-layout imus.toml
  aaria template config -o ranges.toml     # aaria dataset -n 100 --config ranges.toml -o ds.h5
  aaria template imu-model --imu-model bmi088 -o imu.toml  # aaria simulate --imu-model imu.toml
  aaria template hardware -o hw.toml       # aaria simulate --robot ur5 --hardware hw.toml
  aaria template recording -o rec.toml     # aaria import lab.bag --map rec.toml -o rec.h5
  aaria template dh                        # print it"""
)
@click.argument("kind", type=click.Choice(KINDS))
@click.option("-o", "--output", type=click.Path(path_type=Path, dir_okay=False, allow_dash=True),
    help="File to write (default, or '-': print it).")  # fmt: skip
@click.option("--overwrite", is_flag=True, help="Replace an existing file.")
@click.option("--imu-model", help="The preset of the imu-model template (default adis16485).")
def template(kind: str, output: Path | None, overwrite: bool, imu_model: str | None) -> None:
    """Write a commented input file to start from.

    A DH, joint or base table (CSV), an IMU layout, a data-set configuration, an IMU model,
    a hardware file or a recording map (TOML). Each is valid as written (the paper's Figure 2
    arm, the default motions, ranges and hardware): edit it and pass it to the command it names.
    """
    from aaria_pin.aaria.templates import template_text
    from aaria_pin.core.conflicts import OptionConflictError
    from aaria_pin.files.io import write_text_atomic

    text = template_text(kind, imu_model)
    if output is None or str(output) == "-":
        if overwrite:  # nothing to replace: say so rather than ignore it
            raise OptionConflictError(parameter="overwrite", other="output", given_with=False)
        click.echo(text, nl=False)
        return
    write_text_atomic(output, text, overwrite=overwrite)
    click.echo(f"wrote {output}: the {kind} template", err=True)
