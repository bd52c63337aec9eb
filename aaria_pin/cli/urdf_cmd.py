"""``aaria urdf``: a DH table to a URDF file."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import click

from aaria_pin.cli._options import load_table_source, table_source_options
from aaria_pin.cli._viz_options import output_option

if TYPE_CHECKING:
    from aaria_pin.aaria.dh_robot import DHRobot

URDF_SUFFIXES = (".urdf", ".xml")
"""Suffixes of a URDF output."""


def table_arm(
    preset: str | None, dh_file: Path | None, convention: str, density: float
) -> tuple[DHRobot, str]:
    """The DH arm of ``--preset`` or ``--dh`` (:func:`~aaria_pin.apps.robot_mjcf.dh_arm`)."""
    from aaria_pin.apps.robot_mjcf import dh_arm

    source = load_table_source(preset, dh_file, convention)
    return dh_arm(source, density, preset), source[2]


@click.command(
    epilog="""\b
Examples:
  aaria urdf --preset aaria-fig2 -o fig2.urdf          # the paper's Table 3 arm
  aaria template dh -o arm.csv && aaria urdf --dh arm.csv -o arm.urdf
  aaria urdf --dh wrist.csv --convention standard --density 7850 -o wrist.urdf"""
)
@table_source_options
@click.option("--density", type=float, default=2700.0, show_default=True,
    help="Density of every body [kg/m^3].")  # fmt: skip
@output_option("URDF file", URDF_SUFFIXES, help="URDF file to write (.urdf or .xml).")
def urdf(
    preset: str | None, dh_file: Path | None, convention: str, density: float, output: Path
) -> None:
    """Write the URDF of a DH table (fixed base, tool tip and IMU frames included).

    Prints the joints and the IMU frames the file holds (two per link, the base and the tool
    tip; an empty module has no link and so no IMUs).
    """
    from aaria_pin.files.io import write_text_atomic

    robot, _ = table_arm(preset, dh_file, convention, density)
    write_text_atomic(output, robot.urdf)
    imus = [slot.name for slot in robot.imu_slots if slot.parent is not None]
    click.echo(
        f"wrote {output}: {len(robot.chain.joints)} joints "
        f"(modules {', '.join(map(str, robot.chain.modules))}), "
        f"{len(imus)} IMUs: {', '.join(imus)}"
    )
