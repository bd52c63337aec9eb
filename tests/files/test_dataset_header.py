"""The data set header: the file attributes read once, by name and type."""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import pytest

from aaria_pin.errors import InputFileError
from aaria_pin.files.dataset.header import DatasetHeader
from aaria_pin.files.dataset.reader import DatasetReader

FIXTURES = Path(__file__).resolve().parents[1] / "fixtures"


def test_a_version_2_header_holds_what_the_attributes_say() -> None:
    path = FIXTURES / "v0_3_0" / "ur5_dataset.h5"
    with h5py.File(path, "r") as handle:
        attrs = dict(handle.attrs)
    with DatasetReader(path) as reader:
        header = reader.header
    assert (header.format_version, header.n_runs, header.samples) == (2, 2, 21)
    assert (header.dtype, header.kind, header.robot, header.seed) == ("float32", "urdf", "ur5", 7)
    assert header.rate == 100.0 and header.duration == 0.2 and header.noise is True
    assert header.noise_stream == 3 and header.vary == ["joints", "base"]
    assert header.robot_info == json.loads(attrs["robot_info_json"])
    assert header.noise_parameters == json.loads(attrs["noise_parameters_json"])
    assert header.command == attrs["command"] and header.written_by == "0.3.0"
    assert header.versions == json.loads(attrs["versions_json"])
    assert header.failures == {} and header.stored_card == json.loads(attrs["card_json"])


def test_a_version_1_header_takes_the_urdf_robot_from_robot() -> None:
    path = FIXTURES / "v0_1_0" / "ur5_dataset.h5"
    with h5py.File(path, "r") as handle:
        robot = json.loads(handle.attrs["robot_json"])
    with DatasetReader(path) as reader:
        header = reader.header
    assert header.format_version == 1 and header.kind == "urdf" and header.robot is None
    assert header.robot_info == robot and header.noise_stream is None
    with DatasetReader(FIXTURES / "v0_1_0" / "dh_dataset.h5") as reader:
        dh = reader.header
    assert dh.kind == "dh" and dh.robot_info is None and dh.n_runs == 3 and dh.command is None


def test_typed_from_plain_values_and_a_damaged_header_is_refused() -> None:
    header = DatasetHeader.from_attributes(
        {
            "N": 4,
            "samples": 10,
            "command": ["aaria", "dataset", "-o", "a b.h5"],
            "failures": {"2": "diverged"},
            "versions": "0.2.0",
        },
        2,
    )
    assert header.command == "aaria dataset -o 'a b.h5'"
    assert header.failures == {2: "diverged"} and header.versions == {"": "0.2.0"}
    assert header.kind == "dh" and header.written_by is None
    with pytest.raises(InputFileError, match="no 'N' or 'samples'") as bad:
        DatasetHeader.from_attributes({"N": 4}, 2, "x.h5")
    assert bad.value.parameter == "file"
