"""Dynamic identification: the regressor against Pinocchio's, the base parameter count against an
independent rank, the total mass and centre of mass against the URDF's own numbers, held-out
torques, the JSON report and the command body."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from dataclasses import replace

import numpy as np
import pinocchio as pin
import pytest
from pinocchio_oracles import reference_torque_regressor

from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.apps.identify import (
    base_parameters,
    identify_dynamics,
    standard_parameters,
    torque_regressor,
)
from aaria_pin.apps.record_model import record_base, record_columns, record_model
from aaria_pin.core.catalogue import find_robot
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory
from aaria_pin.core.urdf_run import simulate_urdf_run
from aaria_pin.errors import ParameterError


@pytest.fixture(scope="module")
def ur5_record():
    entry = find_robot("ur5")
    return simulate_urdf_run(
        entry.urdf.read_text(), urdf_dir=entry.urdf.parent, duration=20, rate=100, noise=False
    )


@pytest.fixture(scope="module")
def fig2_record():
    preset = get_preset("aaria-fig2")
    return simulate_run(
        preset.table, preset.joint_table, preset.base_table, duration=20, rate=100, noise=False
    )


@pytest.fixture(scope="module")
def fig3_record():
    preset = get_preset("aaria-fig3")
    return simulate_run(
        preset.table, preset.joint_table, preset.base_table, duration=10, rate=100, noise=False
    )


def _urdf_mass(urdf: str) -> float:
    """The sum of every link's <mass value> in the URDF text (no Pinocchio)."""
    root = ET.fromstring(urdf)
    return sum(float(mass.get("value")) for mass in root.iter("mass"))


def _parts(record, moving_base=True):
    base = record_base(record)
    robot = record_model(record, moving_base=moving_base)
    columns = record_columns(record, robot)
    base = base or BaseMotion.resting(record.n_samples)
    trajectory = JointTrajectory(
        record.time,
        *(np.ascontiguousarray(x[:, columns]) for x in (record.q, record.qd, record.qdd)),
    )
    return robot, base, trajectory, columns


@pytest.mark.parametrize("name", ["ur5_record", "fig3_record"])
def test_regressor_equals_pinocchios(request, name):
    """ur5 (revolute) and aaria-fig3 (prismatic, revolute, an empty module), moving base."""
    robot, base, trajectory, _ = _parts(request.getfixturevalue(name))
    every = slice(None, None, 7)
    part = JointTrajectory(
        *(x[every] for x in (trajectory.time, trajectory.q, trajectory.qd, trajectory.qdd))
    )
    part_base = BaseMotion(
        *(
            getattr(base, f)[every]
            for f in ("position", "velocity", "acceleration", "rotation", "omega", "omega_dot")
        )
    )
    fast = torque_regressor(robot, part_base, part)
    reference = reference_torque_regressor(robot, part_base, part)
    assert (
        fast.shape
        == reference.shape
        == (part.q.shape[0], robot.model.nv, 10 * (robot.model.njoints - 1))
    )
    assert np.max(np.abs(fast - reference)) <= 1e-9 * np.max(np.abs(reference))


def test_regressor_on_a_fixed_base_equals_pinocchios(ur5_record):
    robot, _, trajectory, _ = _parts(ur5_record, moving_base=False)
    every = slice(None, None, 25)
    part = JointTrajectory(
        *(x[every] for x in (trajectory.time, trajectory.q, trajectory.qd, trajectory.qdd))
    )
    resting = BaseMotion.resting(part.q.shape[0])
    fast = torque_regressor(robot, resting, part)
    reference = reference_torque_regressor(robot, resting, part)
    assert np.max(np.abs(fast - reference)) <= 1e-9 * np.max(np.abs(reference))


def test_regressor_times_the_model_parameters_gives_the_recorded_torques(fig2_record):
    robot, base, trajectory, columns = _parts(fig2_record)
    _, parameters = standard_parameters(robot)
    generalized = torque_regressor(robot, base, trajectory) @ parameters
    tau = fig2_record.tau[:, columns]
    assert np.max(np.abs(generalized[:, 6:] - tau)) <= 1e-9 * np.max(np.abs(tau))
    R = base.rotation  # the record's wrench is world-aligned; the regressor's in base axes
    force = np.einsum("tij,tj->ti", R, generalized[:, :3])
    assert np.max(np.abs(force - fig2_record.base_wrench[:, :3])) <= 1e-9 * np.max(
        np.abs(fig2_record.base_wrench[:, :3])
    )


