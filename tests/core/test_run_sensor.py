"""A sensor is one object plus its registration: a toy clock and a tool-height sensor are
recorded by the engine and found in the run file written by write_run."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from aaria_pin.aaria.arm_run import preset_arm
from aaria_pin.core.run import (
    IMU,
    RunRobot,
    RunSettings,
    SensorState,
    join_chunks,
    register_sensor,
    sensor,
    simulate,
    simulate_pieces,
)
from aaria_pin.errors import ParameterError
from aaria_pin.files.runfile import read_run, write_run


@dataclass(frozen=True)
class Clock:
    name: str = "clock"
    columns: tuple[str, ...] = ("t",)
    units: str = "s"
    noise_stream: str | None = None

    def signals(self, robot: RunRobot, state: SensorState) -> np.ndarray:
        return state.times[:, None]


@dataclass(frozen=True)
class ToolHeight:
    name: str = "tool_height"
    columns: tuple[str, ...] = ("z",)
    units: str = "m"
    noise_stream: str | None = None

    def signals(self, robot: RunRobot, state: SensorState) -> np.ndarray:
        return state.series.tool_pose[:, 2, 3:4]


def test_a_registered_toy_sensor_is_found_in_the_run_file(tmp_path: Path) -> None:
    clock = register_sensor(Clock())
    assert sensor("clock") is clock and sensor("imu") is IMU
    settings = RunSettings(duration=1.0, rate=40.0)
    record = simulate(preset_arm("aaria-fig2"), None, settings, 0, [clock, ToolHeight()])
    path = write_run(tmp_path / "run.h5", record)
    stored = read_run(path)
    # the clock's column is each sample's index over the rate, written out
    np.testing.assert_array_equal(stored.tables["sensor_clock"][:, 0], np.arange(41) / 40.0)
    # the tool height is the z of T_world_tool, which the file stores apart
    np.testing.assert_array_equal(
        stored.tables["sensor_tool_height"][:, 0], stored.tool_pose[:, 2, 3]
    )
    described = stored.attributes["sensors"]
    assert described["clock"]["columns"] == ["t"] and described["clock"]["units"] == "s"
    assert described["tool_height"]["table"] == "sensor_tool_height"


def test_a_sensor_in_pieces_is_its_whole_series_and_a_bad_shape_is_refused() -> None:
    robot = preset_arm("aaria-fig2")
    settings = RunSettings(duration=1.0, rate=40.0, chunk=10, noise=False)
    joined = join_chunks(simulate_pieces(robot, None, settings, 0, [Clock()]))
    np.testing.assert_array_equal(joined.tables["sensor_clock"][:, 0], np.arange(41) / 40.0)

    @dataclass(frozen=True)
    class Broken(Clock):
        name: str = "broken"

        def signals(self, robot: RunRobot, state: SensorState) -> np.ndarray:
            return state.times

    with pytest.raises(ParameterError) as error:
        simulate(robot, None, settings, 0, [Broken()])
    assert error.value.parameter == "sensors"
    with pytest.raises(ParameterError) as error:
        sensor("sonar")
    assert error.value.parameter == "sensor"
