"""The recording map (``files/recordings/mapping``): TOML, flags over it, its text back."""

from __future__ import annotations

from pathlib import Path

import pytest

from aaria_pin.aaria.templates import template_text
from aaria_pin.errors import InputFileError, ParameterError
from aaria_pin.files.recordings.mapping import (
    RecordingMap,
    SensorMap,
    map_toml,
    read_map,
    with_flags,
)


def test_the_template_reads_and_flags_go_over_it(tmp_path: Path) -> None:
    path = tmp_path / "rec.toml"
    path.write_text(template_text("recording"))
    mapping = read_map(path)
    assert mapping.time == "header" and mapping.joints == "/joint_states"
    assert mapping.imus[0] == SensorMap("imu_tool", "/imu/imu_tool")
    assert [w.name for w in mapping.wrenches] == ["base"]
    flagged = with_flags(mapping, ["imu_tool=/imus@tool", "extra=/x"], "/js", ["ft=/ft"], "log")
    assert flagged.imus[-2:] == (SensorMap("imu_tool", "/imus", "tool"), SensorMap("extra", "/x"))
    assert len(flagged.imus) == len(mapping.imus) + 1  # imu_tool replaced, extra added
    assert (flagged.joints, flagged.time) == ("/js", "log")
    assert flagged.wrenches[-1] == SensorMap("ft", "/ft")


def test_the_text_of_a_map_reads_back_to_it(tmp_path: Path) -> None:
    mapping = RecordingMap((SensorMap("a", "/i", "f"), SensorMap('q"b', "", "", tuple("uvwxyz"))),
                           "/js", (SensorMap("w", "/w"),), "log", "t")  # fmt: skip
    path = tmp_path / "m.toml"
    path.write_text(map_toml(mapping))
    assert read_map(path) == mapping


def test_bad_maps_are_one_line(tmp_path: Path) -> None:
    path = tmp_path / "m.toml"
    for text, match in (
        ("tiem = 'log'\n", "key tiem is unknown"),
        ("[[imu]]\ntopic = '/x'\n", r"\[\[imu\]\] 1 has no name"),
        ("[[imu]]\nname = 'a'\ncolumns = ['x']\n", "has 1 columns; allowed: 6"),
        ("time = [\n", "allowed: a TOML recording map"),
    ):
        path.write_text(text)
        with pytest.raises(InputFileError, match=match) as caught:
            read_map(path)
        assert caught.value.parameter == "map" and "\n" not in str(caught.value)
    with pytest.raises(ParameterError, match="time is 'utc'; allowed: header, log"):
        RecordingMap(time="utc")
    with pytest.raises(ParameterError, match="sensor a is mapped twice"):
        RecordingMap((SensorMap("a", "/x"),), wrenches=(SensorMap("a", "/y"),))
    with pytest.raises(ParameterError, match="wrench is 'ft'; allowed: NAME=TOPIC"):
        with_flags(None, wrenches=["ft"])