@pytest.mark.parametrize("name", ["ur5_record", "fig2_record"])
def test_identification_predicts_held_out_torques_and_recovers_the_mass(request, name):
    record = request.getfixturevalue(name)
    result = identify_dynamics(record, holdout=0.25)
    assert result.samples_holdout == round(0.25 * record.n_samples)
    assert result.signals[:6] == ("base_fx", "base_fy", "base_fz", "base_mx", "base_my", "base_mz")
    assert np.all(result.holdout_relative_rms <= 1e-6)
    # the total mass against the URDF's masses added up by hand
    assert result.total_mass == pytest.approx(_urdf_mass(record.urdf), rel=1e-9)
    assert result.total_mass_model == pytest.approx(_urdf_mass(record.urdf), rel=1e-12)
    # the centre of mass at t = 0 against Pinocchio's centerOfMass, base at the origin
    robot, _, trajectory, _ = _parts(record)
    q = np.concatenate([[0, 0, 0, 0, 0, 0, 1.0], trajectory.q[0]])
    com = pin.centerOfMass(robot.model, robot.model.createData(), q)
    report = result.to_json()
    assert np.allclose(report["centre_of_mass"]["estimate_start"], com, rtol=0, atol=1e-9)
    assert report["centre_of_mass"]["error"]["max"] <= 1e-9
    # the estimates are the model's base parameters, with tiny standard deviations
    scale = np.maximum(np.abs(result.model_values), 1.0)  # kg, kg·m, kg·m²
    assert np.all(np.abs(result.estimate - result.model_values) <= 1e-6 * scale)
    assert np.all(result.std <= 1e-6 * scale)


def _independent_rank(reference_rows: np.ndarray) -> int:
    """Rank of a stacked regressor from its singular values: the largest gap (log scale)."""
    columns = reference_rows / np.maximum(np.linalg.norm(reference_rows, axis=0), 1e-300)
    singular = np.linalg.svd(columns, compute_uv=False)
    singular = singular[singular > 0]
    gaps = np.diff(np.log10(singular))
    return int(np.argmin(gaps)) + 1


@pytest.mark.parametrize("name", ["ur5_record", "fig2_record", "fig3_record"])
def test_base_parameter_count_equals_an_independent_rank(request, name):
    record = request.getfixturevalue(name)
    result = identify_dynamics(record)
    robot, base, trajectory, _ = _parts(record)
    every = slice(0, result.samples_train, 4)
    part = JointTrajectory(
        *(x[every] for x in (trajectory.time, trajectory.q, trajectory.qd, trajectory.qdd))
    )
    part_base = BaseMotion(
        *(
            getattr(base, f)[every]
            for f in ("position", "velocity", "acceleration", "rotation", "omega", "omega_dot")
        )
    )
    rows = reference_torque_regressor(robot, part_base, part).reshape(
        -1, result.base.combination.shape[1]
    )
    assert result.base.rank == _independent_rank(rows)
    # every base parameter's combination is one the data see: W·Kᵀ·K = W on the regressor
    K = result.base.combination
    W1 = rows[:, list(result.base.independent)]
    assert np.allclose(W1 @ K, rows, rtol=0, atol=1e-8 * np.max(np.abs(rows)))


def test_base_parameters_of_a_known_rank_deficient_matrix():
    """Column 2 = 2·column 0 - column 1, column 3 zero: two base parameters, named combinations."""
    rng = np.random.default_rng(0)
    a, b = rng.standard_normal((2, 50))
    W = np.column_stack([a, b, 2 * a - b, np.zeros(50)])
    names = ("p0", "p1", "p2", "p3")
    found = base_parameters(W, names)
    assert found.rank == 2
    # K·pi gives the same torques: W = W1·K for any parameter vector
    assert np.allclose(W[:, list(found.independent)] @ found.combination, W, atol=1e-12)
    assert all(name in {"p0", "p1", "p2"} for name in found.names)
    # W·pi = a·(p0 + 2·p2) + b·(p1 - p2): those two are determined, p0 or p3 alone is not
    assert found.identifiable(np.array([1.0, 0, 2, 0]))
    assert found.identifiable(np.array([0, 1.0, -1, 0]))
    assert not found.identifiable(np.array([1.0, 0, 0, 0]))
    assert not found.identifiable(np.array([0, 0, 0, 1.0]))
    assert found.pivots[2] < 1e-12 and found.pivots[3] == 0
    with pytest.raises(ParameterError) as error:
        base_parameters(W, names[:3])
    assert error.value.parameter == "names"


