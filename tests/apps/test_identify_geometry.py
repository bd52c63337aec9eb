"""Kinematic identification from IMUs and encoders (issue 17): structure, DH table, deficiencies.

Each identified table is checked by an independent forward kinematics: Pinocchio's frame
placements of the URDF model built from the estimated table, against the tool pose the
simulation recorded (``inv(base_pose) · tool_pose``), at samples over the run.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from click.testing import CliRunner

from aaria_pin.aaria.dh_robot import build_dh_robot
from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.randomize import (
    PARTS,
    load_config,
    random_base_table,
    random_dh_table,
    random_joint_table,
)
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.apps.identify import identify_kinematics
from aaria_pin.apps.identify.geometry_start import detect_kind
from aaria_pin.cli.identify_cmd import identify
from aaria_pin.core.record import ImuMount, RunRecord
from aaria_pin.core.seeds import RunSeeds
from aaria_pin.errors import ParameterError
from aaria_pin.files.io import read_table
from aaria_pin.files.runfile import write_run

DURATION, RATE = 4.0, 50.0


def _tool_tip_error(table: np.ndarray, record: RunRecord, samples: int = 40) -> float:
    """Largest distance between the estimated table's tool tip and the recorded one [m]."""
    robot = build_dh_robot(table)
    model = robot.model()
    data = model.model.createData()
    frame = model.frame_id("tool_tip")
    columns = [m - 1 for m in robot.chain.modules]
    worst = 0.0
    for t in np.linspace(0, record.n_samples - 1, samples).astype(int):
        pin.framesForwardKinematics(model.model, data, record.q[t, columns])
        T_base_tool = np.linalg.inv(record.base_pose[t]) @ record.tool_pose[t]
        worst = max(worst, float(np.linalg.norm(data.oMf[frame].translation - T_base_tool[:3, 3])))
    return worst


def _preset_record(name: str) -> RunRecord:
    preset = get_preset(name)
    return simulate_run(
        preset.table,
        preset.joint_table,
        preset.base_table,
        duration=DURATION,
        rate=RATE,
        noise=False,
    )


@pytest.mark.parametrize("name", ["aaria-fig2", "aaria-fig3"])
def test_presets_recover_structure_and_tool_tip(name: str) -> None:
    record = _preset_record(name)
    result = identify_kinematics(record)
    assert result.link_types == tuple(int(t) for t in get_preset(name).table[:6, 4])
    assert _tool_tip_error(result.table, record) < 1e-4
    assert result.truth is not None and all(result.truth.link_types_right)
    assert result.truth.tool_tip_max < 1e-4
    assert max(result.truth.axis_angle_max.values()) < 1e-4
    # the base and tool IMUs define their frames; link IMUs end where the simulation put them
    for estimated, true in zip(result.mounts, record.imu_mounts, strict=True):
        assert estimated.parent == true.parent


def test_random_arm_with_prismatic_and_empty_modules() -> None:
    config = load_config(None)
    structure, joints, base = (RunSeeds(0, 2).generator(p) for p in PARTS)
    table = random_dh_table(config, structure)
    types = table[:6, 4]
    assert (types == 0).any() and (types == 2).any()  # the case this test is about
    record = simulate_run(
        table,
        random_joint_table(config, table, joints),
        random_base_table(config, base),
        duration=DURATION,
        rate=RATE,
        noise=False,
    )
    result = identify_kinematics(record)
    assert result.link_types == tuple(int(t) for t in types)
    assert _tool_tip_error(result.table, record) < 1e-4


def test_parallel_axes_reported_as_undetermined() -> None:
    # two revolute modules about parallel axes (alpha2 = 0): only d1 + d2 is determined
    record = _parallel_arm_record()
    result = identify_kinematics(record)
    named = [d for d in result.deficiencies if set(d.parameters) == {"d1", "d2"}]
    assert len(named) == 1 and "add up" in named[0].description
    assert named[0].coefficients == pytest.approx((1.0, -1.0), abs=1e-6)
    sigma = dict(zip(result.parameter_names, result.sigmas, strict=True))
    assert np.isnan(sigma["d1"]) and np.isnan(sigma["d2"])  # not a confident wrong number
    assert np.isfinite(sigma["alpha2"]) and np.isfinite(sigma["a1"])
    assert result.table[0, 3] + result.table[1, 3] == pytest.approx(0.35, abs=1e-6)
    assert _tool_tip_error(result.table, record) < 1e-4


