"""``aaria export`` and ``aaria import`` through the command line: a short simulated run out to
every recording format and back in gives its arrays; a bag written by ``rosbags`` itself (not our
writer) reads in; bad recordings are one line each, exit 2, nothing written."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner, Result

pytest.importorskip("rosbags")

from aaria_pin.cli import main
from aaria_pin.core.record import RunRecord
from aaria_pin.core.recording import RecordedRun
from aaria_pin.files.runfile import read_recorded_run, read_run


def _aaria(*args: str | Path) -> Result:
    return CliRunner().invoke(main, [str(a) for a in args])


@pytest.fixture(scope="module")
def run_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """An aaria-fig2 run, 0.2 s at 100 Hz, IMU noise on."""
    path = tmp_path_factory.mktemp("run") / "run.h5"
    result = _aaria("simulate", "--preset", "aaria-fig2", "--duration", "0.2", "-o", path)
    assert result.exit_code == 0, result.output
    return path


def _same_as_run(back: RecordedRun, record: RunRecord) -> None:
    """The recorded streams are the run's IMU signals, joint values and torques, base wrench."""
    mounts = [(slot, m.name) for slot, m in enumerate(record.imu_mounts) if m.parent]
    assert sorted(s.name for s in back.of_kind("imu")) == sorted(name for _, name in mounts)
    for slot, name in mounts:
        imu = back.stream(name)
        np.testing.assert_array_equal(imu.values, record.imu[:, slot])
        np.testing.assert_allclose(imu.time, record.time, rtol=0, atol=1e-9)
    joints = back.stream("joints")
    n = len(record.joint_names)
    assert joints.columns[:n] == tuple(f"q:{j}" for j in record.joint_names)
    np.testing.assert_array_equal(joints.values, np.hstack([record.q, record.qd, record.tau]))
    np.testing.assert_array_equal(back.stream("base").values, record.base_wrench)


@pytest.mark.parametrize(
    ("name", "form"),
    [("run.mcap", None), ("run.bag", None), ("run.db3", None), ("run.csv", None),
     ("bag_sqlite", "ros2-sqlite3"), ("bag_mcap", "ros2-mcap")],
)  # fmt: skip
def test_export_then_import_gives_the_runs_arrays(
    run_file: Path, tmp_path: Path, name: str, form: str | None
) -> None:
    out = tmp_path / name
    result = _aaria("export", run_file, "-o", out, *(["--format", form] if form else []))
    assert result.exit_code == 0, result.output
    assert result.output.startswith(f"wrote {out}: 16 streams")
    if form is not None:
        assert (out / "metadata.yaml").is_file()
    result = _aaria("import", out, "-o", tmp_path / "rec.h5")
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    assert len(lines) == 1 + 16 and "imu_tool" in result.output and "100.000 Hz" in lines[1]
    record = read_run(run_file)
    _same_as_run(read_recorded_run(tmp_path / "rec.h5"), record)
    # the recorded run goes out and in again unchanged (its own streams, not a simulation's)
    assert _aaria("export", tmp_path / "rec.h5", "-o", tmp_path / "again.mcap").exit_code == 0
    assert _aaria("import", tmp_path / "again.mcap", "-o", tmp_path / "again.h5").exit_code == 0
    _same_as_run(read_recorded_run(tmp_path / "again.h5"), record)


def test_a_recorded_run_is_shown_by_info_and_refused_by_commands_needing_truth(
    run_file: Path, tmp_path: Path
) -> None:
    assert _aaria("export", run_file, "-o", tmp_path / "run.mcap").exit_code == 0
    assert _aaria("import", tmp_path / "run.mcap", "-o", tmp_path / "rec.h5").exit_code == 0
    info = _aaria("info", tmp_path / "rec.h5")
    assert info.exit_code == 0 and "recorded run (measured signals only)" in info.output
    assert "joints joints" in info.output and "/joint_states" in info.output
    check = _aaria("check", tmp_path / "rec.h5")
    assert check.exit_code == 0 and "all intact" in check.output, check.output
    for command, suffix in (("torques", ""), ("plot", ".png"), ("view", ".html")):
        extra = ["-o", str(tmp_path / f"x{suffix}")] if suffix else []
        result = _aaria(command, tmp_path / "rec.h5", *extra)
        assert result.exit_code == 2, (command, result.output)
        assert result.stderr.count("\n") == 1 and "is a recorded run" in result.stderr


