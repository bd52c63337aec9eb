from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from scipy.io import savemat

from aaria_pin.cli import main
from aaria_pin.presets import get_preset

ROOT = Path(__file__).resolve().parent.parent


def _run(*args: str) -> tuple[int, str, str]:
    result = CliRunner().invoke(main, list(args))
    return result.exit_code, result.stdout, result.stderr


def test_urdf_from_preset_and_from_files(tmp_path: Path) -> None:
    code, out, _ = _run("urdf", "--preset", "aaria-fig2", "-o", str(tmp_path / "a.urdf"))
    assert code == 0, out
    assert "6 joints" in out
    table = get_preset("aaria-fig3").table
    np.savetxt(tmp_path / "t.csv", table, delimiter=",")
    savemat(tmp_path / "t.mat", {"senSenDH": table})
    for name in ("t.csv", "t.mat"):
        code, out, _ = _run(
            "urdf", "--dh", str(tmp_path / name), "-o", str(tmp_path / f"{name}.urdf")
        )
        assert code == 0, out
        assert "modules 1, 3, 4, 5, 6" in out
    np.savetxt(tmp_path / "wrist.csv", get_preset("spherical-wrist").table, delimiter=",")
    code, out, _ = _run(
        "urdf",
        "--dh",
        str(tmp_path / "wrist.csv"),
        "--convention",
        "standard",
        "--density",
        "7850",
        "-o",
        str(tmp_path / "w.urdf"),
    )
    assert code == 0, out
    assert "3 joints" in out


def _bad_table(tmp_path: Path, row: int, col: int, value: float) -> Path:
    table = get_preset("aaria-fig2").table.copy()
    table[row, col] = value
    path = tmp_path / "bad.csv"
    np.savetxt(path, table, delimiter=",")
    return path


@pytest.mark.parametrize(
    ("setup", "pattern"),
    [
        (lambda p: ["--dh", str(_bad_table(p, 2, 4, 5))], "row 3, column 5 (link type) is 5"),
        (lambda p: ["--dh", str(_bad_table(p, 1, 1, np.nan))], "row 2, column 2 (a) is nan"),
        (lambda p: ["--dh", str(_bad_table(p, 0, 3, -0.5))], "row 1, column 4 (d) is -0.5"),
        (lambda p: ["--preset", "aaria-fig2", "--density", "-3"], "density is -3.0"),
        (lambda p: ["--preset", "nope"], "preset 'nope' is not known"),
        (lambda p: ["--dh", str(p / "missing.csv")], "no such file"),
        (
            lambda p: ["--dh", str((p / "e.csv", (p / "e.csv").write_text("0,0,0,0,0\n" * 8))[0])],
            "every module",
        ),
        (
            lambda p: ["--dh", str((p / "s.csv", (p / "s.csv").write_text("1,2,3\n"))[0])],
            "shape (1, 3)",
        ),
    ],
)
def test_bad_input_one_line_exit_2_no_output(tmp_path: Path, setup, pattern: str) -> None:
    output = tmp_path / "out.urdf"
    args = setup(tmp_path)
    code, _, err = _run("urdf", *args, "-o", str(output))
    assert code == 2
    assert pattern in err
    assert err.count("\n") == 1 and err.startswith("aaria: error: ")
    assert not output.exists()
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".out")]


def test_unwritable_output(tmp_path: Path) -> None:
    code, _, err = _run("urdf", "--preset", "aaria-fig2", "-o", str(tmp_path / "no" / "r.urdf"))
    assert code == 2 and "does not exist" in err


def test_neither_or_both_table_sources(tmp_path: Path) -> None:
    code, _, err = _run("urdf", "-o", str(tmp_path / "r.urdf"))
    assert code == 2 and "exactly one of --preset" in err


def test_checkout_cli_py_runs_the_same_app() -> None:
    result = subprocess.run(
        [sys.executable, str(ROOT / "cli.py"), "--help"], capture_output=True, text=True, check=True
    )
    assert "urdf" in result.stdout


def test_help_starts_fast_without_heavy_imports() -> None:
    code = (
        "import sys, time; t=time.perf_counter(); from aaria_pin.cli import main; "
        "heavy=[m for m in ('pinocchio','h5py','scipy','matplotlib') if m in sys.modules]; "
        "print(heavy)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
    start = time.perf_counter()
    subprocess.run(
        [sys.executable, str(ROOT / "cli.py"), "--help"], capture_output=True, check=True
    )
    assert time.perf_counter() - start < 2.0  # generous bound for a loaded CI machine