def test_detect_kind_on_rates() -> None:
    # an independent construction: a child body turning about j at qd on a turning parent
    rng = np.random.default_rng(1)
    t = np.linspace(0, 3, 200)
    omega_parent = np.column_stack([np.sin(t), np.cos(2 * t), 0.3 * t])
    qd = 0.8 * np.cos(1.3 * t)
    axis = np.array([0.0, 0.6, 0.8])
    R = np.linalg.qr(rng.normal(size=(3, 3)))[0]
    R *= np.sign(np.linalg.det(R))
    revolute = (omega_parent + qd[:, None] * axis) @ R
    assert detect_kind(revolute, omega_parent, qd)[0] == "revolute"
    assert detect_kind(omega_parent @ R, omega_parent, qd)[0] == "prismatic"


def test_detect_kind_of_a_slow_sliding_joint_under_noise() -> None:
    # ADIS16485-like gyroscope noise (1.7e-3 rad/s per sample) on both IMUs, 30 s at 200 Hz:
    # a prismatic joint moving at 2-10 mm/s (its qd² far below the noise of the squared rates)
    # and a revolute joint at 0.5 rad/s
    rng = np.random.default_rng(7)
    t = np.linspace(0.0, 30.0, 6001)
    omega_parent = 0.5 * np.column_stack([np.sin(0.7 * t), np.cos(0.4 * t + 1), np.sin(0.3 * t)])
    R = np.linalg.qr(rng.normal(size=(3, 3)))[0]
    R *= np.sign(np.linalg.det(R))

    def noisy(values: np.ndarray) -> np.ndarray:
        return values + 1.7e-3 * rng.standard_normal(values.shape)

    for speed in (0.002, 0.003, 0.005, 0.007, 0.01):  # [m/s]: the qd² coefficient's error 0.3-8
        slow = speed * np.cos(0.9 * t)
        kind, slope = detect_kind(noisy(omega_parent @ R), noisy(omega_parent), slow)
        assert kind == "prismatic" and slope < 0.1
    qd = 0.5 * np.cos(0.9 * t)
    q = 0.5 / 0.9 * np.sin(0.9 * t)
    # the child turns about its z axis by q after a fixed rotation R from the parent
    c, s = np.cos(q), np.sin(q)
    turned = omega_parent @ R
    child = np.column_stack(
        [
            c * turned[:, 0] + s * turned[:, 1],
            -s * turned[:, 0] + c * turned[:, 1],
            turned[:, 2] + qd,
        ]
    )
    assert detect_kind(noisy(child), noisy(omega_parent), qd)[0] == "revolute"


def test_record_without_tool_imu_is_refused() -> None:
    record = _preset_record("aaria-fig3")
    mounts = tuple(
        ImuMount(m.name, "elsewhere" if m.parent == "tool_tip" else m.parent, m.T_parent_imu)
        for m in record.imu_mounts
    )
    with pytest.raises(ParameterError, match="tool_tip"):
        identify_kinematics(dataclasses.replace(record, imu_mounts=mounts))


def _parallel_arm_record() -> RunRecord:
    table = np.zeros((8, 5))
    table[0] = [np.pi / 2, 0.8, 0.0, 0.2, 1]
    table[1] = [0.0, 0.85, 0.0, 0.15, 1]
    table[6] = [0.0, 0.8, 0.0, 0.0, 1]
    return simulate_run(table, duration=DURATION, rate=RATE, noise=False)


def test_cli_writes_table_urdf_and_json(tmp_path: Path) -> None:
    record = _parallel_arm_record()
    run = tmp_path / "run.h5"
    write_run(run, record)
    runner = CliRunner()
    table, urdf = tmp_path / "est.csv", tmp_path / "est.urdf"
    result = runner.invoke(identify, [str(run), "-o", str(table), "--urdf", str(urdf), "--json"])
    assert result.exit_code == 0, result.output
    report = json.loads(result.output)
    estimated = read_table(table, "table")
    assert np.allclose(estimated, report["table"])
    assert _tool_tip_error(estimated, record) < 1e-4
    assert "<robot" in urdf.read_text() and "imu_link2_a" in urdf.read_text()
    assert report["truth"]["link_types_right"] == [True] * 6
    assert any("d1 and d2 add up" in d["description"] for d in report["deficiencies"])
    # a wrong suffix is refused before anything is computed or written
    bad = runner.invoke(identify, [str(run), "-o", str(tmp_path / "t.txt")])
    assert bad.exit_code != 0 and not (tmp_path / "t.txt").exists()


