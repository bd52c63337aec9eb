"""``aaria urdf``: a DH table to a URDF file."""

from __future__ import annotations

from pathlib import Path

import click

from aaria_pin.cli._options import load_table_source, robot_name, table_source_options


@click.command()
@table_source_options
@click.option(
    "--density",
    type=float,
    default=2700.0,
    show_default=True,
    help="Density of every body [kg/m^3].",
)
@click.option(
    "-o",
    "--output",
    type=click.Path(path_type=Path, dir_okay=False),
    required=True,
    help="URDF file to write.",
)
def urdf(
    preset: str | None, dh_file: Path | None, convention: str, density: float, output: Path
) -> None:
    """Write the URDF of a DH table (fixed base, tool tip and IMU frames included)."""
    from aaria_pin.aaria.dh_robot import BodyDimensions, build_dh_robot
    from aaria_pin.aaria.presets import get_preset
    from aaria_pin.files.io import write_text_atomic

    table, table_convention, name = load_table_source(preset, dh_file, convention)
    robot = build_dh_robot(
        table,
        table_convention,
        BodyDimensions(density=density),
        name=robot_name(name),
        mass_properties=get_preset(preset).mass_properties if preset else None,
    )
    write_text_atomic(output, robot.urdf)
    click.echo(
        f"wrote {output}: {len(robot.chain.joints)} joints "
        f"(modules {', '.join(map(str, robot.chain.modules))}), "
        f"{len(robot.imu_slots)} IMU slots"
    )