def test_the_recording_template_maps_an_export_as_written(run_file: Path, tmp_path: Path) -> None:
    assert _aaria("template", "recording", "-o", tmp_path / "rec.toml").exit_code == 0
    assert _aaria("export", run_file, "-o", tmp_path / "run.bag").exit_code == 0
    result = _aaria("import", tmp_path / "run.bag", "--map", tmp_path / "rec.toml",
                    "--imu", "imu_base=/imu/imu_link1_a", "-o", tmp_path / "rec.h5")  # fmt: skip
    assert result.exit_code == 0, result.output
    back = read_recorded_run(tmp_path / "rec.h5")
    assert [s.name for s in back.streams] == ["imu_tool", "imu_link6_b", "imu_base", "base",
                                              "joints"]  # fmt: skip
    record = read_run(run_file)
    slot = next(k for k, m in enumerate(record.imu_mounts) if m.name == "imu_link1_a")
    np.testing.assert_array_equal(back.stream("imu_base").values, record.imu[:, slot])  # the flag


def _imu_bag(path: Path, messages: list[tuple[str, str, int, int, float]]) -> Path:
    """A ROS 1 bag written with rosbags itself: (topic, frame id, stamp, log time [ns], wx)."""
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC)
    t = store.types
    vector = t["geometry_msgs/msg/Vector3"]
    with Writer(path) as writer:
        connections = {}
        for k, (topic, frame, ns, log, wx) in enumerate(messages):
            if topic not in connections:
                connections[topic] = writer.add_connection(topic, "sensor_msgs/msg/Imu",
                                                           typestore=store)  # fmt: skip
            stamp = t["builtin_interfaces/msg/Time"](sec=ns // 10**9, nanosec=ns % 10**9)
            message = t["sensor_msgs/msg/Imu"](
                header=t["std_msgs/msg/Header"](seq=k, stamp=stamp, frame_id=frame),
                orientation=t["geometry_msgs/msg/Quaternion"](x=np.nan, y=np.nan, z=np.nan,
                                                              w=np.nan),
                orientation_covariance=np.r_[-1.0, np.zeros(8)],
                angular_velocity=vector(x=wx, y=0.0, z=0.0),
                angular_velocity_covariance=np.zeros(9),
                linear_acceleration=vector(x=0.0, y=0.0, z=9.81),
                linear_acceleration_covariance=np.zeros(9),
            )  # fmt: skip
            raw = store.serialize_ros1(message, "sensor_msgs/msg/Imu")
            writer.write(connections[topic], log, raw)
    return path


T0 = 1_700_000_000 * 10**9
"""A wall-clock stamp [ns] (recorded bags carry the epoch's)."""


def test_a_lab_bag_two_imus_on_one_topic_at_their_own_rates(tmp_path: Path) -> None:
    a = [("/imus", "imu_a", T0 + k * 5_000_000, T0 + k * 5_000_000 + 777, 0.1 * k)
         for k in range(6)]  # 200 Hz  # fmt: skip
    b = [("/imus", "imu_b", T0 + 1_234_567 + k * 10_000_000, T0 + 2_000_000 + k * 10_000_000,
          -0.2 * k) for k in range(3)]  # 100 Hz, its own clock  # fmt: skip
    bag = _imu_bag(tmp_path / "lab.bag", a + b)
    result = _aaria("import", bag, "-o", tmp_path / "rec.h5")
    assert result.exit_code == 0, result.output
    back = read_recorded_run(tmp_path / "rec.h5")
    assert back.time_origin_ns == T0
    np.testing.assert_array_equal(back.stream("imu_a").time, np.arange(6) * 0.005)
    np.testing.assert_array_equal(back.stream("imu_b").time, 0.001234567 + np.arange(3) * 0.01)
    np.testing.assert_array_equal(back.stream("imu_b").values[:, 0], [0.0, -0.2, -0.4])
    # mapped by frame id and on the receive clock
    flags = ["--imu", "tool=/imus@imu_b", "--time", "log"]
    result = _aaria("import", bag, *flags, "-o", tmp_path / "log.h5")
    assert result.exit_code == 0, result.output
    back = read_recorded_run(tmp_path / "log.h5")
    assert [s.name for s in back.streams] == ["tool"] and back.time_origin_ns == T0 + 2_000_000
    np.testing.assert_array_equal(back.stream("tool").time, np.arange(3) * 0.01)


def _fails(tmp_path: Path, *args: str | Path, match: str) -> None:
    """The command exits 2 with one line matching ``match``, writing nothing."""
    out = tmp_path / "out.h5"
    result = _aaria(*args, "-o", out)
    assert result.exit_code == 2, result.output
    assert result.stderr.startswith("aaria: error: ") and result.stderr.count("\n") == 1
    assert match in result.stderr, result.stderr
    assert not out.exists()


def test_bad_recordings_are_one_line_exit_2_nothing_written(run_file: Path, tmp_path: Path) -> None:
    assert _aaria("export", run_file, "-o", tmp_path / "run.bag").exit_code == 0
    _fails(tmp_path, "import", tmp_path / "run.bag", "--imu", "tool=/imu/nope",
           match="topic /imu/nope (imu tool) is not in the recording; allowed: /imu/")  # fmt: skip
    _fails(tmp_path, "import", tmp_path / "run.bag", "--wrench", "ft=/imu/imu_tool",
           match="topic /imu/imu_tool (wrench ft) holds imu messages")  # fmt: skip
    back = [("/imu", "imu", T0 + ns, T0 + k, 0.0) for k, ns in enumerate((0, 10**7, 5 * 10**6))]
    _fails(tmp_path, "import", _imu_bag(tmp_path / "back.bag", back),
           match="imu time at sample 2 is 0.005 s after 0.01 s; allowed: strictly")  # fmt: skip
    nan = [("/imu", "imu", T0 + k * 10**7, T0 + k, w) for k, w in enumerate((0.0, np.nan))]
    _fails(tmp_path, "import", _imu_bag(tmp_path / "nan.bag", nan),
           match="stream imu sample 1 wx is nan; allowed: a finite number")  # fmt: skip
    for suffix in (".bag", ".mcap", ".db3"):
        cut = tmp_path / f"cut{suffix}"
        assert _aaria("export", run_file, "-o", cut).exit_code == 0
        cut.write_bytes(cut.read_bytes()[: cut.stat().st_size // 2])
        _fails(tmp_path, "import", cut, match="is damaged (")
    _fails(tmp_path, "import", tmp_path / "missing.bag", match="missing.bag: no such file")
    _fails(tmp_path, "import", tmp_path / "run.bag", "--imu", "tool", match="--imu is 'tool';")


def test_a_recording_without_imus_is_one_line(tmp_path: Path) -> None:
    from aaria_pin.core.recording import STREAM_COLUMNS, SensorStream
    from aaria_pin.files.recordings.bag_write import write_bag

    wrench = SensorStream("ft", "wrench", np.array([0.0, 0.01]), np.zeros((2, 6)),
                          STREAM_COLUMNS["wrench"])  # fmt: skip
    path = write_bag(tmp_path / "ft.mcap", RecordedRun([wrench]))
    _fails(tmp_path, "import", path, match="has no sensor_msgs/msg/Imu topic")


def test_export_refuses_a_format_that_is_not_the_outputs(run_file: Path, tmp_path: Path) -> None:
    out = tmp_path / "run.mcap"
    result = _aaria("export", run_file, "-o", out, "--format", "ros1")
    assert result.exit_code == 2 and "--format ros1 writes .bag" in result.stderr, result.stderr
    result = _aaria("export", run_file, "-o", tmp_path / "folder")
    assert result.exit_code == 2 and "--format is not given" in result.stderr, result.stderr
    assert list(tmp_path.iterdir()) == []  # nothing, not even a scratch folder
    result = _aaria("export", run_file, "-o", tmp_path / "no" / "bag", "--format", "ros2-mcap")
    assert result.exit_code == 2 and "folder" in result.stderr and "does not exist" in result.stderr
    (tmp_path / "bag").mkdir()
    result = _aaria("export", run_file, "-o", tmp_path / "bag", "--format", "ros2-mcap")
    assert result.exit_code == 2 and "exists; allowed: a new folder" in result.stderr
    assert [p.name for p in tmp_path.iterdir()] == ["bag"] and not any((tmp_path / "bag").iterdir())


def test_a_data_sets_run_is_exported(tmp_path: Path) -> None:
    data = tmp_path / "ds.h5"
    made = _aaria("dataset", "-n", "2", "--duration", "0.2", "--quiet", "-o", data)
    assert made.exit_code == 0, made.output
    assert _aaria("export", data, "--run", "1", "-o", tmp_path / "run1.db3").exit_code == 0
    assert _aaria("import", tmp_path / "run1.db3", "-o", tmp_path / "rec.h5").exit_code == 0
    from aaria_pin.files.source import open_record

    _same_as_run(read_recorded_run(tmp_path / "rec.h5"), open_record(data, 1))
    result = _aaria("export", data, "-o", tmp_path / "run.db3")
    assert result.exit_code == 2 and "--run is None; allowed: a run index" in result.stderr


def test_a_recording_split_in_two_files_imports_as_one_run(run_file: Path, tmp_path: Path) -> None:
    from aaria_pin.apps.recordings import open_recorded
    from aaria_pin.files.recordings.bag_write import write_bag

    whole = open_recorded(run_file)
    half = whole.streams[0].time.size // 2
    for name, rows in (("a.bag", slice(None, half)), ("b.bag", slice(half, None))):
        streams = [replace(s, time=s.time[rows], values=s.values[rows]) for s in whole.streams]
        write_bag(tmp_path / name, RecordedRun(streams, whole.time_origin_ns))
    result = _aaria("import", tmp_path / "b.bag", tmp_path / "a.bag", "-o", tmp_path / "rec.h5")
    assert result.exit_code == 0, result.output
    _same_as_run(read_recorded_run(tmp_path / "rec.h5"), read_run(run_file))
    both = _aaria("import", tmp_path / "a.bag", tmp_path / "a.bag", "-o", tmp_path / "x.h5")
    assert both.exit_code == 2 and "time at sample" in both.stderr, both.stderr
