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


@pytest.mark.parametrize(
    "cylinder", [[1, 2], "round", {"x": 0.3}, {"x": "a", "y": 0, "radius": 1, "height": 1}]
)
def test_a_malformed_cylinder_is_refused_in_one_line(cylinder: object) -> None:
    from aaria_pin.apps.arm.run import stored_cylinder

    with pytest.raises(InputFileError, match=r"^attribute 'cylinder' is .*; allowed: an object"):
        stored_cylinder({"cylinder": cylinder})
    record = open_record(FIXTURES / "v0_3_0" / "pick_place_run.h5")
    damaged = replace(record, attributes={**record.attributes, "cylinder": cylinder})
    with pytest.raises(InputFileError, match="attribute 'cylinder' is"):
        stored_task(damaged)


def test_a_preset_or_source_that_is_not_text_is_refused() -> None:
    from aaria_pin.apps.arm.run import stored_preset

    assert stored_preset({}) == "pick-place-arm"
    assert stored_preset({"preset": "", "source": "pick-place-arm"}) == "pick-place-arm"
    for name in ("preset", "source"):
        with pytest.raises(InputFileError, match=rf"^attribute '{name}' is 3; allowed") as error:
            stored_preset({name: 3})
        assert error.value.parameter == "file"


@pytest.mark.filterwarnings("ignore")
@pytest.mark.parametrize(
    "argv",
    [
        ["simulate", "--from", "{file}", "-o", "{out}"],
        ["plot", "{file}", "-o", "{out}.png"],
        ["render", "--from", "{file}", "-o", "{out}.png"],
    ],
)
def test_the_cli_names_the_file_of_a_malformed_cylinder(tmp_path: Path, argv: list[str]) -> None:
    import shutil

    import h5py
    from click.testing import CliRunner

    from aaria_pin.cli import main

    file = tmp_path / "pp.h5"
    shutil.copy(FIXTURES / "v0_3_0" / "pick_place_run.h5", file)
    with h5py.File(file, "r+") as handle:
        handle.attrs.pop("checksums", None)
        handle.attrs["cylinder_json"] = "[1, 2]"
    names = {"file": str(file), "out": str(tmp_path / "out.h5")}
    result = CliRunner().invoke(main, [a.format(**names) for a in argv])
    assert result.exit_code == 2, result.output
    last = result.stderr.strip().splitlines()[-1]
    assert last.startswith(f"aaria: error: {file}: "), last
    assert "attribute 'cylinder' is [1, 2]" in last and "RunFile(" not in last


def test_a_run_file_is_named_by_its_path_and_a_data_set_run_by_its_index() -> None:
    from aaria_pin.viz._run_view import dataset_run, run_file

    assert str(run_file("a/run.h5")) == "a/run.h5"
    assert str(dataset_run("ds.h5", 3)) == "run 3 of ds.h5"
