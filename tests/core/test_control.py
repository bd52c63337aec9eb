"""Closed-loop drives (``core/control.py`` and its kernel): tracking, the laws, the loop's parts.

Each law is checked against an independent computation from the recorded run: the PD's
command from the recorded reference and state; the computed torque's from Pinocchio's RNEA at
the recorded state; the motor torque the plant received (the actuator channel's
``tau + armature·qdd + friction(qd)``, Pinocchio's RNEA of the resulting motion) against the
recorded command. Tracking is measured on the default motions of ur5 and aaria-fig2 with the
default controller and friction on (the issue's 1 mrad RMS).
"""

from __future__ import annotations

import itertools
from functools import cache
from typing import Any

import numpy as np
import pinocchio as pin
import pytest

import aaria_pin as ap
from aaria_pin.aaria.simulate import dh_request
from aaria_pin.core.catalogue import find_robot
from aaria_pin.core.control import (
    ControllerSensing,
    closed_loop_simulate,
    control_substeps,
    controller_gains,
)
from aaria_pin.core.forward import forward_simulate
from aaria_pin.core.joint_sensors import (
    ActuatorModel,
    ControllerModel,
    EncoderModel,
    TorqueSensorModel,
)
from aaria_pin.core.record import RunRecord
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory
from aaria_pin.core.urdf_robot import read_urdf_file
from aaria_pin.core.urdf_run import urdf_request
from aaria_pin.errors import ParameterError, TrackingError

FRICTION = ActuatorModel(rotor_inertia=2e-5, gear_ratio=100, viscous=0.5, coulomb=1.0)
"""Armature 0.2 kg·m², viscous 0.5 N·m·s/rad, Coulomb 1 N·m on every joint."""


def ur5_run(**options: Any) -> RunRecord:
    """A ur5 run on a fixed base (noise off unless given)."""
    text = read_urdf_file(find_robot("ur5").urdf)
    options = {"noise": False, "moving_base": False, **options}
    return urdf_request(text, source="ur5", **options).record()


def fig2_run(**options: Any) -> RunRecord:
    """An aaria-fig2 run on its moving base (noise off unless given)."""
    preset = ap.get_preset("aaria-fig2")
    options = {"noise": False, "joint_table": preset.joint_table, **options}
    return dh_request(preset.table, base_table=preset.base_table, **options).record()


RUNS = {"ur5": ur5_run, "aaria-fig2": fig2_run}


def rms(record: RunRecord) -> float:
    """Tracking RMS over every joint and sample [rad or m]."""
    return float(np.sqrt(np.mean((record.q - record.tables["q_reference"]) ** 2)))


@cache
def tracked(name: str, law: str) -> RunRecord:
    """The default motion of ``name`` (10 s at 100 Hz) tracked by ``law``, friction on."""
    return RUNS[name](drive=law, actuator=FRICTION)


@pytest.mark.parametrize("name", sorted(RUNS))
@pytest.mark.parametrize(("law", "bound"), [("pd", 1e-3), ("computed-torque", 1e-5)])
def test_default_controllers_track_the_default_motion(name: str, law: str, bound: float) -> None:
    record = tracked(name, law)
    assert record.attributes["drive"] == law
    assert record.attributes["controller"]["frequency"] == 50.0
    assert rms(record) < bound, rms(record)
    np.testing.assert_array_equal(record.q[0], record.tables["q_reference"][0])


@pytest.mark.parametrize("name", sorted(RUNS))
def test_the_pd_command_is_the_law_of_the_recorded_state(name: str) -> None:
    record = tracked(name, "pd")
    kp, kd = record.tables["controller_kp"][0], record.tables["controller_kd"][0]
    error = record.tables["q_reference"] - record.q
    rate_error = record.tables["qd_reference"] - record.qd
    expected = kp * error + kd * rate_error
    scale = np.abs(expected).max()
    np.testing.assert_allclose(record.tables["tau_command"], expected, atol=1e-9 * scale)


@pytest.mark.parametrize("name", sorted(RUNS))
@pytest.mark.parametrize("law", ["pd", "computed-torque"])
def test_the_plant_receives_the_command(name: str, law: str) -> None:
    """RNEA of the resulting motion + armature·qdd + friction = the command (no saturation)."""
    record = tracked(name, law)
    motor = record.tables["tau_motor"]  # the actuator channel: tau + armature qdd + friction
    command = record.tables["tau_command"]
    present = np.abs(command).max(axis=0) > 0  # an Aaria arm's empty modules are 0
    scale = np.abs(command).max()
    np.testing.assert_allclose(motor[:, present], command[:, present], atol=1e-8 * scale)


