"""The run engine (core/run): settings checked once, motions that store and load themselves,
the registry of run kinds, pieces that put together are the whole run."""

from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.aaria.arm_run import DHArmSpec, dh_arm, preset_arm
from aaria_pin.aaria.presets import get_preset
from aaria_pin.core.record import RunRecord
from aaria_pin.core.run import (
    FourierMotion,
    RunSettings,
    SampledTrajectory,
    SineTable,
    TorqueDrive,
    join_chunks,
    kind_of,
    motion_from_record,
    simulate,
    simulate_pieces,
)
from aaria_pin.core.seeds import RunSeeds
from aaria_pin.core.trajectory import JointTrajectory
from aaria_pin.errors import InputFileError, ParameterError


@pytest.mark.parametrize(
    ("kwargs", "parameter"),
    [
        ({"duration": -1.0}, "duration"),
        ({"rate": 0.0}, "rate"),
        ({"duration": 0.001, "rate": 100.0}, "duration"),  # one sample
        ({"chunk": 0}, "chunk"),
        ({"threads": 0}, "threads"),
    ],
)
def test_run_settings_refuse_bad_values_naming_the_parameter(kwargs, parameter):
    with pytest.raises(ParameterError) as error:
        RunSettings(**kwargs)
    assert error.value.parameter == parameter
    assert "\n" not in str(error.value)


def test_run_settings_round_trip_through_the_attributes():
    settings = RunSettings(duration=2.5, rate=40.0, noise=False)
    attributes = settings.attributes(7)
    assert attributes["rate"] == 40.0 and attributes["duration"] == 2.5
    assert attributes["seed"] == 7 and attributes["noise"] is False
    assert RunSettings.from_attributes(attributes) == settings
    assert RunSettings.from_attributes(attributes, rate=80.0).rate == 80.0
    assert settings.samples() == 101  # ⌊2.5 · 40⌋ + 1


def test_pieces_put_together_are_the_whole_run_and_the_noise_is_the_seeds_stream():
    robot = preset_arm("aaria-fig2")
    settings = RunSettings(duration=1.0, rate=50.0, chunk=16)
    pieces = list(simulate_pieces(robot, None, settings, RunSeeds(5)))
    assert [p.n_samples for p in pieces] == [16, 16, 16, 3]
    whole = simulate(robot, None, settings, 5)
    joined = join_chunks(pieces)
    for name in ("time", "q", "qd", "qdd", "tau", "imu", "base_wrench", "tool_pose"):
        np.testing.assert_array_equal(getattr(joined, name), getattr(whole, name), name)
    np.testing.assert_array_equal(whole.time, np.arange(51) / 50.0)
    assert whole.attributes["kind"] == "dh" and whole.attributes["robot"] == "aaria-fig2"
    assert whole.attributes["motion"] == "sine" and whole.attributes["drive"] == "motion"
    quiet = simulate(robot, None, RunSettings(duration=1.0, rate=50.0, noise=False))
    assert not np.array_equal(quiet.imu, whole.imu)  # noise on by default


def test_a_sampled_trajectory_is_followed_by_module_and_stored():
    preset = get_preset("aaria-fig3")  # module 2 is empty
    robot = dh_arm(preset.table, DHArmSpec(preset.joint_table, preset.base_table))
    time = np.arange(26) / 25.0
    q = np.zeros((26, 6))
    q[:, 0] = 0.05 * np.sin(2.0 * time)
    qd = np.zeros((26, 6))
    qd[:, 0] = 0.1 * np.cos(2.0 * time)
    qdd = np.zeros((26, 6))
    qdd[:, 0] = -0.2 * np.sin(2.0 * time)
    motion = SampledTrajectory(JointTrajectory(time, q, qd, qdd))
    record = simulate(robot, motion, RunSettings(duration=1.0, rate=25.0, noise=False))
    np.testing.assert_array_equal(record.q[:, 0], 0.05 * np.sin(2.0 * time))
    assert not np.any(record.q[:, 1])  # the empty module
    assert record.attributes["motion"] == "trajectory"
    table = record.tables["joint_trajectory"]
    assert table.shape == (26, 19)
    loaded = motion_from_record(record.tables, record.attributes)
    assert isinstance(loaded, SampledTrajectory)
    np.testing.assert_array_equal(loaded.samples.q, q)


def test_motions_load_themselves_back_and_a_torque_drive_is_one_piece():
    tables = {"torque_table": np.zeros((11, 6))}
    assert isinstance(motion_from_record({}, {}), SineTable)  # a run written before motions
    drive = motion_from_record(tables, {"motion": "sine"})
    assert isinstance(drive, TorqueDrive) and drive.whole and drive.drive == "torque"
    assert isinstance(motion_from_record(tables, {"motion": "sine"}, drive=False), SineTable)
    with pytest.raises(InputFileError) as error:
        motion_from_record({}, {"motion": "fourier"})
    assert error.value.parameter == "fourier_coefficients"
    with pytest.raises(InputFileError) as error:
        motion_from_record({}, {"motion": "waltz"})
    assert error.value.parameter == "motion"
    robot = preset_arm("aaria-fig2")
    settings = RunSettings(duration=0.2, rate=50.0, chunk=4, noise=False)
    start = simulate(robot, None, settings)
    pieces = list(simulate_pieces(robot, TorqueDrive(start.tau), settings))
    assert len(pieces) == 1 and pieces[0].attributes["drive"] == "torque"
    np.testing.assert_array_equal(pieces[0].tables["torque_table"], start.tau)


