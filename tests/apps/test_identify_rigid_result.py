"""The rigid-pair result as text and JSON: numbers in the units the lines name."""

from __future__ import annotations

import json

import numpy as np

from aaria_pin.apps.identify.rigid_result import RigidPairFit
from aaria_pin.core.rotations import elementary


def _fit(**changes: object) -> RigidPairFit:
    values: dict[str, object] = {
        "imu_a": "base",
        "imu_b": "tool",
        "rotation": elementary(2, np.radians(30.0)),
        "rotation_sigma": np.radians([0.001, 0.002, 0.003]),
        "position": np.array([0.2, -0.1, 0.05]),
        "position_sigma": np.array([1e-5, 2e-5, 3e-5]),
        "time_offset": 0.0125,
        "time_offset_sigma": 2e-6,
        "gyro_bias_a": np.zeros(3),
        "gyro_bias_b": np.array([1e-3, 0.0, 0.0]),
        "accel_bias_b": np.zeros(3),
        "noise": np.array([1e-3, 5e-3, 2e-3, 6e-3]),
        "samples": (4001, 5001),
        "iterations": 3,
        "converged": True,
    }
    values.update(changes)
    return RigidPairFit(**values)  # type: ignore[arg-type]


def test_lines_give_millimetres_degrees_and_milliseconds() -> None:
    lines = _fit().lines()
    assert lines[0] == "rigid pair base -> tool: 4001 + 5001 samples, 3 iterations"
    assert lines[1] == (
        "  position of tool in base [mm]: 200.000 +/- 0.010  -100.000 +/- 0.020  50.000 +/- 0.030"
    )
    assert lines[2].startswith("  rotation (roll pitch yaw, xyz) [deg]: 0.0000  0.0000  30.0000")
    assert lines[2].endswith("(sigma about base's axes: 0.0010, 0.0020, 0.0030)")
    assert lines[3] == "  time offset of tool [ms]: 12.5000 +/- 0.0020"
    assert lines[4] == (
        "  residual RMS: gyro 0.001 / 0.002 rad/s, accel 0.005 / 0.006 m/s^2 (base / tool)"
    )


def test_what_is_not_determined_and_a_failure_end_the_lines() -> None:
    fit = _fit(converged=False, undetermined=("position along z",), failure="above the floor")
    lines = fit.lines()
    assert lines[0].endswith("3 iterations (not converged)")
    assert lines[-2:] == ["  not determined: position along z", "  fit failed: above the floor"]


def test_json_is_si_and_round_trips() -> None:
    fit = _fit()
    data = json.loads(json.dumps(fit.to_json()))
    assert data["position_m"] == [0.2, -0.1, 0.05]
    assert data["time_offset_s"] == 0.0125
    assert data["residual_rms"]["accel_b_m_s2"] == 6e-3
    assert data["samples"] == [4001, 5001] and data["failure"] == ""
    assert (
        np.degrees(fit.rotation_error(np.eye(3))) == np.float64(30.0).round(10)
        or abs(np.degrees(fit.rotation_error(np.eye(3))) - 30.0) < 1e-12
    )
