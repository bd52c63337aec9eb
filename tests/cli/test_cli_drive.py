"""``--drive pd|computed-torque`` through the command line: runs, data sets, failures, re-makes.

What the user types: a closed-loop run, its summary line (the tracking RMS, checked against the
file's own ``q - q_reference``), a closed-loop data set whose runs equal their re-made runs
array for array, a run that loses its reference (exit 1, one line, nothing written) and the
options that do not go together.
"""

from __future__ import annotations

import re
from pathlib import Path

import h5py
import numpy as np
from conftest import run_cli

from aaria_pin.files.source import open_record


def test_a_closed_loop_run_reports_its_tracking(tmp_path: Path) -> None:
    out = tmp_path / "pd.h5"
    code, stdout, err = run_cli(
        "simulate", "--robot", "ur5", "--drive", "pd", "--duration", "1", "-o", str(out)
    )
    assert code == 0, err
    record = open_record(out)
    rms = np.sqrt(np.mean((record.q - record.tables["q_reference"]) ** 2))
    shown = float(re.search(r"tracking RMS (\S+) \(rad or m\)", stdout)[1])  # type: ignore[index]
    assert abs(shown - rms) <= 5e-3 * rms and rms < 1e-3
    assert "drive pd" in stdout
    with h5py.File(out) as f:
        assert f.attrs["drive"] == "pd"


def test_a_closed_loop_data_set_equals_its_re_made_runs(tmp_path: Path) -> None:
    config = tmp_path / "gains.toml"
    config.write_text(
        "[controller]\nfrequency = [30.0, 60.0]\n[encoder]\ncounts_per_revolution = 1e6\n"
    )
    data = tmp_path / "ds.h5"
    code, _, err = run_cli(
        "dataset", "-n", "2", "--robot", "ur5", "--drive", "pd", "--config", str(config),
        "--duration", "0.5", "--workers", "1", "--quiet", "-o", str(data),
    )  # fmt: skip
    assert code == 0, err
    gains = []
    for run in range(2):
        stored = open_record(data, run)
        again = tmp_path / f"run{run}.h5"
        code, _, err = run_cli("simulate", "--from", str(data), "--run", str(run), "-o", str(again))
        assert code == 0, err
        remade = open_record(again)
        for name in ("q", "qd", "qdd", "tau", "imu"):
            np.testing.assert_array_equal(
                getattr(stored, name), np.asarray(getattr(remade, name)).astype(np.float32)
            )
        for name in ("q_reference", "tau_command", "q_measured"):
            np.testing.assert_array_equal(
                stored.tables[name], remade.tables[name].astype(np.float32)
            )
        np.testing.assert_array_equal(
            stored.tables["controller_kp"], remade.tables["controller_kp"]
        )
        gains.append(stored.tables["controller_kp"])
    assert not np.array_equal(gains[0], gains[1])  # drawn per run


def test_a_lost_reference_exits_1_and_writes_nothing(tmp_path: Path) -> None:
    hardware = tmp_path / "bad.toml"
    hardware.write_text("[controller]\nkp = 1e7\nkd = 10.0\n")
    out = tmp_path / "bad.h5"
    code, _, err = run_cli(
        "simulate", "--robot", "ur5", "--drive", "pd", "--hardware", str(hardware), "-o", str(out)
    )
    assert code == 1
    assert (
        err.count("\n") == 1 and "drive pd lost its reference: joint" in err and "kp 1e+07" in err
    )
    assert not out.exists()


def test_a_controller_for_a_followed_motion_is_refused(tmp_path: Path) -> None:
    hardware = tmp_path / "hw.toml"
    hardware.write_text("[controller]\nfrequency = 30.0\n")
    code, _, err = run_cli(
        "simulate", "--robot", "ur5", "--hardware", str(hardware), "-o", str(tmp_path / "x.h5")
    )
    assert code == 2 and "controller is given for a run of drive 'motion'" in err


def test_torques_with_a_closed_loop_drive_are_refused(tmp_path: Path) -> None:
    code, _, err = run_cli(
        "simulate", "--robot", "ur5", "--drive", "pd", "--torques", str(tmp_path / "t.npy"),
        "-o", str(tmp_path / "x.h5"),
    )  # fmt: skip
    assert code == 2 and "--drive torque and --torques FILE go together" in err


def test_a_drive_given_with_from_replaces_the_stored_one(tmp_path: Path) -> None:
    pd = tmp_path / "pd.h5"
    code, _, err = run_cli("simulate", "--robot", "ur5", "--drive", "pd", "--duration", "0.3",
                           "-o", str(pd))  # fmt: skip
    assert code == 0, err
    followed = tmp_path / "followed.h5"
    code, _, err = run_cli("simulate", "--from", str(pd), "--drive", "motion", "-o", str(followed))
    assert code == 0, err
    record = open_record(followed)
    assert record.attributes["drive"] == "motion" and "controller" not in record.attributes
    np.testing.assert_allclose(record.q, open_record(pd).tables["q_reference"], atol=1e-12)
    tracked = tmp_path / "tracked.h5"
    code, _, err = run_cli(
        "simulate", "--from", str(pd), "--drive", "computed-torque", "-o", str(tracked)
    )
    assert code == 0, err
    assert open_record(tracked).attributes["drive"] == "computed-torque"
