"""The pick-and-place report: phases, peaks and payload share per joint, effort warnings."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from aaria_pin.apps.arm.dims import ArmDimensions
from aaria_pin.apps.arm.report import pick_place_report, write_arm_folder
from aaria_pin.errors import ParameterError


def _run(tau: np.ndarray, tau_free: np.ndarray) -> Any:
    boundaries = np.arange(14.0).reshape(7, 2) / 2  # 0-0.5, 1-1.5, … 6-6.5 s
    return SimpleNamespace(
        tau=tau,
        tau_free=tau_free,
        dims=ArmDimensions(),
        path=SimpleNamespace(boundaries=boundaries),
    )


def test_peaks_shares_units_and_warnings() -> None:
    tau = np.zeros((3, 7))
    tau[1] = [-600.0, 20.0, -3.0, 1.0, 2.0, -12.5, 4.0]  # lift over 500 N, hand_roll over 10 N·m
    tau_free = tau.copy()
    tau_free[1, 0] = -550.0  # the payload's part of the lift: 50 N
    text, warnings = pick_place_report(_run(tau, tau_free))
    lines = text.splitlines()
    assert lines[0].split() == ["approach", "0.00", "-", "0.50", "s"]
    assert lines[6].split() == ["release", "6.00", "-", "6.50", "s"]
    rows = {line.split()[0]: line.split()[1:] for line in lines[8:]}
    assert rows["lift"] == ["600", "N", "50", "N"]
    assert rows["hand_roll"] == ["12.5", "N*m", "0", "N*m"]
    assert rows["finger"] == ["4", "N", "0", "N"]
    assert warnings == (
        "lift peak |tau| 600 N exceeds the URDF effort limit 500 N",
        "hand_roll peak |tau| 12.5 N*m exceeds the URDF effort limit 10 N*m",
    )


def test_arm_folder_checks_the_cylinder_first(tmp_path: Path) -> None:
    with pytest.raises(ParameterError, match="radius"):
        write_arm_folder(tmp_path / "arm", radius=float("nan"))
    assert not (tmp_path / "arm").exists()
    urdf, meshes = write_arm_folder(tmp_path / "arm")
    assert urdf == tmp_path / "arm" / "pick_place_arm.urdf" and urdf.is_file()
    assert meshes == len(list((tmp_path / "arm" / "meshes").glob("*.stl"))) > 0