def test_a_fourier_motion_of_other_joints_is_refused_before_any_work():
    from aaria_pin.core.excitation import fourier_excitation

    excitation = fourier_excitation(2, 1.0, 50.0)
    with pytest.raises(ParameterError) as error:
        simulate(preset_arm("aaria-fig2"), FourierMotion(excitation), RunSettings(1.0, 50.0))
    assert error.value.parameter == "motion"


def test_a_record_finds_its_kind_in_the_registry():
    import aaria_pin.aaria.simulate  # noqa: F401  (registers the DH kind)
    from aaria_pin.apps.remake import run_kind

    record = simulate(preset_arm("aaria-fig2"), None, RunSettings(duration=0.1, rate=50.0))
    assert kind_of(record).name == "dh"
    older = RunRecord(**{**record.__dict__, "attributes": {}})  # a file with no kind
    assert run_kind(older) == "dh"
    other = RunRecord(**{**record.__dict__, "attributes": {"kind": "boat"}})
    with pytest.raises(InputFileError) as error:
        kind_of(other)
    assert error.value.parameter == "kind"


def test_run_metadata_reads_the_attributes_as_fields_and_writes_them_back():
    from aaria_pin.core.run import RunMetadata

    record = simulate(preset_arm("aaria-fig2"), None, RunSettings(duration=0.2, rate=50.0), 3)
    meta = record.metadata
    assert (meta.kind, meta.robot, meta.rate, meta.duration) == ("dh", "aaria-fig2", 50.0, 0.2)
    assert meta.seed == 3 and meta.noise is True and meta.motion == "sine"
    assert meta.extra["body_dimensions"] == record.attributes["body_dimensions"]
    assert meta.to_attributes() == record.attributes
    older = RunMetadata.from_attributes({"rate": 100.0, "duration": 1.0, "seed": 4.0})
    assert older.kind is None and older.motion == "sine" and older.drive == "motion"
    assert older.seed == 4 and isinstance(older.seed, int)  # MATLAB stores a double
    with pytest.raises(InputFileError) as error:
        RunMetadata.from_attributes({"rate": "fast"})
    assert error.value.parameter == "rate"


class _Carrying:
    """A robot adapter with a payload: every other attribute is the wrapped robot's."""

    def __init__(self, robot, payload):
        self._robot = robot
        self.payload = payload

    def __getattr__(self, name):
        return getattr(self._robot, name)


def test_a_payload_loads_the_torques_of_the_held_samples_only_in_every_piece():
    from dataclasses import replace

    import pinocchio as pin

    from aaria_pin.core.dynamics import inverse_dynamics
    from aaria_pin.core.run import Payload

    robot = preset_arm("aaria-fig2")
    bare = robot.model
    model = bare.model.copy()
    last = model.njoints - 1
    model.inertias[last] = model.inertias[last] + pin.Inertia.FromSphere(3.0, 0.05)
    loaded = replace(bare, model=model)
    held = np.zeros(51, dtype=bool)
    held[10:30] = True
    carrying = _Carrying(robot, Payload(loaded, held))
    settings = RunSettings(duration=1.0, rate=50.0, noise=False)
    free = simulate(robot, None, settings)
    whole = simulate(carrying, None, settings)
    joined = join_chunks(list(simulate_pieces(carrying, None, replace(settings, chunk=16))))
    for name in ("tau", "base_wrench", "q", "tool_pose", "imu"):
        np.testing.assert_array_equal(getattr(joined, name), getattr(whole, name), name)
    # the loaded model's RNEA (Pinocchio, on the same motion) where held, the bare run elsewhere
    times = whole.time
    trajectory = SineTable().trajectory(robot, (0, 51), times, robot.base(times))
    tau, wrench = inverse_dynamics(loaded, robot.base(times), trajectory)
    np.testing.assert_allclose(whole.tau[held], robot.record_columns(tau)[held], atol=1e-12)
    np.testing.assert_allclose(whole.base_wrench[held], wrench[held], atol=1e-12)
    np.testing.assert_array_equal(whole.tau[~held], free.tau[~held])
    np.testing.assert_array_equal(whole.base_wrench[~held], free.base_wrench[~held])
    assert np.abs(whole.tau[held] - free.tau[held]).max() > 1.0  # 3 kg on the last body
    np.testing.assert_array_equal(whole.imu, free.imu)  # the kinematics do not change


def test_a_misspelt_option_is_refused_as_python_refuses_a_keyword() -> None:
    """``**options: Unpack[...]`` is not checked by Python: the requests check it themselves."""
    import warnings

    from aaria_pin.aaria.presets import get_preset
    from aaria_pin.aaria.simulate import dh_request, simulate_run
    from aaria_pin.core.catalogue import find_robot
    from aaria_pin.core.urdf_run import urdf_request

    table = get_preset("aaria-fig2").table
    with pytest.raises(TypeError, match="unexpected keyword argument 'durration'"):
        dh_request(table, durration=0.1)  # type: ignore[call-arg]
    with warnings.catch_warnings(), pytest.raises(TypeError, match="'rat'"):
        warnings.simplefilter("ignore", DeprecationWarning)
        simulate_run(table, rat=10.0)  # type: ignore[call-arg]
    with pytest.raises(TypeError, match="'tool'"):
        urdf_request(find_robot("ur5").urdf.read_text(), tool="x")  # type: ignore[call-arg]
    assert dh_request(table, duration=0.1).record().n_samples == 11
