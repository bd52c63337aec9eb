"""``aaria identify RECORDING``: the DH table of a recording, as of the run it was exported from.

Runs made by ``aaria simulate`` (float64, a 3-module arm with an empty module) and ``aaria
dataset`` (the default random arm, float32 as written by default, and float64), exported by
``aaria export`` to MCAP, ROS 1 bag and CSV (and imported to a recorded run file), identified by
``aaria identify``. The expectations are independent of the fit: the tool tip by Pinocchio's
forward kinematics of the true table (the run file's ``senSenDH``) at its joint values, the link
types of the true table, and the identification of the run file itself.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from conftest import run_cli
from recorded_arm import small_arm_tables, tool_tip_error

from aaria_pin.apps.recordings import export_run, recorded_from_run
from aaria_pin.core.recording import STREAM_COLUMNS, RecordedRun, SensorStream
from aaria_pin.files.source import open_record

MM = 1e-3


def _tool_tip_error(table: list[list[float]], truth_file: Path, run: int | None) -> float:
    """Largest tool-tip distance [m] between ``table`` and the run's true table (Pinocchio)."""
    truth = open_record(truth_file, run)
    return tool_tip_error(np.asarray(table), truth.tables["senSenDH"], np.asarray(truth.q))


@pytest.fixture(scope="module")
def small_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """``aaria simulate`` of a 3-module arm (module 2 empty), 2 s at 200 Hz, no noise."""
    folder = tmp_path_factory.mktemp("recorded")
    table, joints, base = small_arm_tables()
    for name, values in (("dh", table), ("joints", joints), ("base", base)):
        np.savetxt(folder / f"{name}.csv", values, delimiter=",")
    path = folder / "run.h5"
    code, _, err = run_cli(
        "simulate", "--dh", str(folder / "dh.csv"), "--joints", str(folder / "joints.csv"),
        "--base", str(folder / "base.csv"), "--duration", "2", "--rate", "200", "--no-noise",
        "-o", str(path),
    )  # fmt: skip
    assert code == 0, err
    return path


def _dataset(folder: Path, dtype: str) -> Path:
    path = folder / f"ds_{dtype}.h5"
    code, _, err = run_cli(
        "dataset", "-n", "1", "--seed", "5", "--duration", "3", "--rate", "200", "--no-noise",
        "--dtype", dtype, "--workers", "1", "--quiet", "-o", str(path),
    )  # fmt: skip
    assert code == 0, err
    return path


def _identified(*args: str) -> dict[str, object]:
    code, out, err = run_cli("identify", *args, "--json")
    assert code == 0, err
    report: dict[str, object] = json.loads(out)
    return report


def _check_recordings(run: Path, index: int | None, suffixes: tuple[str, ...]) -> None:
    """Each export of the run identified: the run file's table, within 1 mm of the truth."""
    selected = () if index is None else ("--run", str(index))
    of_run = _identified(str(run), *selected)
    truth = of_run["truth"]
    assert isinstance(truth, dict)
    for suffix in suffixes:
        recording = run.parent / f"{run.stem}{index or ''}{suffix}"
        code, _, err = run_cli("export", str(run), *selected, "-o", str(recording))
        assert code == 0, err
        report = _identified(str(recording))
        assert report["truth"] is None and str(report["noise_model"]).startswith("none")
        assert report["link_types"] == truth["link_types_true"]
        assert _tool_tip_error(report["table"], run, index) <= 1 * MM  # type: ignore[arg-type]
        np.testing.assert_allclose(report["table"], of_run["table"], atol=1e-9)  # type: ignore[arg-type]


def test_a_simulated_arm_with_an_empty_module(small_run: Path) -> None:
    _check_recordings(small_run, None, (".mcap", ".bag", ".csv"))


def test_the_default_arm_stored_in_float32(tmp_path: Path) -> None:
    _check_recordings(_dataset(tmp_path, "float32"), 0, (".mcap", ".bag", ".csv"))


def test_the_default_arm_stored_in_float64(tmp_path: Path) -> None:
    _check_recordings(_dataset(tmp_path, "float64"), 0, (".mcap",))


def test_a_recorded_run_file_and_a_bag_folder(small_run: Path, tmp_path: Path) -> None:
    folder, recorded = tmp_path / "bag", tmp_path / "rec.h5"
    assert run_cli("export", str(small_run), "-o", str(folder), "--format", "ros2-mcap")[0] == 0
    assert run_cli("import", str(folder), "-o", str(recorded))[0] == 0
    table = tmp_path / "est.csv"
    from_folder = _identified(str(folder))
    from_file = _identified(str(recorded), "-o", str(table))
    np.testing.assert_allclose(from_file["table"], from_folder["table"], atol=1e-9)  # type: ignore[arg-type]
    np.testing.assert_allclose(np.loadtxt(table, delimiter=","), from_file["table"])  # type: ignore[arg-type]
    assert _tool_tip_error(from_file["table"], small_run, None) <= 1 * MM  # type: ignore[arg-type]
    # commands that need the truth still refuse a recorded run, naming what it can do
    code, _, err = run_cli("identify", "--dynamics", str(recorded))
    assert code == 2 and "aaria identify FILE for an Aaria arm's DH table" in err


def _renamed(stream: SensorStream, name: str) -> SensorStream:
    return SensorStream(name, "imu", stream.time, stream.values, STREAM_COLUMNS["imu"])


@pytest.mark.parametrize(
    ("keep", "message"),
    [
        (lambda s: s.name != "imu_base", "recording has no IMU imu_base"),
        (lambda s: s.kind != "joints", "recording has 0 joint state streams"),
        (lambda s: not s.name.startswith("imu_link3"), "module 3 moves but no IMU is on its link"),
        (lambda s: True, "IMU name is wrist; allowed: imu_base, imu_tool, imu_link<k>_a"),
    ],
)
def test_bad_recordings_one_line_exit_2(
    small_run: Path, tmp_path: Path, keep: object, message: str
) -> None:
    streams = [s for s in recorded_from_run(open_record(small_run)).streams if keep(s)]  # type: ignore[operator]
    if message.startswith("IMU name"):
        streams = [_renamed(s, "wrist") if s.name == "imu_tool" else s for s in streams]
    bad = export_run(RecordedRun(streams), tmp_path / "bad.csv")
    table = tmp_path / "est.csv"
    code, out, err = run_cli("identify", str(bad), "-o", str(table))
    assert code == 2 and out == "" and not table.exists()
    assert len(err.strip().splitlines()) == 1 and message in err


def test_the_recordings_imu_model_is_given_by_flag(small_run: Path, tmp_path: Path) -> None:
    recording = tmp_path / "run.mcap"
    assert run_cli("export", str(small_run), "-o", str(recording))[0] == 0
    report = _identified(str(recording), "--imu-model", "bmi088")
    assert str(report["noise_model"]).endswith("of bmi088's (below 0.01: a noise-free recording)")
    # a simulated run holds its own noise model; another mode takes none: one line, exit 2
    for args in ((str(small_run),), (str(recording), "--rigid", "imu_base", "imu_tool")):
        code, out, err = run_cli("identify", *args, "--imu-model", "bmi088")
        assert code == 2 and out == "" and len(err.strip().splitlines()) == 1
        assert "--imu-model" in err
    code, _, err = run_cli("identify", str(recording), "--imu-model", "no-such-part")
    assert code == 2 and "--imu-model" in err and "bmi088" in err