def _random_record(k: int, noise: bool) -> tuple[np.ndarray, RunRecord]:
    config = load_config(None)
    structure, joints, base = (RunSeeds(0, k).generator(p) for p in PARTS)
    table = random_dh_table(config, structure)
    record = simulate_run(
        table,
        random_joint_table(config, table, joints),
        random_base_table(config, base),
        duration=30.0,
        rate=200.0,
        noise=noise,
        seed=k,
    )
    return table, record


def test_noisy_arm_reaches_the_noise_floor() -> None:
    # random arm 13 (prismatic modules 4 and 6) with ADIS16485 noise: its closed-form start
    # once ended in a local minimum 0.86 m off at the tool tip, five times the noise floor,
    # when the base's signals were smoothed (a bias); taken as measured, the fit reaches the
    # floor and the right arm
    table, record = _random_record(13, noise=True)
    result = identify_kinematics(record)
    assert result.fit["end_rms_weighted"] < 1.1  # weights are 1 / the noise level
    assert result.link_types == tuple(int(t) for t in table[:6, 4])
    assert _tool_tip_error(result.table, record) < 0.01


def test_noisy_derivative_of_a_sine() -> None:
    # against the analytic derivative: a slow sine takes a long window (error within 1 % of
    # its amplitude), a fast one a shorter window (within 2 %: the longest would bend it by
    # 70 %); both far below a difference quotient's error
    from aaria_pin.apps.identify.geometry_signals import noisy_derivative

    rng = np.random.default_rng(3)
    time = np.arange(6001) / 200.0
    level = 1e-3
    for frequency, share in ((0.5, 1e-2), (6.0, 2e-2)):  # [rad/s]
        exact = 0.05 * np.sin(frequency * time)
        truth = 0.05 * frequency * np.cos(frequency * time)
        noisy = exact + level * rng.standard_normal(time.size)
        estimate = noisy_derivative(time, noisy[:, None], level)[:, 0]
        error = np.sqrt(np.mean((estimate - truth)[600:-600] ** 2))
        raw = np.sqrt(np.mean((np.gradient(noisy, time) - truth) ** 2))
        assert error < share * 0.05 * frequency and error < raw / 40, (frequency, error, raw)


def test_clipped_samples_are_those_at_an_imu_range() -> None:
    from aaria_pin.apps.identify.geometry_signals import clipped_samples
    from aaria_pin.core.imu_noise import ADIS16485, noise_attributes

    parameters = noise_attributes(ADIS16485)
    g_range, a_range = parameters["gyro_range_rad_s"], parameters["accel_range_m_s2"]
    imu = np.zeros((10, 3, 6))
    imu[2, 1, 4] = -a_range  # an accelerometer at -5 g
    imu[5, 0, 1] = g_range  # a gyroscope at +450 °/s
    imu[7, 2, 3] = 0.99 * a_range  # within range: kept
    expected = np.zeros(10, dtype=bool)
    expected[[2, 5]] = True
    np.testing.assert_array_equal(clipped_samples(imu, parameters), expected)
    assert not clipped_samples(imu, None).any()  # no noise model: no flat top either


def test_without_a_range_a_flat_top_is_clipped() -> None:
    from aaria_pin.apps.identify.geometry_signals import clipped_samples

    rng = np.random.default_rng(3)
    t = np.linspace(0.0, 4.0, 801)
    imu = np.zeros((t.size, 2, 6))
    imu[:, :, :] = 30.0 * np.sin(2.0 * np.pi * t)[:, None, None]
    imu += rng.normal(0.0, 0.05, imu.shape)  # a noisy signal: its peaks are not flat
    imu[:, 0, 5] = 9.81  # a still axis reads a constant: not clipped
    assert not clipped_samples(imu, None).any()
    imu[:, 1, 4] = np.clip(imu[:, 1, 4], -25.0, 25.0)  # an accelerometer saturating at 25 m/s²
    expected = np.abs(imu[:, 1, 4]) >= 25.0
    np.testing.assert_array_equal(clipped_samples(imu, None), expected)
    assert expected.sum() > 100  # (the check can fail: the clip holds many samples)
