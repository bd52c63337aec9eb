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


def test_a_registered_toy_sensor_is_found_in_a_data_set_and_its_card(tmp_path: Path) -> None:
    """The must-show of issue 23: a sensor registered here is a column of a run file (above),
    of a data set and of its data card, with its units."""
    from aaria_pin.apps.dataset.card_file import dataset_card
    from aaria_pin.apps.dataset.card_text import card_text
    from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
    from aaria_pin.apps.dataset.generate import generate_dataset
    from aaria_pin.files.dataset.reader import DatasetReader

    clock = register_sensor(Clock())
    spec = DhDatasetSpec(n_runs=3, seed=2, duration=0.5, rate=20.0, sensors=(clock, ToolHeight()))
    path = tmp_path / "set.h5"
    generate_dataset(path, spec, workers=1)
    with DatasetReader(path) as reader:
        assert reader.header.sensors["clock"]["columns"] == ["t"]
        for run in range(3):
            record = reader.record(run)
            # float32 in the file: the clock's times k / 20 as float32, back in float64
            expected = (np.arange(11) / 20.0).astype(np.float32)
            np.testing.assert_array_equal(record.tables["sensor_clock"][:, 0], expected)
            np.testing.assert_array_equal(
                record.tables["sensor_tool_height"][:, 0], record.tool_pose[:, 2, 3]
            )
        assert reader.handle["sensor_clock"].dtype == np.float32  # a series: the data set's dtype
    card = dataset_card(path)
    entry = {column.name: column for column in card.columns}["sensor_tool_height"]
    assert (entry.role, entry.units, entry.shape) == ("sensor", "m", (3, 11, 1))
    assert [group.first for group in entry.column_groups] == ["z"]
    text = card_text(card)
    assert "sensor_clock" in text and "clock t: 1 column (t) [s]" in text


def test_the_sensors_a_record_names_re_make_its_tables(tmp_path: Path) -> None:
    from aaria_pin.core.run.sensor import recorded_sensors

    clock, height = register_sensor(Clock()), register_sensor(ToolHeight())
    settings = RunSettings(duration=0.5, rate=40.0)
    robot = preset_arm("aaria-fig2")
    stored = read_run(write_run(tmp_path / "run.h5", simulate(robot, None, settings, 3, [clock])))
    assert recorded_sensors(stored.attributes) == (clock,)
    again = simulate(robot, None, settings, 3, recorded_sensors(stored.attributes))
    np.testing.assert_array_equal(again.tables["sensor_clock"], stored.tables["sensor_clock"])
    assert recorded_sensors({}) == () and height.name == "tool_height"
    with pytest.raises(ParameterError) as error:
        recorded_sensors({"sensors": {"sonar": {}}})
    assert error.value.parameter == "sensor"


@pytest.mark.parametrize("suffix", [".h5", ".mat"])
def test_a_run_streamed_in_pieces_keeps_its_whole_sensor_table(tmp_path: Path, suffix: str) -> None:
    """write_run_pieces of a run longer than a piece: each piece's rows land in the table."""
    from aaria_pin.files.runfile import write_run_pieces

    settings = RunSettings(duration=1.0, rate=40.0, chunk=10, noise=False)
    pieces = simulate_pieces(preset_arm("aaria-fig2"), None, settings, 0, [Clock(), ToolHeight()])
    path = tmp_path / f"run{suffix}"
    _, samples, _ = write_run_pieces(path, pieces, None, mat_version="7.3")
    stored = read_run(path)
    assert samples == 41
    np.testing.assert_array_equal(stored.tables["sensor_clock"][:, 0], np.arange(41) / 40.0)
    np.testing.assert_array_equal(
        stored.tables["sensor_tool_height"][:, 0], stored.tool_pose[:, 2, 3]
    )


def test_the_joint_channels_time_axis_tables_are_sensor_tables() -> None:
    from aaria_pin.core.record import JOINT_RUN_TABLES, JOINT_SERIES
    from aaria_pin.core.run.sensor import is_sensor_table

    assert all(is_sensor_table(name) for name in JOINT_SERIES)
    assert not any(is_sensor_table(name) for name in (*JOINT_RUN_TABLES, "senSenDH", "tau"))
    assert is_sensor_table("sensor_toy")
