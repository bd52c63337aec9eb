"""Where a robot and its inputs come from: presets, table files, URDF files, torque files."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.robot_inputs import dh_table_source, read_torques, robot_name, urdf_source
from aaria_pin.core.conflicts import OptionConflictError
from aaria_pin.errors import InputFileError, ParameterError

FIXTURES = Path(__file__).parents[1] / "fixtures" / "v0_3_0"


def test_a_preset_or_a_table_file(tmp_path: Path) -> None:
    preset = get_preset("aaria-fig3")
    table, convention, name = dh_table_source("aaria-fig3")
    assert np.array_equal(table, preset.table) and (convention, name) == ("aaria", "aaria-fig3")
    path = tmp_path / "my arm.csv"
    np.savetxt(path, preset.table, delimiter=",", fmt="%.17g")
    table, convention, name = dh_table_source(dh_file=path, convention="standard")
    assert np.array_equal(table, preset.table) and (convention, name) == ("standard", "my arm")
    for given in ({}, {"preset": "aaria-fig3", "dh_file": path}):
        with pytest.raises(ParameterError) as caught:
            dh_table_source(**given)  # type: ignore[arg-type]
        assert caught.value.parameter == "preset"


def test_a_convention_is_for_a_table_file_not_a_preset(tmp_path: Path) -> None:
    path = tmp_path / "t.npy"
    np.save(path, get_preset("aaria-fig2").table)
    assert dh_table_source(dh_file=path)[1] == "aaria"  # a file's default convention
    with pytest.raises(OptionConflictError) as caught:
        dh_table_source("aaria-fig2", convention="standard")
    assert (caught.value.parameter, caught.value.other) == ("convention", "preset")
    assert str(caught.value) == (
        "convention is given with preset; allowed: convention without preset"
    )


def test_a_urdf_file_or_nothing(tmp_path: Path) -> None:
    urdf = tmp_path / "r.urdf"
    urdf.write_text('<robot name="r"><link name="base"/></robot>')
    text, folder, name = urdf_source(urdf_file=urdf)
    assert text == urdf.read_text() and folder == tmp_path and name == str(urdf)
    with pytest.raises(InputFileError):
        urdf_source(urdf_file=tmp_path / "missing.urdf")
    with pytest.raises(ParameterError) as caught:
        urdf_source()
    assert caught.value.parameter == "robot"


def test_torques_of_a_run_file_carry_its_grid_a_table_none() -> None:
    tau, grid = read_torques(FIXTURES / "dh_run.h5")
    with h5py.File(FIXTURES / "dh_run.h5", "r") as handle:
        stored = handle["tau"][()]
        samples = handle["time"].shape[0]
    np.testing.assert_array_equal(tau, stored)
    assert grid == {"rate": 100.0, "duration": pytest.approx((samples - 1) / 100.0)}
    tau, grid = read_torques(FIXTURES / "tau.npy")
    np.testing.assert_array_equal(tau, np.load(FIXTURES / "tau.npy"))
    assert grid == {}


def test_robot_names() -> None:
    assert robot_name("aaria-fig2") == "aaria_fig2"
    assert robot_name("2 arms") == "arm_2_arms"
