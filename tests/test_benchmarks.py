"""The benchmarks run in CI in their smoke mode (sizes tiny, no timing asserted)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.slow
@pytest.mark.parametrize(
    "script",
    [
        "bench_record.py",
        "bench_cli.py",
        "bench_dataset.py",
        "bench_rotations.py",
        "bench_memory.py",
        "bench_identify.py",
        "bench_identify_dynamics.py",
        "bench_forward.py",
        "bench_windows.py",
        "bench_online.py",
    ],
)
def test_benchmark_smoke(script: str) -> None:
    result = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / script), "--smoke"],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert result.returncode == 0, result.stderr
    assert "floor" in result.stdout or "/s" in result.stdout
