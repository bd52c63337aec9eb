"""Kinematic identification of a recording (``ArmSignals.of_recorded``): a DH table from a bag.

Each table is checked against an independent expectation: the tool tip by Pinocchio's forward
kinematics of the estimated and of the true table (the simulated run's ``senSenDH``) at the
run's true joint values, and the link types against the true table's. The recordings are made
from simulated runs' arrays, with each sensor's own stamps where the test is about them.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from recorded_arm import small_arm_tables, tool_tip_error

from aaria_pin.aaria.simulate import dh_request
from aaria_pin.apps.identify import identify_kinematics
from aaria_pin.apps.identify.geometry_input import ArmSignals, imu_parent, white_noise_level
from aaria_pin.apps.recordings import export_run, import_recordings, recorded_from_run
from aaria_pin.core.record import RunRecord
from aaria_pin.core.recording import STREAM_COLUMNS, RecordedRun, SensorStream
from aaria_pin.errors import ParameterError

MM = 1e-3


def small_arm(duration: float, rate: float, noise: bool) -> RunRecord:
    """The 3-module arm (module 2 empty) on a moving base, simulated."""
    table, joints, base = small_arm_tables()
    request = dh_request(
        table, joint_table=joints, base_table=base, duration=duration, rate=rate, noise=noise
    )
    return request.record()


def tip_error(table: np.ndarray, truth: RunRecord) -> float:
    return tool_tip_error(table, truth.tables["senSenDH"], np.asarray(truth.q))


def true_types(truth: RunRecord) -> tuple[int, ...]:
    return tuple(int(t) for t in truth.tables["senSenDH"][:6, 4])


@pytest.fixture(scope="module")
def clean() -> RunRecord:
    return small_arm(2.0, 200.0, noise=False)


def test_a_recording_of_a_run_gives_the_runs_table(clean: RunRecord, tmp_path: Path) -> None:
    path = export_run(clean, tmp_path / "run.mcap")
    signals = ArmSignals.of_recorded(import_recordings([path]))
    assert not signals.noisy and signals.noise_model.startswith("none")
    assert signals.truth is None and signals.notes == ()
    found = identify_kinematics(signals)
    assert found.failure is None and found.truth is None
    assert found.link_types == true_types(clean)
    assert tip_error(found.table, clean) <= 1 * MM
    # the run file's own identification: the same arrays, the same table
    np.testing.assert_allclose(found.table, identify_kinematics(clean).table, atol=1e-9)
    assert [m.parent for m in found.mounts] == ["base", "link1", "link1", "link3", "link3",
                                                "tool_tip"]  # fmt: skip


def _jittered(record: RunRecord, step: int, rng: np.random.Generator) -> np.ndarray:
    """Indices of every ``step``-th sample, each moved by up to a fifth of the step."""
    index = np.arange(step, record.n_samples - step, step)
    return np.unique(index + rng.integers(-(step // 5), step // 5 + 1, index.size))


@pytest.fixture(scope="module")
def fine() -> RunRecord:
    return small_arm(2.0, 1000.0, noise=False)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_jittered_stamps_and_an_imu_at_half_the_rate(fine: RunRecord, dtype: type) -> None:
    # simulated at 1000 Hz; every IMU and the joints sampled at ~200 Hz with their own jitter
    # (up to 1 ms of the 5 ms period), imu_link3_a at ~100 Hz; stored in float64 or float32
    rng = np.random.default_rng(7)
    time = np.asarray(fine.time, dtype=float)
    streams, taken = [], {}
    for stream in recorded_from_run(fine).streams:
        if stream.kind == "wrench":
            continue
        index = taken[stream.name] = _jittered(fine, 10 if stream.name == "imu_link3_a" else 5, rng)
        values = stream.values[index].astype(dtype).astype(float)
        streams.append(SensorStream(stream.name, stream.kind, time[index], values, stream.columns))
    recording = RecordedRun(streams)
    steps = np.diff(recording.stream("imu_base").time)
    assert steps.max() - steps.min() > 1e-3  # the base's own stamps are not even
    signals = ArmSignals.of_recorded(recording)
    half = [note for note in signals.notes if note.startswith("imu_link3_a resampled")]
    assert len(half) == 1 and any(
        note.startswith("joint states resampled") for note in signals.notes
    )
    if dtype is np.float64:
        # the stated error of the resampling against the simulated signals at the base's stamps
        at = taken["imu_base"][np.isin(time[taken["imu_base"]], signals.time)]
        true = fine.imu[at, fine.imu_names.index("imu_link3_a")]
        error = np.abs(signals.imu[:, signals.imu_names.index("imu_link3_a")] - true)
        stated = [
            float(x) for x in re.findall(r"error ([0-9.e+-]+) rad/s, ([0-9.e+-]+) m/s", half[0])[0]
        ]
        assert error[:, :3].max() <= 2 * stated[0] and error[:, 3:].max() <= 2 * stated[1]
    found = identify_kinematics(signals)
    assert found.failure is None
    assert found.link_types == true_types(fine)
    assert tip_error(found.table, fine) <= 1 * MM


def test_a_late_recordings_own_stamps_are_kept(clean: RunRecord) -> None:
    # an hour into a log, stamps jittered by 0.1 ms: within 4 float32 roundings of an even grid
    # (1 ms at 3600 s), but float64 stamps of their own, not a float32 run's: kept as they are
    rng = np.random.default_rng(3)
    time = np.asarray(clean.time, dtype=float) + 3600.0
    time = time + rng.uniform(-1e-4, 1e-4, time.size)
    streams = [
        SensorStream(s.name, s.kind, time, s.values, s.columns)
        for s in recorded_from_run(clean).streams
        if s.kind != "wrench"
    ]
    signals = ArmSignals.of_recorded(RecordedRun(streams))
    np.testing.assert_array_equal(signals.time, time)


def test_noisy_recording_as_accurate_as_its_run(tmp_path: Path) -> None:
    # ADIS16485 noise, the simulator's default: the recording assumes that model, measures
    # its noise as the model's, and reaches what the run file reaches (not a tuned constant)
    noisy = small_arm(6.0, 200.0, noise=True)
    signals = ArmSignals.of_recorded(import_recordings([export_run(noisy, tmp_path / "n.bag")]))
    assert signals.noisy and signals.noise_model.startswith("ADIS16485 (assumed")
    from_recording = identify_kinematics(signals)
    from_run = identify_kinematics(noisy)
    assert from_recording.link_types == from_run.link_types == true_types(noisy)
    # the recording keeps its own float64 stamps where the run's are rebuilt: equal within 1 %
    assert tip_error(from_recording.table, noisy) <= 1.01 * tip_error(from_run.table, noisy)


def test_white_noise_level_of_jittered_samples() -> None:
    # a smooth signal at jittered stamps plus white noise of σ = 0.01: the level is σ, not
    # the jitter; without the noise it is far below
    rng = np.random.default_rng(3)
    time = np.sort(rng.uniform(0.0, 10.0, 2000))
    smooth = np.column_stack([np.sin(2 * time), np.cos(0.7 * time)])
    noisy = smooth + 0.01 * rng.standard_normal(smooth.shape)
    assert white_noise_level(time, noisy) == pytest.approx([0.01, 0.01], rel=0.1)
    assert np.all(white_noise_level(time, smooth) < 1e-6)


def _renamed(stream: SensorStream) -> SensorStream:
    return SensorStream("wrist", "imu", stream.time, stream.values, STREAM_COLUMNS["imu"])


def _joints_named(stream: SensorStream) -> SensorStream:
    columns = tuple(c.replace(":joint", ":j") for c in stream.columns)
    return SensorStream(stream.name, "joints", stream.time, stream.values, columns)


def _without_joint3(stream: SensorStream) -> SensorStream:
    kept = [k for k, c in enumerate(stream.columns) if not c.endswith(":joint3")]
    columns = tuple(stream.columns[k] for k in kept)
    return SensorStream(stream.name, "joints", stream.time, stream.values[:, kept], columns)


def _streams(record: RunRecord) -> list[SensorStream]:
    return list(recorded_from_run(record).streams)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda s: [x for x in s if x.name != "imu_base"], "recording has no IMU imu_base"),
        (lambda s: [_renamed(x) if x.name == "imu_tool" else x for x in s], "IMU name is wrist;"),
        (lambda s: [x for x in s if x.name != "imu_tool"], "recording has no IMU imu_tool"),
        (lambda s: [x for x in s if x.kind != "joints"], "recording has 0 joint state streams"),
        (lambda s: [_joints_named(x) if x.kind == "joints" else x for x in s], "joint name is j1;"),
        (
            lambda s: [_without_joint3(x) if x.kind == "joints" else x for x in s],
            "IMU imu_link3_a is on module 3, whose joint3 is not in the joint states",
        ),
        (
            lambda s: [x for x in s if not x.name.startswith("imu_link3")],
            "module 3 moves but no IMU is on its link",
        ),
    ],
)
def test_bad_recordings_are_refused(clean: RunRecord, change: object, message: str) -> None:
    streams = change(_streams(clean))  # type: ignore[operator]
    with pytest.raises(ParameterError, match=message):
        identify_kinematics(ArmSignals.of_recorded(RecordedRun(streams)))


def test_imu_parent_of_the_names_export_writes() -> None:
    assert imu_parent("imu_base") == "base" and imu_parent("imu_tool") == "tool_tip"
    assert imu_parent("imu_link4_b") == "link4"
    for bad in ("imu_link7_a", "imu_link1_c", "IMU_BASE"):
        with pytest.raises(ParameterError, match=f"IMU name is {bad};"):
            imu_parent(bad)