def test_the_computed_torque_is_rnea_at_the_state() -> None:
    record = tracked("ur5", "computed-torque")
    text = read_urdf_file(find_robot("ur5").urdf)
    model = pin.buildModelFromXML(text)
    data = model.createData()
    kp, kd = record.tables["controller_kp"][0], record.tables["controller_kd"][0]
    omega = 2 * np.pi * 50.0
    np.testing.assert_allclose(kp, omega**2)
    np.testing.assert_allclose(kd, 2 * omega)
    armature = 2e-5 * 100**2
    for t in (0, 137, 555, 1000):
        q, qd = record.q[t], record.qd[t]
        u = (
            _reference_acceleration(record, t)
            + kp * (record.tables["q_reference"][t] - q)
            + kd * (record.tables["qd_reference"][t] - qd)
        )
        qd_ref = record.tables["qd_reference"][t]
        friction = 0.5 * qd_ref + 1.0 * np.tanh(qd_ref / 0.01)
        expected = pin.rnea(model, data, q, qd, u) + armature * u + friction
        np.testing.assert_allclose(record.tables["tau_command"][t], expected, rtol=1e-9, atol=1e-9)


def _reference_acceleration(record: RunRecord, t: int) -> np.ndarray:
    """The reference's acceleration at sample t: the sine table's, in closed form."""
    table = record.tables["joint_table"]
    amplitude, w, phase = table[:, 0], table[:, 3], table[:, 4]
    return -amplitude * w**2 * np.sin(w * record.time[t] + phase)


def test_encoder_offsets_are_in_the_loop() -> None:
    """The controller tracks in its encoders' frame: the true joint sits ``-offset`` away."""
    encoder = EncoderModel(counts_per_revolution=2**20, offset=0.01)
    record = ur5_run(drive="computed-torque", encoder=encoder, duration=2.0)
    offset = record.tables["encoder_offset"][0]
    assert np.abs(offset).min() > 1e-4  # drawn: the check below can fail
    settled = record.time > 0.5
    error = record.q[settled] - record.tables["q_reference"][settled]
    np.testing.assert_allclose(error.mean(axis=0), -offset, atol=2e-5)
    step = 2 * np.pi / 2**20
    counts = (record.tables["q_measured"] - offset) / step
    np.testing.assert_allclose(counts, np.round(counts), atol=1e-6)


def test_torque_feedback_makes_up_the_friction_without_chatter() -> None:
    heavy = ActuatorModel(coulomb=8.0, viscous=2.0)
    sensor = TorqueSensorModel()
    plain = ur5_run(drive="pd", actuator=heavy, torque_sensor=sensor, duration=3.0)
    fed = ur5_run(
        drive="pd",
        actuator=heavy,
        torque_sensor=sensor,
        duration=3.0,
        controller=ControllerModel(torque_feedback=4.0),
    )
    assert rms(fed) < 0.35 * rms(plain), (rms(fed), rms(plain))
    motor = fed.tables["tau_motor"]
    assert np.abs(motor).max() < 0.9 * 150.0  # never at ur5's effort limit: no chatter
    steps = np.abs(np.diff(motor, axis=0))[10:]  # after the first 0.1 s
    assert np.median(steps) < 0.2, np.median(steps)


def test_computed_torque_with_the_torque_loop_does_not_compensate_twice() -> None:
    """Its loop holds the link-side torque M·u + b, not the motor command (review finding)."""
    motors = ActuatorModel(coulomb=8.0, viscous=2.0, rotor_inertia=2e-5, gear_ratio=100)
    options = {"drive": "computed-torque", "actuator": motors, "duration": 3.0}
    sensor = TorqueSensorModel()
    plain = ur5_run(torque_sensor=sensor, **options)
    fed = ur5_run(torque_sensor=sensor, controller=ControllerModel(torque_feedback=4.0), **options)
    assert rms(fed) < 3 * rms(plain) < 3e-6, (rms(fed), rms(plain))


def test_motor_torques_saturate_at_their_limit() -> None:
    weak = ActuatorModel(torque_limit=45.0)
    record = ur5_run(drive="computed-torque", actuator=weak, duration=2.0, limits="ignore")
    assert np.abs(record.tables["tau_command"]).max() > 45.0  # the controller asks for more
    assert np.abs(record.tables["tau_motor"]).max() <= 45.0 + 1e-9


def test_unstable_gains_fail_the_run_naming_the_joint_and_gains() -> None:
    with pytest.raises(TrackingError, match=r"drive pd lost its reference: joint \w+ at t = .*kp"):
        ur5_run(drive="pd", controller=ControllerModel(kp=1e7, kd=1.0), duration=1.0)


def test_a_controller_without_a_closed_loop_drive_is_refused() -> None:
    with pytest.raises(ParameterError, match="controller is given for a run of drive 'motion'"):
        ur5_run(controller=ControllerModel(), duration=1.0)


def test_control_rate_is_one_number_and_sets_the_substeps() -> None:
    with pytest.raises(ParameterError, match="rate"):
        ControllerModel(rate=(1000.0, 2000.0))
    assert control_substeps(ControllerModel(rate=2000.0), 100.0) == 20
    for rate in (50.0, 150.0, 1e9):
        with pytest.raises(ParameterError, match="allowed: a whole multiple of the sample rate"):
            control_substeps(ControllerModel(rate=rate), 100.0)


