"""The Aaria arm of 0.1.0's DH files: its slots' parents, as the 0.1.0 README's slot table."""

from __future__ import annotations

from pathlib import Path

from aaria_pin.aaria.legacy_v0_1 import AARIA_V0_1, aaria_slot_parent
from aaria_pin.files.legacy_arm import legacy_arm


def test_the_slot_table_of_the_0_1_0_readme() -> None:
    assert aaria_slot_parent("imu_base") == "base"
    assert aaria_slot_parent("imu_tool") == "tool_tip"
    assert [aaria_slot_parent(f"imu_link{k}_{s}") for k in (1, 6) for s in "ab"] == [
        "link1",
        "link1",
        "link6",
        "link6",
    ]
    assert aaria_slot_parent("imu_link0_a") == "" and aaria_slot_parent("other") == ""


def test_it_is_the_arm_the_files_layer_reads_0_1_0_files_with() -> None:
    assert legacy_arm(Path("x.h5")) is AARIA_V0_1
    assert AARIA_V0_1.slots == 14 and AARIA_V0_1.modules == 6
