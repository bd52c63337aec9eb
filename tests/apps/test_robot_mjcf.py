"""A robot as an MJCF file (``apps/robot_mjcf``): the DH arm of a preset, its file's sensors."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

from aaria_pin.aaria.robot_inputs import dh_table_source
from aaria_pin.apps.robot_mjcf import MjcfSource, dh_arm, robot_mjcf


def test_a_preset_arm_is_written_with_a_gyro_and_an_accelerometer_per_imu(tmp_path: Path) -> None:
    arm = dh_arm(dh_table_source("aaria-fig2"), 2700.0, "aaria-fig2")
    out = tmp_path / "fig2.xml"
    line, notes = robot_mjcf(out, MjcfSource("dh", (arm, "aaria-fig2"), moving_base=False))
    root = ET.parse(out).getroot()
    gyros, accelerometers = root.iter("gyro"), root.iter("accelerometer")
    imus = [slot for slot in arm.imu_slots if slot.parent is not None]
    assert len(list(gyros)) == len(list(accelerometers)) == len(imus)
    assert line.startswith(f"wrote {out}: aaria-fig2, ") and "fixed base" in line
    assert notes == []
