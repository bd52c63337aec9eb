"""The pick-and-place task read from a run record's typed metadata (apps/arm/stored_task.py)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from aaria_pin.apps.arm.dims import ArmDimensions
from aaria_pin.apps.arm.stored_task import is_pick_place, stored_task
from aaria_pin.apps.arm.task import Cylinder
from aaria_pin.errors import InputFileError
from aaria_pin.files.source import open_record

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures"


def test_the_task_of_the_v0_3_0_fixture_is_what_its_readme_command_asked() -> None:
    # aaria arm pick-place --cylinder 0.35 0.1 --place 0.2 -0.3 (README of the fixtures)
    record = open_record(FIXTURES / "v0_3_0" / "pick_place_run.h5")
    task = stored_task(record)
    assert task is not None
    assert task.cylinder == Cylinder(0.35, 0.1, radius=0.03, height=0.12, mass=0.5)
    assert task.place == (0.2, -0.3)
    assert task.dims == ArmDimensions()  # the default preset
    assert task.payload_joint == "hand_roll"
    start, end = task.held
    assert 0 < start < end < record.time[-1]


def test_a_v0_1_0_pick_place_run_names_its_arm_by_its_source() -> None:
    record = open_record(FIXTURES / "v0_1_0" / "pick_place_run.h5")
    assert "preset" not in record.attributes
    task = stored_task(record)
    assert task is not None and task.dims == ArmDimensions()
    assert task.cylinder.x == 0.5 and task.place == (-0.3, 0.4)


def test_runs_of_other_kinds_have_no_task() -> None:
    record = open_record(FIXTURES / "v0_3_0" / "dh_run.h5")
    assert not is_pick_place(record.metadata)
    assert stored_task(record) is None
    pick_place = open_record(FIXTURES / "v0_3_0" / "pick_place_run.h5")
    other_task = {**pick_place.attributes, "task": "stack"}
    assert stored_task(replace(pick_place, attributes=other_task)) is None
    no_cylinder = {k: v for k, v in pick_place.attributes.items() if k != "cylinder"}
    assert stored_task(replace(pick_place, attributes=no_cylinder)) is None


@pytest.mark.parametrize(
    "damage",
    [{"held_interval": [1.0]}, {"place": "here"}, {"preset": "no-such-arm"}],
)
def test_damaged_task_attributes_are_an_input_file_error(damage: dict[str, object]) -> None:
    record = open_record(FIXTURES / "v0_3_0" / "pick_place_run.h5")
    damaged = replace(record, attributes={**record.attributes, **damage})
    with pytest.raises(InputFileError, match="pick-place attributes cannot be used") as error:
        stored_task(damaged)
    assert error.value.parameter == "record"
