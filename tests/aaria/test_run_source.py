"""A run's request from its sources (``aaria/run_source``): tables, input files, stored runs."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.robot_inputs import dh_table_source
from aaria_pin.aaria.run_motion import MotionChoice
from aaria_pin.aaria.run_source import (
    dh_file_overrides,
    dh_run_request,
    effort_warnings,
    urdf_file_overrides,
    urdf_run_request,
)
from aaria_pin.errors import ParameterError


def test_a_preset_gives_its_joint_and_base_tables_and_a_stored_run_is_remade() -> None:
    options = {"duration": 0.1, "rate": 100.0, "noise": False}
    request = dh_run_request(MotionChoice(), dict(options), dh_table_source("aaria-fig2"),
                             "aaria-fig2")  # fmt: skip
    record = request.record()
    preset = get_preset("aaria-fig2")
    np.testing.assert_array_equal(record.tables["senSenJ"], preset.joint_table)
    np.testing.assert_array_equal(record.tables["senSenB"], preset.base_table)
    again = dh_run_request(MotionChoice(), {}, stored=(record, "fig2.h5")).record()
    np.testing.assert_array_equal(again.imu, record.imu)


def test_a_table_of_another_convention_is_refused_in_one_line() -> None:
    table = np.zeros((8, 5))
    with pytest.raises(ParameterError, match=r"is a standard DH table; allowed: an Aaria 8 × 5"):
        dh_run_request(MotionChoice(), {}, (table, "standard", "mine.csv"))


def test_a_urdf_robot_by_name_and_its_stored_run() -> None:
    options = {"duration": 0.05, "rate": 100.0, "noise": False}
    record = urdf_run_request(MotionChoice(), dict(options), ("ur5", None)).record()
    assert record.joint_names[0] == "shoulder_pan_joint" and len(record.joint_names) == 6
    assert effort_warnings(record) == []  # ur5's gentle default sines stay within its limits
    again = urdf_run_request(MotionChoice(), {}, stored=record).record()
    np.testing.assert_array_equal(again.imu, record.imu)


def test_the_input_files_become_run_options(tmp_path: Path) -> None:
    from aaria_pin.aaria.templates import template_text

    (tmp_path / "joints.csv").write_text(template_text("joints"))
    (tmp_path / "base.csv").write_text(template_text("base"))
    files = {"joints_file": tmp_path / "joints.csv", "base_file": tmp_path / "base.csv"}
    dh = dh_file_overrides({**files, "density": 7850.0, "mount_file": None})
    preset = get_preset("aaria-fig2")
    np.testing.assert_allclose(dh["joint_table"], preset.joint_table, rtol=1e-12)  # its arm
    assert dh["dims"].density == 7850.0 and "imu_mount" not in dh
    urdf = urdf_file_overrides({"tool_frame": "tool0", "base_file": files["base_file"]})
    assert set(urdf) == {"tool_frame", "base_table"} and urdf["tool_frame"] == "tool0"
    np.testing.assert_array_equal(urdf["base_table"], dh["base_table"])
    assert dh_file_overrides({}) == {} == urdf_file_overrides({"joints_file": None})