def test_pd_gains_keep_every_pose_of_the_reference_stable() -> None:
    """At every pose along the reference, ``K ≤ diag(1/(M⁻¹)_ii)·ω²``, so ``eig(M⁻¹K) ≤ n·ω²``."""
    record = tracked("ur5", "pd")
    model = pin.buildModelFromXML(read_urdf_file(find_robot("ur5").urdf))
    data = model.createData()
    kp = record.tables["controller_kp"][0]
    omega2 = (2 * np.pi * 50.0) ** 2
    tight = 0.0
    for t in range(record.q.shape[0]):
        mass = pin.crba(model, data, record.tables["q_reference"][t])
        mass = np.triu(mass) + np.triu(mass, 1).T + np.diag(np.full(6, 0.2))  # armature
        effective = 1 / np.diag(np.linalg.inv(mass))
        assert (kp <= effective * omega2 * (1 + 1e-9)).all()
        tight = max(tight, float((kp / (effective * omega2)).max()))
        modes = np.linalg.eigvals(np.linalg.solve(mass, np.diag(kp))).real
        assert modes.max() <= 6 * omega2
    assert tight > 0.95  # the lightest pose is among those checked: the bound is reached


def test_the_laws_are_the_closed_loop_drives_in_the_kernels_order() -> None:
    from aaria_pin.core import _control_kernel
    from aaria_pin.core.control import LAWS
    from aaria_pin.core.joint_sensors import CLOSED_LOOP_DRIVES

    assert tuple(LAWS) == CLOSED_LOOP_DRIVES
    assert (_control_kernel.PD, _control_kernel.COMPUTED_TORQUE) == (0, 1)


def test_a_loop_ringing_fast_is_lost_though_its_position_stays_near() -> None:
    with pytest.raises(TrackingError, match="faster or slower than it"):
        ur5_run(drive="pd", controller=ControllerModel(frequency=150.0), limits="ignore")


def test_a_closed_loop_run_in_spans_is_the_run_at_once() -> None:
    """With encoders in the loop, progress told or not: the same numbers (the noise per span)."""
    text = read_urdf_file(find_robot("ur5").urdf)
    robot = ap.load_urdf_robot(text, moving_base=False).robot
    record = tracked("ur5", "pd")
    reference = JointTrajectory(
        record.time, record.tables["q_reference"], record.tables["qd_reference"], record.qdd
    )
    base = BaseMotion.resting(record.time.size)
    n, zeros = 6, np.zeros(6)

    def sensing() -> ControllerSensing:
        return ControllerSensing(
            np.full(n, 2 * np.pi / 2**20), zeros + 1e-3, zeros + 1e-5, None, zeros, zeros,
            zeros, np.random.default_rng(1), np.random.default_rng(2),
        )  # fmt: skip

    told: list[int] = []
    once = closed_loop_simulate(robot, base, reference, "pd", ControllerModel(), sensing=sensing())
    spans = closed_loop_simulate(
        robot, base, reference, "pd", ControllerModel(), sensing=sensing(),
        progress=lambda done, total: told.append(done),
    )  # fmt: skip
    assert len(told) > 5
    np.testing.assert_array_equal(once.trajectory.q, spans.trajectory.q)
    np.testing.assert_array_equal(once.command, spans.command)


def test_given_gains_are_kept() -> None:
    robot = ap.load_urdf_robot(read_urdf_file(find_robot("ur5").urdf), moving_base=False).robot
    record = tracked("ur5", "pd")
    reference = JointTrajectory(record.time, record.q, record.qd, record.qdd)
    kp, kd = controller_gains(robot, reference, "pd", ControllerModel(kp=(1.0, 0, 3, 0, 5, 0)))
    assert kp[0] == 1.0 and kp[2] == 3.0 and kp[4] == 5.0 and kp[1] > 100
    assert (kd > 0).all()


def test_a_run_in_spans_is_the_run_at_once() -> None:
    """The torque drive's kernel in spans (with progress told) is bit for bit the run at once."""
    record = ur5_run(duration=3.0, rate=200.0)
    robot = ap.load_urdf_robot(read_urdf_file(find_robot("ur5").urdf), moving_base=False).robot
    base = BaseMotion.resting(record.time.size)
    told: list[tuple[int, int]] = []
    args = (robot, base, record.tau * 0.9, record.time, record.q[0], record.qd[0])
    once = forward_simulate(*args)
    spans = forward_simulate(*args, progress=lambda done, total: told.append((done, total)))
    for a, b in ((once.q, spans.q), (once.qd, spans.qd), (once.qdd, spans.qdd)):
        np.testing.assert_array_equal(a, b)
    assert len(told) > 5 and told[-1] == (record.time.size, record.time.size)
    assert all(a[0] < b[0] for a, b in itertools.pairwise(told))