def test_without_the_base_wrench_the_total_mass_is_not_determined(ur5_record):
    result = identify_dynamics(ur5_record, use_base_wrench=False)
    assert result.signals == ur5_record.joint_names
    assert np.isnan(result.total_mass)
    assert np.all(result.holdout_relative_rms <= 1e-6)
    report = result.to_json()
    assert report["total_mass"]["estimate"] is None and report["centre_of_mass"]["error"] == {}
    json.dumps(report)


def test_report_and_holdout_checks(fig3_record):
    result = identify_dynamics(fig3_record, holdout=0.0)
    report = result.to_json()
    assert report["samples_holdout"] == 0 and report["worst_holdout_relative_rms"] is None
    assert len(report["base_parameters"]) == report["n_base"] == result.base.rank
    assert "joint2" not in report["signals"]  # module 2 of aaria-fig3 is empty
    first = report["base_parameters"][0]
    assert set(first) == {"name", "combination", "estimate", "std", "model"}
    assert first["combination"].startswith(first["name"])
    json.dumps(report)
    for bad in (-0.1, 0.95, float("nan")):
        with pytest.raises(ParameterError) as error:
            identify_dynamics(fig3_record, holdout=bad)
        assert error.value.parameter == "holdout" and "\n" not in str(error.value)


def test_the_estimate_follows_the_data_not_the_urdf(ur5_record):
    """Torques and wrench 10 % larger are those of the robot with every inertia 10 % larger:
    the estimate finds that robot, while the model's values stay the URDF's."""
    heavier = replace(
        ur5_record, tau=ur5_record.tau * 1.1, base_wrench=ur5_record.base_wrench * 1.1
    )
    result = identify_dynamics(heavier)
    assert np.all(result.holdout_relative_rms <= 1e-6)
    assert result.total_mass == pytest.approx(1.1 * result.total_mass_model, rel=1e-9)
    scale = np.maximum(np.abs(result.model_values), 1.0)  # kg, kg·m, kg·m²
    assert np.all(np.abs(result.estimate - 1.1 * result.model_values) <= 1e-6 * scale)


def test_a_fixed_base_with_its_mount_load_recovers_the_mass():
    """A ur5 on a fixed base: the recorded load on the mount identifies the total mass."""
    entry = find_robot("ur5")
    record = simulate_urdf_run(
        entry.urdf.read_text(),
        urdf_dir=entry.urdf.parent,
        moving_base=False,
        duration=10,
        rate=100,
        noise=False,
    )
    assert record_base(record) is None
    result = identify_dynamics(record)
    assert result.extras["moving_base"] and result.signals[0] == "base_fx"
    assert np.all(result.holdout_relative_rms <= 1e-6)
    assert result.total_mass == pytest.approx(_urdf_mass(record.urdf), rel=1e-9)


def test_pieces_give_the_one_piece_result(fig3_record):
    whole = identify_dynamics(fig3_record, chunk=10**6)
    pieces = identify_dynamics(fig3_record, chunk=97)
    assert pieces.base.rank == whole.base.rank  # (ties may pivot other, equivalent columns)
    assert pieces.total_mass == pytest.approx(whole.total_mass, rel=1e-12)
    assert np.allclose(pieces.holdout_rms, whole.holdout_rms, rtol=0, atol=1e-9)
    assert np.all(pieces.holdout_relative_rms <= 1e-6)
    assert pieces.to_json()["centre_of_mass"]["error"]["max"] <= 1e-9


def test_fourier_excitation_identifies(ur5_record):
    """The ur5 moved by a Fourier excitation (torques and wrench by Pinocchio's RNEA): every
    base parameter the sines found, held-out torques to 1e-6, the mass."""
    from aaria_pin.core.dynamics import inverse_dynamics
    from aaria_pin.core.excitation import fourier_motion

    robot, base, trajectory, _ = _parts(ur5_record)
    motion = fourier_motion(
        6, 20.0, 100.0, q_limits=(-2.0, 2.0), qd_limits=2.0, qdd_limits=8.0, seed=11
    )
    assert np.array_equal(motion.time, trajectory.time)
    tau, wrench = inverse_dynamics(robot, base, motion)
    excited = replace(
        ur5_record, q=motion.q, qd=motion.qd, qdd=motion.qdd, tau=tau, base_wrench=wrench
    )
    result = identify_dynamics(excited)
    assert result.base.rank >= identify_dynamics(ur5_record).base.rank
    assert np.all(result.holdout_relative_rms <= 1e-6)
    assert result.total_mass == pytest.approx(_urdf_mass(ur5_record.urdf), rel=1e-9)
