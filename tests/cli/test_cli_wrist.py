"""The wrist commands: the round trip of their own printed output, bad inputs, help."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import run_cli, wrist_equation_9
from scipy.spatial.transform import Rotation


def _printed_rotation(stdout: str) -> list[str]:
    """The nine entries of the rotation as ``aaria wrist`` prints them (6 decimals)."""
    lines = stdout.splitlines()
    start = lines.index("rotation:") + 1
    return [value for line in lines[start : start + 3] for value in line.split()]


def _printed_solutions(stdout: str) -> np.ndarray:
    lines = stdout.splitlines()
    start = next(n for n, line in enumerate(lines) if line.startswith("joint solutions")) + 1
    return np.array([[float(v) for v in line.split()] for line in lines[start:]])


def test_ik_of_the_matrix_fk_prints_gives_the_same_rotation() -> None:
    # the issue: 57 of 300 round trips ended in a traceback, 63 were refused
    rng = np.random.default_rng(18)
    joints = rng.uniform(-180.0, 180.0, (60, 3))
    joints[:20, 1] = rng.choice([0.0, 180.0, 1e-8, 180.0 - 1e-8, 1e-4], 20)  # singular, near
    for q in joints:
        code, out, err = run_cli("wrist", "fk", *(f"{v:.10g}" for v in q))
        assert code == 0, err
        printed = _printed_rotation(out)
        code, again, err = run_cli("wrist", "ik", "--matrix", *printed)
        assert code == 0, err
        given = np.array(printed, dtype=float).reshape(3, 3)
        np.testing.assert_allclose(
            np.array(_printed_rotation(again), dtype=float).reshape(3, 3), given, atol=1.5e-6
        )
        for solution in np.radians(_printed_solutions(again)):  # 4 decimals of a degree
            np.testing.assert_allclose(
                wrist_equation_9(*solution, d=0.132)[:3, :3], given, atol=5e-6
            )
        if np.abs(given.T @ given - np.eye(3)).max() > 1e-12:
            assert err.startswith("aaria: note: --matrix is") and "nearest rotation" in err


def test_projected_matrix_gives_exact_solutions_of_the_nearest_rotation() -> None:
    import json

    R = Rotation.from_euler("ZYZ", [0.3, 1.1, -2.0]).as_matrix()
    rounded = np.round(R, 6)
    code, out, err = run_cli(
        "wrist", "ik", "--json", "--matrix", *(f"{v:.6f}" for v in rounded.ravel())
    )
    assert code == 0 and "nearest rotation (SVD)" in err
    result = json.loads(out)
    nearest = np.array(result["rotation"])
    np.testing.assert_allclose(nearest.T @ nearest, np.eye(3), atol=1e-15)
    np.testing.assert_allclose(nearest, R, atol=1e-6)
    assert result["residual"] < 1e-14
    for q in np.radians(result["solutions"]):
        np.testing.assert_allclose(wrist_equation_9(*q, d=0.132)[:3, :3], nearest, atol=1e-14)


def test_near_singular_angles_give_exact_solutions() -> None:
    import json

    for theta2 in (1e-9, 1e-11, 180 - 1e-10):  # degrees: 1.7e-11 to 1.7e-13 rad from it
        code, out, err = run_cli(
            "wrist", "ik", "--json", "--angles", "20", str(theta2), "-70", "--order", "ZYZ"
        )
        assert code == 0 and not err, err
        result = json.loads(out)
        assert result["singular"] and result["residual"] < 2e-15


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["workspace", "--theta2", "0", "inf"], "--theta2 is inf; allowed: a finite number"),
        (["workspace", "--theta1", "nan", "30"], "--theta1 is nan; allowed: a finite number"),
        (["workspace", "--theta2", "90", "0"], "--theta2 is 90 0 (reversed)"),
        (["workspace", "--theta1", "10", "-10"], "--theta1 is 10 -10 (reversed)"),
        (["workspace", "--samples", "100", "--plot", "{tmp}/ws.jpg"], "suffix '.jpg'"),
        (["workspace", "--samples", "100", "--plot", "{tmp}/no/ws.png"], "no folder"),
        (["fk", "nan", "0", "0"], "JOINTS holds nan; allowed: finite numbers"),
        (["fk", "0", "inf", "0"], "JOINTS holds inf"),
        (["ik", "--angles", "0", "nan", "0"], "--angles is nan"),
        (["ik", "--matrix", *"1 0 0 0 1 0 0 0 nan".split()], "--matrix is nan"),
        (["ik", "--matrix", *"1 0 0 0 1 0 0 0 1.001".split()], "--matrix is not a rotation"),
        (["ik", "--matrix", *"1 0 0 0 1 0 0 0 -1".split()], "det = -1"),
        (["ik", "--matrix", *"0.5 0 0 0 1 0 0 0 1".split()], "|RᵀR - I| = 0.75"),
        (["ik"], "exactly one of --angles"),
        (["simulate", "nan", "0", "0", "-o", "{tmp}/w.h5"], "TARGETS holds nan"),
        (["simulate", "10", "0", "0", "--speed", "inf", "-o", "{tmp}/w.h5"], "--speed is inf"),
        (
            ["simulate", "10", "0", "0", "--speed", "-5", "-o", "{tmp}/w.h5"],
            "--speed is -5; allowed: > 0",
        ),
        (
            ["simulate", "10", "0", "0", "--acceleration", "0", "-o", "{tmp}/w.h5"],
            "--acceleration is 0",
        ),
        (["simulate", "10", "0", "0", "--rate", "nan", "-o", "{tmp}/w.h5"], "--rate is nan"),
        (
            ["simulate", "10", "0", "0", "--speed", "1e-9", "-o", "{tmp}/w.h5"],
            "speed 1.74533e-11 rad/s (1e-09 deg/s) and acceleration 1.39626 rad/s^2 (80 deg/s^2)",
        ),
        (
            ["simulate", "10", "0", "0", "--duration", "inf", "-o", "{tmp}/w.h5"],
            "--duration is inf",
        ),
    ],
)
def test_bad_wrist_inputs_exit_2_with_one_line(
    tmp_path: Path, args: list[str], message: str
) -> None:
    code, out, err = run_cli("wrist", *(a.replace("{tmp}", str(tmp_path)) for a in args))
    assert code == 2
    assert err.startswith("aaria: error: ") and err.count("\n") == 1, err
    assert message in err
    assert "Traceback" not in err + out and "np.float64" not in err
    assert not list(tmp_path.iterdir())  # nothing written


@pytest.mark.parametrize("command", ["fk", "ik", "simulate", "workspace"])
def test_every_wrist_help_ends_with_examples(command: str) -> None:
    code, out, _ = run_cli("wrist", command, "--help")
    assert code == 0
    examples = out[out.index("Examples:") :].splitlines()[1:]
    assert examples and all(line.strip().startswith(("aaria wrist", "#", "-")) for line in examples)
    assert f"aaria wrist {command}" in out[out.index("Examples:") :]


def test_help_examples_run() -> None:
    code, out, _ = run_cli("wrist", "ik", "--help")
    examples = out[out.index("Examples:") :].replace("\\\n", " ").splitlines()[1:]
    ran = 0
    for line in examples:
        if line.strip().startswith("aaria wrist ik"):
            args = line.split("#")[0].split()[2:]
            code, _, err = run_cli("wrist", *args)
            assert code == 0, (line, err)
            ran += 1
    assert ran == 4


def test_ik_angles_help_names_the_order() -> None:
    _, out, _ = run_cli("wrist", "ik", "--help")
    text = " ".join(out.split())
    assert (
        "--angles FLOAT... Tool rotation as three angles A B C in the sequence of --order" in text
    )
