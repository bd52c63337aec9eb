"""``aaria simulate --motion fourier`` and ``--trajectory FILE``: DH presets and a URDF robot.

A Fourier run is re-made bit for bit by ``--from``; a trajectory file's q is the run's q at its
samples exactly (no smoothing), its columns matched by name in any order; bad options and files
are one line, exit 2, nothing written.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from aaria_pin.files.runfile import read_run
from tests.conftest import run_cli


def _same_series(a: Path, b: Path) -> None:
    one, two = read_run(a), read_run(b)
    for name in ("q", "qd", "qdd", "tau", "imu", "tool_pose", "base_wrench"):
        assert np.array_equal(getattr(one, name), getattr(two, name)), name
    assert one.attributes == two.attributes


def test_fourier_run_of_a_preset_is_remade_by_from(tmp_path: Path) -> None:
    first, again = tmp_path / "f.h5", tmp_path / "g.h5"
    code, out, err = run_cli(
        "simulate", "--preset", "aaria-fig3", "--motion", "fourier", "--harmonics", "4",
        "--duration", "5", "--rate", "40", "-o", str(first),
    )  # fmt: skip
    assert code == 0, err
    assert "motion fourier" in out
    run = read_run(first)
    assert run.attributes["fourier"]["harmonics"] == 4
    assert run.attributes["fourier"]["base_frequency"] == pytest.approx(0.2)  # 1 period in 5 s
    assert run.tables["fourier_coefficients"].shape == (6, 9)
    assert np.abs(run.q).max() <= 1.0 and np.abs(run.qd).max() <= 1.5
    code, _, err = run_cli("simulate", "--from", str(first), "-o", str(again))
    assert code == 0, err
    _same_series(first, again)
    # another seed draws other coefficients
    other = tmp_path / "h.h5"
    code, _, err = run_cli(
        "simulate", "--from", str(first), "--motion", "fourier", "--seed", "3", "-o", str(other)
    )
    assert code == 0, err
    assert not np.allclose(read_run(other).q, run.q)
    # a joint table given beside --from is followed: back to sines
    table = tmp_path / "joints.npy"
    np.save(table, run.tables["senSenJ"])
    sines = tmp_path / "s.h5"
    code, out, err = run_cli(
        "simulate", "--from", str(first), "--joints", str(table), "-o", str(sines)
    )
    assert code == 0, err
    assert "motion" not in out and read_run(sines).attributes["motion"] == "sine"
    assert "fourier_coefficients" not in read_run(sines).tables


def test_trajectory_file_gives_the_run_its_q_at_the_samples(tmp_path: Path) -> None:
    """A ur5 CSV with named columns in another order and given qd: q and qd exactly."""
    t = np.arange(0, 121) / 40.0
    q = np.column_stack([0.4 * np.sin(0.9 * t + k) for k in range(6)])
    qd = np.column_stack([0.36 * np.cos(0.9 * t + k) for k in range(6)])
    names = [
        "shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
        "wrist_1_joint", "wrist_2_joint", "wrist_3_joint",
    ]  # fmt: skip
    order = [3, 0, 5, 1, 4, 2]
    header = ["time", *(names[j] for j in order), *(f"qd_{names[j]}" for j in order)]
    table = np.column_stack([t, q[:, order], qd[:, order]])
    csv = tmp_path / "motion.csv"
    np.savetxt(csv, table, delimiter=",", header=",".join(header), comments="", fmt="%.17g")
    out_file = tmp_path / "u.h5"
    code, out, err = run_cli(
        "simulate", "--robot", "ur5", "--trajectory", str(csv), "--no-noise", "-o", str(out_file)
    )
    assert code == 0, err
    assert "121 samples at 40 Hz, motion trajectory" in out
    run = read_run(out_file)
    assert np.array_equal(run.q, q) and np.array_equal(run.qd, qd)
    assert np.array_equal(run.time, t)
    again = tmp_path / "again.h5"
    assert run_cli("simulate", "--from", str(out_file), "-o", str(again))[0] == 0
    _same_series(out_file, again)
    # a DH arm from an .npy of its moving modules only (aaria-fig3: module 2 empty)
    dh_q = q[:, :5] * np.array([0.1, 0.1, 0.1, 1.0, 1.0])  # modules 1, 3, 4 prismatic
    npy = tmp_path / "dh.npy"
    np.save(npy, np.column_stack([t, dh_q]))
    dh_file = tmp_path / "dh.h5"
    code, _, err = run_cli(
        "simulate", "--preset", "aaria-fig3", "--trajectory", str(npy), "--duration", "2",
        "-o", str(dh_file),
    )  # fmt: skip
    assert code == 0, err
    dh = read_run(dh_file)
    assert dh.n_samples == 81
    assert np.array_equal(dh.q[:, [0, 2, 3, 4, 5]], dh_q[:81]) and not np.any(dh.q[:, 1])


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--harmonics", "3"], "--harmonics is given without --motion fourier; allowed"),
        (
            ["--motion", "fourier", "--trajectory", "T"],
            "--motion is given with --trajectory; allowed",
        ),
        (["--smoothing", "0.1"], "--smoothing is given without --trajectory; allowed"),
        (
            ["--motion", "fourier", "--joints", "T"],
            "--joints is given with --motion fourier; allowed",
        ),
        (["--motion", "fourier", "--harmonics", "600"], "harmonics × base_frequency is 600 ×"),
        (["--motion", "fourier", "--base-frequency", "0"], "--base-frequency is 0; allowed: > 0"),
        (["--trajectory", "T", "--duration", "9"], "--duration is 9; allowed: at most 3 s"),
        (["--trajectory", "WIDE"], "has 7 joint columns; allowed: 6 joint columns"),
        (["--trajectory", "NAMED"], "joint 'elbow' is not the robot's"),
        (["--trajectory", "FAR"], "joint1 of --trajectory is [2.0, 2.0]; allowed: within"),
    ],
)
def test_bad_motion_options_are_one_line_exit_2(
    tmp_path: Path, extra: list[str], message: str
) -> None:
    t = np.arange(0, 31) / 10.0
    files = {
        "T": np.column_stack([t, np.zeros((31, 6))]),
        "WIDE": np.column_stack([t, np.zeros((31, 7))]),
        "FAR": np.column_stack([t, np.full((31, 6), 2.0)]),
    }
    for name, array in files.items():
        np.save(tmp_path / f"{name}.npy", array)
    (tmp_path / "NAMED.csv").write_text("time,elbow\n0,0\n1,0\n2,0\n3,0\n4,0\n5,0\n6,0\n")
    paths = {"T": "T.npy", "WIDE": "WIDE.npy", "FAR": "FAR.npy", "NAMED": "NAMED.csv"}
    args = [str(tmp_path / paths[x]) if x in paths else x for x in extra]
    output = tmp_path / "x.h5"
    code, _, err = run_cli("simulate", "--preset", "aaria-fig2", *args, "-o", str(output))
    assert code == 2
    assert message in err and err.count("\n") == 1, err
    assert not output.exists()
